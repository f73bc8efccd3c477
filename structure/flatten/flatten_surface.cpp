#include "mspline/structure/flatten/flatten_surface.h"

#include <algorithm>
#include <cmath>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/stopwatch.h"
#include "mspline/structure/intrinsic/intrinsic_flattening.h"
#include "mspline/structure/mesh/boundary_loops.h"
#include "mspline/structure/ricci/circle_packing_energy.h"
#include "mspline/structure/ricci/cone_placement.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "mspline/structure/topology/topology.h"

namespace mspline::structure {

namespace {

// The cones given, or the automatic placement's (its outcome in `message`).
ConePlacementResult chooseCones(const TriMesh& mesh, const FlattenOptions& options) {
  if (options.cones && !options.singleCone) {
    ConePlacementResult given;
    given.cones = *options.cones;
    return given;
  }
  ConePlacementOptions placement;
  placement.quantize = options.quantize;
  placement.maxQuarterTurns = options.maxConeQuarterTurns;
  placement.minSeparationLength = options.minConeSeparation;
  placement.singleCone = options.singleCone;
  placement.targetCount = options.coneCount;
  return placeCones(mesh, placement);
}

// Geodesic curvatures for a disk whose boundary is prescribed: a circle (curvature spread by
// boundary length) or a rectangle (pi/2 at four corners a quarter of the perimeter apart).
std::vector<Cone> boundaryShape(const TriMesh& mesh, BoundaryShape shape,
                                const std::vector<Cone>& interiorCones) {
  const std::string shapeName = shape == BoundaryShape::Fixed ? "fixed" : "rectangle";
  auto loops = boundaryLoops(mesh);
  if (loops.size() != 1)
    throw InputError("--boundary " + shapeName +
                     " needs a surface with exactly one boundary loop; this one has " +
                     std::to_string(loops.size()));
  const auto& loop = loops.front();
  const std::size_t n = loop.size();
  std::vector<double> arc(n + 1, 0.0);  // arc length from loop[0] to loop[i]
  for (std::size_t i = 0; i < n; ++i) {
    auto p = mesh.point(loop[i]);
    auto q = mesh.point(loop[(i + 1) % n]);
    arc[i + 1] = arc[i] + (q - p).norm();
  }
  double interior = 0.0;
  for (const auto& cone : interiorCones) interior += cone.curvature;
  const double total = 2.0 * kPi - interior;  // Gauss-Bonnet on a disk
  std::vector<Cone> cones = interiorCones;
  if (shape == BoundaryShape::Fixed) {
    for (std::size_t i = 0; i < n; ++i) {
      const double before = arc[i == 0 ? n : i] - arc[i == 0 ? n - 1 : i - 1];
      const double after = arc[i + 1] - arc[i];
      cones.push_back({loop[i].idx(), total * 0.5 * (before + after) / arc[n]});
    }
    return cones;
  }
  if (std::abs(total - 2.0 * kPi) > 1e-12)
    throw InputError("--boundary rectangle needs interior cones whose curvatures sum to 0");
  for (int corner = 0; corner < 4; ++corner) {
    const double wanted = arc[n] * corner / 4.0;
    std::size_t best = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (std::abs(arc[i] - wanted) < std::abs(arc[best] - wanted)) best = i;
    cones.push_back({loop[best].idx(), kPi / 2});
  }
  return cones;
}

RicciScheme makeScheme(const TriMesh& mesh, MetricScheme scheme) {
  switch (scheme) {
    case MetricScheme::Tangential:
      return circlePackingScheme(mesh, thurstonPackingMetric(mesh), metricSchemeName(scheme));
    case MetricScheme::Inversive:
      return circlePackingScheme(mesh, inversiveDistanceMetric(mesh), metricSchemeName(scheme));
    case MetricScheme::Yamabe:
      break;
  }
  return vertexScalingScheme(mesh);
}

// exp(2u) over the input vertices, with u shifted so the flat metric has the input's total area.
// `mesh` is the surface laid out (the input or its overlay) with its flat lengths.
Flattening::AreaDistortion areaDistortion(const TriMesh& mesh, const Eigen::VectorXd& flatLengths,
                                          const Eigen::VectorXd& u) {
  auto area = [&](const Eigen::VectorXd& lengths) {
    double sum = 0.0;
    for (auto f : mesh.faces()) {
      double l[3];
      int k = 0;
      for (auto e : mesh.fe_range(f)) l[k++] = lengths[e.idx()];
      double s = 0.5 * (l[0] + l[1] + l[2]);
      sum += std::sqrt(std::max(0.0, s * (s - l[0]) * (s - l[1]) * (s - l[2])));
    }
    return sum;
  };
  const double shift = 0.5 * std::log(area(edgeLengths(mesh)) / area(flatLengths));
  Eigen::ArrayXd scale = (2.0 * (u.array() + shift)).exp();
  return {scale.minCoeff(), scale.maxCoeff(), scale.mean()};
}

// With quantized cones every seam is a quarter-turn rotation plus a translation.
Flattening::SeamRotations seamRotations(const FlatLayout& layout) {
  Flattening::SeamRotations rotations;
  double quarterTurnError = 0.0;
  for (const auto& seam : layout.seams) {
    const double quarters = seam.angle / (kPi / 2.0);
    quarterTurnError = std::max(quarterTurnError, std::abs(quarters - std::round(quarters)));
    rotations.rotated += std::round(quarters) != 0.0;
  }
  rotations.maxQuarterTurnError = quarterTurnError * kPi / 2.0;
  return rotations;
}

// At most this many automatic cone sets in all when the handle rotations cannot be quantized
// (knot.off needed 2, joint.off 4; each costs a flattening).
constexpr int kMaxConeSets = 4;

}  // namespace

std::string metricSchemeName(MetricScheme scheme) {
  switch (scheme) {
    case MetricScheme::Tangential:
      return "tangential";
    case MetricScheme::Inversive:
      return "inversive";
    case MetricScheme::Yamabe:
      break;
  }
  return "yamabe";
}

namespace {

// One flattening with the given cones; `clock` started before the cones were chosen.
Flattening flattenWithCones(const TriMesh& mesh, const FlattenOptions& options,
                            ConePlacementResult chosen, Stopwatch& clock,
                            const Progress& progress) {
  const std::string named = options.name.empty() ? "" : options.name + ": ";
  Flattening out;
  out.input = &mesh;
  out.cones = std::move(chosen.cones);
  out.conePlacement = std::move(chosen.message);
  out.reachedMaxCones = chosen.reachedMaxCones;
  const std::vector<Cone>& cones = out.cones;
  out.stageSeconds.emplace_back("cones", clock.lap());
  if (out.reachedMaxCones)
    report(progress, "warning: cone placement stopped at its maximum number of cones (" +
                         out.conePlacement + ")");
  const auto topology = analyzeTopology(mesh);
  BoundaryCondition condition = BoundaryCondition::FixedScale;
  std::vector<Cone> targets = cones;
  if (!topology.closed && options.boundary != BoundaryShape::Free) {
    condition = BoundaryCondition::PrescribedGeodesicCurvature;
    targets = boundaryShape(mesh, options.boundary, cones);
  }
  CurvatureTarget target = flatTarget(mesh, targets, condition);
  report(progress, std::to_string(cones.size()) + " cones; Newton on the " +
                       metricSchemeName(options.scheme) + " Ricci energy");

  RicciNewtonOptions newton;
  newton.tolerance = options.tolerance / (2.0 * kPi);  // the solver counts in units of 2 pi
  newton.maxIterations = options.maxIterations;
  RicciResult& flow = out.flow;
  flow = solveRicciFlow(mesh, makeScheme(mesh, options.scheme), target, newton);
  // The flip solve, when the input triangulation degenerates.
  std::optional<IntrinsicFlattening> flipped;
  out.stageSeconds.emplace_back("ricci_flow", clock.lap());
  report(progress, std::to_string(flow.iterations) + " Newton steps, max curvature error " +
                       std::to_string(flow.maxCurvatureError) + ": " + flow.message);

  // Where the input triangulation degenerates, vertex scaling continues on an intrinsic
  // triangulation kept Delaunay by Ptolemy flips, and the surface laid out is the common
  // subdivision of the input and that triangulation.
  if (!flow.converged && flow.status == RicciStatus::DegenerateTriangles &&
      options.scheme == MetricScheme::Yamabe) {
    report(progress, "the input triangulation degenerates (" + flow.message +
                         "); retrying with intrinsic Delaunay flips" +
                         (topology.closed ? "" : " on the doubled surface"));
    out.plainSolve = Flattening::PlainSolve{flow.message, flow.iterations};
    flipped = flattenWithFlips(mesh, target, newton);
    flow = flipped->solve.ricci;
    flow.u = flipped->u;
    out.flips = int(flipped->solve.flips);
    out.doubled = flipped->doubled;
    if (flow.converged) {
      out.splitEdges = flipped->splitEdges;
      out.overlay = std::move(flipped->overlay);
    }
    out.stageSeconds.emplace_back("ricci_flow_flips", clock.lap());
  }
  if (!flow.converged) {
    out.message = named + "the Ricci flow did not converge: " + flow.message;
    return out;
  }

  out.flatLengths = out.overlay ? out.overlay->edgeLengths : flow.edgeLengths;
  // Quantized cones make the rotations around cones quarter turns; on a closed surface with
  // handles the rotations along the handles must be made so too (on a torus without cones they
  // are no rotations at all).
  if (options.quantize && topology.closed && topology.genus >= 1 &&
      !(topology.genus == 1 && cones.empty())) {
    report(progress,
           "quantizing the rotation along " + std::to_string(2 * topology.genus) + " handle loops");
    HolonomyQuantizationResult& holonomy = out.holonomy.emplace();
    const auto quantize = [&](const IntrinsicTriangulation& start, bool flips) {
      HolonomyQuantizationOptions quantization;
      quantization.flips = flips;
      try {
        holonomy = quantizeHolonomy(start, cones, quantization);
      } catch (const SolverError& error) {
        // A singular step (too few triangles to move the rotations): as non-convergence.
        holonomy.converged = false;
        holonomy.message = error.what();
      }
    };
    // The metric that comes out may live on a triangulation the steps flipped; the surface laid
    // out is then its common subdivision with the input.
    const auto take = [&]() {
      const IntrinsicTriangulation& tri = holonomy.triangulation;
      if (tri.flipCount() == 0) {
        out.flatLengths = holonomy.edgeLengths;
        return;
      }
      IntrinsicOverlay overlay =
          intrinsicOverlay(mesh, tri.flippedEdges(), flow.u, holonomy.edgeLengths);
      if (overlay.degenerateCells > 0) {
        // Crossings rounded onto one another after tens of thousands of flips (cheese.off with
        // some cone sets): as a failed quantization, so that other cone sets are tried.
        holonomy.converged = false;
        holonomy.message = "its common subdivision with the input has " +
                           std::to_string(overlay.degenerateCells) + " cells of zero area after " +
                           std::to_string(tri.flipCount()) + " flips";
        return;
      }
      out.overlay = std::move(overlay);
      out.flatLengths = out.overlay->edgeLengths;
      out.flips = int(tri.flipCount());
    };
    // First on the surface's own triangles (the input's, or the common subdivision's, whose many
    // edges leave the metric the most freedom), without flips. Where the triangles block the steps
    // (the common subdivision's slivers on cheese.off), again with flips, from the flip solver's
    // Delaunay triangulation when there is one.
    quantize(IntrinsicTriangulation(out.surface(), out.flatLengths), false);
    if (holonomy.converged) {
      out.flatLengths = holonomy.edgeLengths;
    } else {
      report(progress, "the handle rotations cannot be quantized on fixed triangles (" +
                           holonomy.message + "); again with flips");
      if (flipped) {
        IntrinsicTriangulation tri = flipped->solve.triangulation;
        tri.setLogLengths0(tri.logLengths(flow.u));
        quantize(tri, true);
      } else {
        quantize(IntrinsicTriangulation(mesh, out.flatLengths), true);
      }
      if (holonomy.converged) take();
    }
    out.stageSeconds.emplace_back("holonomy", clock.lap());
    if (!holonomy.converged)
      report(progress, "warning: the handle rotations stay unquantized (" + holonomy.message +
                           "); seams across handles turn by arbitrary angles");
  }
  report(progress, "laying out");
  out.layout = layoutFlatMetric(out.surface(), out.flatLengths);
  out.stageSeconds.emplace_back("layout", clock.lap());
  out.areaDistortion = areaDistortion(out.surface(), out.flatLengths, flow.u);
  out.seamRotations = seamRotations(out.layout);
  if (out.holonomy && out.holonomy->converged &&
      out.seamRotations.maxQuarterTurnError > options.seamTolerance)
    report(progress, "warning: the laid-out seams miss quarter turns by up to " +
                         std::to_string(out.seamRotations.maxQuarterTurnError) + " rad");
  out.converged = out.layout.flippedTriangles == 0;
  out.message = out.converged
                    ? flow.message
                    : named + "the layout has " + std::to_string(out.layout.flippedTriangles) +
                          " flipped triangles";
  return out;
}

// The handle rotations could not be quantized, or the quantized metric not laid out with seams of
// quarter turns to what the quad layout demands: after tens of thousands of flips the common
// subdivision can have cells of 1e-13 of the mean area, and the layout through them drifts
// (cheese.off with 388 cones: 6e-5 rad, where its residual is 2e-12).
bool handlesFailed(const Flattening& flattening, const FlattenOptions& options) {
  return flattening.holonomy &&
         (!flattening.holonomy->converged || !flattening.converged ||
          flattening.seamRotations.maxQuarterTurnError > options.seamTolerance);
}

bool sameCones(const std::vector<Cone>& a, const std::vector<Cone>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const Cone& x, const Cone& y) {
    return x.vertex == y.vertex && x.curvature == y.curvature;
  });
}

// Cone counts to ask the placement for when `placed` cones leave handle rotations that cannot be
// quantized: a few more first (lower distortion), then fewer, down to none on a torus.
std::vector<int> retryConeCounts(int placed, int genus) {
  std::vector<int> counts;
  for (int more = 1; more <= 4; ++more) counts.push_back(placed + more);
  for (int fewer = placed - 1; fewer >= (genus == 1 ? 0 : 1); --fewer) counts.push_back(fewer);
  return counts;
}

}  // namespace

Flattening flattenSurface(const TriMesh& mesh, const FlattenOptions& options,
                          const Progress& progress) {
  Stopwatch clock;
  Flattening out = flattenWithCones(mesh, options, chooseCones(mesh, options), clock, progress);
  const bool automatic = !options.cones && !options.singleCone && options.coneCount < 0;
  if (!automatic || !handlesFailed(out, options)) return out;

  // The handle rotations depend on where the cones are; the Newton steps that quantize them can
  // degenerate the fixed triangulation for one cone set and not for another. Other automatic
  // cone sets are tried, first one that works wins.
  const int genus = analyzeTopology(mesh).genus;
  std::vector<std::vector<Cone>> tried{out.cones};
  std::vector<int> rejected{int(out.cones.size())};
  std::vector<std::pair<std::string, double>> spent = out.stageSeconds;
  for (const int count : retryConeCounts(int(out.cones.size()), genus)) {
    if (int(tried.size()) == kMaxConeSets) break;
    FlattenOptions retry = options;
    retry.coneCount = count;
    ConePlacementResult placement;
    try {
      placement = chooseCones(mesh, retry);
    } catch (const InputError&) {
      continue;  // a cone angle would come out too small for this count
    }
    const std::vector<Cone>& cones = placement.cones;
    if (std::any_of(tried.begin(), tried.end(),
                    [&](const std::vector<Cone>& other) { return sameCones(cones, other); }))
      continue;
    tried.push_back(cones);
    report(progress, "the handle rotations with " + std::to_string(rejected.back()) +
                         " cones could not be quantized or laid out; trying " +
                         std::to_string(cones.size()) + " cones");
    const int placed = int(cones.size());
    Flattening candidate;
    try {
      candidate = flattenWithCones(mesh, retry, std::move(placement), clock, progress);
    } catch (const Error& error) {
      // Another cone set is only a chance; the first set's result and message stand.
      report(progress, std::string("that failed: ") + error.what());
      rejected.push_back(placed);
      continue;
    }
    for (const auto& stage : candidate.stageSeconds) {
      const auto same = std::find_if(spent.begin(), spent.end(),
                                     [&](const auto& other) { return other.first == stage.first; });
      if (same == spent.end())
        spent.push_back(stage);
      else
        same->second += stage.second;
    }
    if (candidate.converged && !handlesFailed(candidate, retry)) {
      candidate.rejectedConeCounts = rejected;
      candidate.stageSeconds = spent;
      return candidate;
    }
    rejected.push_back(int(candidate.cones.size()));
  }
  out.stageSeconds = spent;
  out.rejectedConeCounts = rejected;
  return out;
}

}  // namespace mspline::structure
