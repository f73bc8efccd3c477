#include "mspline/structure/ricci/cone_placement.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>
#include <sstream>

#include <Eigen/LU>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/index_map.h"
#include "mspline/structure/core/sparse_cholesky.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "mspline/structure/topology/topology.h"

namespace mspline::structure {

namespace {

constexpr double kQuarter = kPi / 2.0;

// The input's cotangent Laplacian L, factorized once with u = 0 held at the base vertices (the
// boundary, or vertex 0 as the gauge of a closed surface). Holding u = 0 at further vertices (the
// cones) changes the system by one rank per vertex, so it is handled by the capacitance-matrix
// method on the Green's functions G e_c of the base system instead of refactorizing.
class BaseLaplacian {
 public:
  BaseLaplacian(const TriMesh& mesh, const std::vector<char>& held)
      : laplacian_(vertexScalingHessian(
            mesh, edgeLengths(mesh),
            Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices())))),
        map_(mesh.n_vertices(), held) {
    const Eigen::SparseMatrix<double> system = map_.restrict(laplacian_);
    try {
      solver_.compute(system);
    } catch (const SolverError& e) {
      throw SolverError(std::string("cone placement: the cotangent Laplacian of the input could "
                                    "not be factorized (degenerate faces?): ") +
                        e.what());
    }
  }

  const Eigen::SparseMatrix<double>& laplacian() const { return laplacian_; }

  // Solves L u = rhs on the vertices that are not held and u = 0 on the held ones.
  Eigen::VectorXd solve(const Eigen::VectorXd& rhs) const {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(rhs.size());
    map_.scatter(solver_.solve(map_.gather(rhs)), u);
    return u;
  }

  // The Green's function of vertex v: solve(e_v), zero when v is held.
  Eigen::VectorXd green(int v) const {
    Eigen::VectorXd unit = Eigen::VectorXd::Zero(laplacian_.rows());
    unit[v] = 1.0;
    return solve(unit);
  }

  // (L u)_v, from column v of the symmetric L.
  double apply(const Eigen::VectorXd& u, int v) const {
    double sum = 0.0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(laplacian_, v); it; ++it)
      sum += it.value() * u[it.row()];
    return sum;
  }

 private:
  Eigen::SparseMatrix<double> laplacian_;
  IndexMap map_;
  SparseCholesky solver_;
};

// One third of the area of every face around each vertex.
Eigen::VectorXd vertexAreas(const TriMesh& mesh) {
  Eigen::VectorXd area = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices()));
  for (const auto f : mesh.faces()) {
    auto v = mesh.cfv_begin(f);
    const auto a = *v++, b = *v++, c = *v;
    const double third =
        ((mesh.point(b) - mesh.point(a)) % (mesh.point(c) - mesh.point(a))).norm() / 6.0;
    area[a.idx()] += third;
    area[b.idx()] += third;
    area[c.idx()] += third;
  }
  return area;
}

// Lowers `distance` (from the earlier sources, `limit` or more where farther) to the distance
// from the nearest of the earlier and the new sources, where that is below `limit`: edge hops
// when `lengths` is empty, else lengths along edges. The search stops where an earlier source is
// as close or the limit is reached, so each new cone costs only its neighbourhood.
void addSeparationSources(const TriMesh& mesh, const Eigen::VectorXd& lengths,
                          const std::vector<int>& sources, double limit,
                          std::vector<double>& distance) {
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  for (int s : sources) {
    distance[s] = 0.0;
    queue.push({0.0, s});
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v]) continue;
    for (const auto h : mesh.voh_range(OpenMesh::VertexHandle(v))) {
      const int w = mesh.to_vertex_handle(h).idx();
      const double next = d + (lengths.size() ? lengths[mesh.edge_handle(h).idx()] : 1.0);
      if (next < distance[w] && next < limit) {
        distance[w] = next;
        queue.push({next, w});
      }
    }
  }
}

double distortionOf(const Eigen::VectorXd& u, bool closed) {
  return closed ? (u.maxCoeff() - u.minCoeff()) / 2.0 : u.cwiseAbs().maxCoeff();
}

// A placement that cannot flatten the surface: the user's to change when the count was theirs,
// a failure of the automatic placement otherwise.
[[noreturn]] void failPlacement(const ConePlacementOptions& options, const std::string& message) {
  if (options.targetCount >= 0) throw InputError(message);
  throw SolverError(message);
}

// The most negative multiple of pi/2 the rounding's moves go to: cone angles up to 4 pi (a quad
// layout's corner of valence 8).
constexpr int kLowestQuarterTurns = -4;

// Largest-remainder rounding of the cone curvatures to multiples of pi/2 summing to `total`
// quarter turns, no multiple above `largest` (at most 3: the cone angle stays positive) or below
// kLowestQuarterTurns.
std::vector<int> roundToQuarterTurns(const std::vector<Cone>& cones, long total, int largest,
                                     const ConePlacementOptions& options) {
  const int lowest = kLowestQuarterTurns;
  std::vector<int> k(cones.size());
  std::vector<double> remainder(cones.size());
  long sum = 0;
  for (std::size_t i = 0; i < cones.size(); ++i) {
    const double q = cones[i].curvature / kQuarter;
    k[i] = std::clamp(static_cast<int>(std::floor(q)), lowest, largest);
    remainder[i] = q - k[i];
    sum += k[i];
  }
  std::vector<std::size_t> order(cones.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return remainder[a] > remainder[b]; });
  // Round after round (a cone may need two quarter turns more: a tetrahedron's right-angled
  // corner rounded to 0 when the other three are capped at `largest`).
  for (bool raised = true; sum < total && raised;) {
    raised = false;
    for (std::size_t i : order) {
      if (sum >= total) break;
      if (k[i] < largest) {
        ++k[i];
        ++sum;
        raised = true;
      }
    }
  }
  // Cones raised to the lowest multiple may leave too many quarter turns: the smallest remainders
  // give theirs back.
  for (bool lowered = true; sum > total && lowered;) {
    lowered = false;
    for (auto i = order.rbegin(); i != order.rend() && sum > total; ++i)
      if (k[*i] > lowest) {
        --k[*i];
        --sum;
        lowered = true;
      }
  }
  if (sum != total) {
    failPlacement(options, "cone placement: " + std::to_string(cones.size()) +
                               " cones cannot be quantized to multiples of pi/2 with positive " +
                               "angles up to 4 pi summing to 2 pi chi; place more cones");
  }
  return k;
}

// Rounding each cone on its own leaves whole quarter turns where the surface needs none: on
// cow.off the linearized distortion goes from 0.9 to 5.9 and the flat metric shrinks clusters of
// cones to a hundredth of a cell. From the rounded k, moves one quarter turn at a time (between two
// cones on a closed surface, where the sum is fixed; to or from one cone otherwise) while that
// lowers the area-weighted squared conformal factor of the linear solve, sum_v a_v u_v^2 with
// u = flat + sum_i k_i pi/2 G_i (mean zero when closed), a quadratic in k whose Gram matrix costs
// one dot product per pair of Green's functions.
void lowerRoundingDistortion(std::vector<int>& k, const std::vector<Eigen::VectorXd>& green,
                             const Eigen::VectorXd& flat, const Eigen::VectorXd& area, bool closed,
                             int largest) {
  const auto m = static_cast<Eigen::Index>(k.size());
  // Closed: the weighted means (u is taken mean zero), written out so that the Gram matrix needs
  // no centred copies of the Green's functions.
  const double total = area.sum();
  const auto mean = [&](const Eigen::VectorXd& x) { return closed ? area.dot(x) / total : 0.0; };
  Eigen::VectorXd means(m);
  for (Eigen::Index i = 0; i < m; ++i) means[i] = mean(green[std::size_t(i)]);
  const double flatMean = mean(flat);
  Eigen::MatrixXd gram(m, m);
  Eigen::VectorXd gradient(m);  // half the gradient of the objective in k
  for (Eigen::Index i = 0; i < m; ++i) {
    const Eigen::VectorXd weighted = area.cwiseProduct(green[std::size_t(i)]);
    for (Eigen::Index j = 0; j <= i; ++j)
      gram(i, j) = gram(j, i) =
          kQuarter * kQuarter * (weighted.dot(green[std::size_t(j)]) - total * means[i] * means[j]);
    gradient[i] = kQuarter * (weighted.dot(flat) - total * means[i] * flatMean);
  }
  for (Eigen::Index i = 0; i < m; ++i)
    for (Eigen::Index j = 0; j < m; ++j) gradient[i] += gram(i, j) * k[std::size_t(j)];
  // Every move lowers the objective, so the descent ends; the bound on its steps is a guard.
  const int lowest = kLowestQuarterTurns;
  // A move must lower the objective by more than rounding.
  const double threshold = -1e-9 * std::max(1.0, gram.diagonal().maxCoeff());
  for (int step = 0; step < 16 * int(m) + 64; ++step) {
    double bestChange = threshold;
    Eigen::Index up = -1, down = -1;
    for (Eigen::Index i = 0; i < m; ++i) {
      if (k[std::size_t(i)] >= largest) continue;
      if (!closed) {
        const double change = 2.0 * gradient[i] + gram(i, i);
        if (change < bestChange) bestChange = change, up = i, down = -1;
        continue;
      }
      for (Eigen::Index j = 0; j < m; ++j) {
        if (j == i || k[std::size_t(j)] <= lowest) continue;
        const double change =
            2.0 * (gradient[i] - gradient[j]) + gram(i, i) + gram(j, j) - 2.0 * gram(i, j);
        if (change < bestChange) bestChange = change, up = i, down = j;
      }
    }
    if (!closed)
      for (Eigen::Index j = 0; j < m; ++j) {
        if (k[std::size_t(j)] <= lowest) continue;
        const double change = -2.0 * gradient[j] + gram(j, j);
        if (change < bestChange) bestChange = change, up = -1, down = j;
      }
    if (up < 0 && down < 0) return;
    if (up >= 0) {
      ++k[std::size_t(up)];
      gradient += gram.col(up);
    }
    if (down >= 0) {
      --k[std::size_t(down)];
      gradient -= gram.col(down);
    }
  }
}

// Solves the capacitance system `system` w = rhs, whose first `cones` unknowns are the cones'
// weights, with each weight beyond [floor, cap] (cap 0: none) held at the bound: the cone farthest
// beyond first, one at a time (u is then free there), while on a closed surface another cone stays
// free to carry the rest. Holding a cone drops its row, which updates the inverse by a rank-one
// term (O(size^2)) instead of a new factorization per held cone: cheese.off holds hundreds of its
// 390 cones every round.
Eigen::VectorXd boundedCapacitanceWeights(const Eigen::MatrixXd& system, Eigen::VectorXd rhs,
                                          Eigen::Index cones, double cap, double floor,
                                          bool closed) {
  // The inverse of the rows and columns still free; a held cone's row and column are zero.
  Eigen::MatrixXd inverse = system.partialPivLu().inverse();
  // The bound each cone's weight is held at, or NaN while it is free.
  std::vector<double> bound(std::size_t(cones), std::numeric_limits<double>::quiet_NaN());
  Eigen::VectorXd weights = inverse * rhs;
  for (long free = cones;;) {
    const auto beyond = [&](Eigen::Index i) {
      return std::max(cap > 0.0 ? weights[i] - cap : 0.0, floor - weights[i]);
    };
    Eigen::Index worst = -1;
    for (Eigen::Index i = 0; i < cones; ++i) {
      if (!std::isnan(bound[std::size_t(i)])) continue;
      if (beyond(i) > 1e-9 && (worst < 0 || beyond(i) > beyond(worst))) worst = i;
    }
    if (worst < 0 || (closed && free <= 1)) return weights;
    // Holding cone k keeps the system solvable iff B_kk != 0; say so rather than spread NaNs.
    if (!(std::abs(inverse(worst, worst)) > 0.0) || !std::isfinite(inverse(worst, worst)))
      throw SolverError(
          "cone placement: holding a cone at its bound left the capacitance system "
          "singular (" +
          std::to_string(cones) + " cones)");
    const double held = weights[worst] > 0.0 ? cap : floor;
    bound[std::size_t(worst)] = held;
    --free;
    // The inverse of a matrix without row and column k: B - B e_k e_k^T B / B_kk.
    const Eigen::VectorXd column = inverse.col(worst), row = inverse.row(worst).transpose();
    inverse.noalias() -= column * row.transpose() / inverse(worst, worst);
    rhs -= system.col(worst) * held;
    rhs[worst] = 0.0;
    weights = inverse * rhs;
    for (Eigen::Index i = 0; i < cones; ++i)
      if (!std::isnan(bound[std::size_t(i)])) weights[i] = bound[std::size_t(i)];
  }
}

}  // namespace

ConePlacementResult placeCones(const TriMesh& mesh, const ConePlacementOptions& options) {
  const auto topology = analyzeTopology(mesh);
  if (mesh.n_faces() == 0 || topology.components != 1) {
    throw TopologyError("cone placement needs a connected mesh with faces; this one has " +
                        std::to_string(topology.components) + " components and " +
                        std::to_string(mesh.n_faces()) + " faces");
  }
  const bool closed = topology.closed;
  const long chi = topology.euler;
  if (options.singleCone && !(closed && topology.genus >= 2)) {
    throw TopologyError("a single cone needs a closed surface of genus >= 2; this one has genus " +
                        std::to_string(topology.genus) + " and " +
                        std::to_string(topology.boundaryLoops) + " boundary loops");
  }
  if (options.quantize && (options.maxQuarterTurns < 1 || options.maxQuarterTurns > 3))
    throw InputError("cone placement: the largest quarter-turn multiple must be 1 to 3");
  if (options.targetCount < -1) {
    throw InputError("cone placement: the target count must be -1 (automatic) or >= 0, not " +
                     std::to_string(options.targetCount));
  }

  const auto n = static_cast<Eigen::Index>(mesh.n_vertices());
  std::vector<int> boundary;
  for (const auto v : mesh.vertices())
    if (mesh.is_boundary(v)) boundary.push_back(v.idx());
  if (boundary.size() == mesh.n_vertices())
    throw TopologyError("cone placement: the mesh has no interior vertex");

  const Eigen::VectorXd inputCurvature = vertexCurvatures(mesh, edgeLengths(mesh));
  // Never a new cone: the boundary and the cones so far.
  std::vector<char> pinned(mesh.n_vertices(), 0);
  for (int v : boundary) pinned[v] = 1;
  // The one factorization: u = 0 held on the boundary, or at vertex 0 (the gauge) when closed.
  std::vector<char> held = pinned;
  if (closed) held[0] = 1;
  const BaseLaplacian system(mesh, held);
  // Flat at every vertex that is not held; the rounds and the final solve start from it.
  const Eigen::VectorXd flat = system.solve(-inputCurvature);
  // Green's functions of the cones, in placement order.
  std::vector<int> greenVertices;
  std::vector<Eigen::VectorXd> greens;

  const Eigen::VectorXd area = vertexAreas(mesh);
  // Round 0. Closed: the conformal factor to constant curvature (2 pi chi spread by area), gauge
  // fixed at vertex 0 and then by mean zero; it is the flat metric itself on a torus. With a
  // boundary: flat with u = 0 on the boundary.
  Eigen::VectorXd u;
  if (closed) {
    const Eigen::VectorXd uniform = area * (2.0 * kPi * static_cast<double>(chi) / area.sum());
    u = system.solve(uniform - inputCurvature);
    u.array() -= u.mean();
  } else {
    u = flat;
  }

  ConePlacementResult result;
  result.distortionPerRound.push_back(distortionOf(u, closed));
  std::ostringstream message;

  if (options.singleCone) {
    Eigen::Index best = 0;
    u.cwiseAbs().maxCoeff(&best);
    const int k = static_cast<int>(4 * chi);
    result.cones.push_back({static_cast<int>(best), k * kQuarter});
    result.quarterTurns.push_back(k);
    message << "single cone at vertex " << best << " (curvature " << k << " pi/2)";
  } else {
    const double minAngle = options.minConeAngle;
    std::vector<Cone>& cones = result.cones;
    const auto valid = [&] {
      if (closed && chi != 0 && cones.empty()) return false;
      for (const Cone& c : cones)
        if (2.0 * kPi - c.curvature < minAngle) return false;
      return true;
    };
    // Rounding to quarter turns needs at least 4 chi / maxQuarterTurns cones on a closed surface
    // of positive Euler characteristic (a blob with three cones of curvature about 2 pi / 3 each
    // cannot be rounded with at most pi per cone), and -chi of negative Euler characteristic (its
    // -4 chi quarter turns in cones of angle at most 4 pi: cheese.off, genus 133, had 64 cones of
    // angles up to 72 rad, and its layout cells 176 times longer than wide): placement goes on
    // until there are enough. The cap is then half as many again: with exactly -chi every cone
    // takes four quarter turns (cheese: linearized distortion 17, area distortion 52; with 396
    // cones 2.5 and 3.2).
    const auto conesToRound = [&]() -> long {
      if (!options.quantize || !closed) return 0;
      if (chi > 0) return (4 * chi + options.maxQuarterTurns - 1) / options.maxQuarterTurns;
      return options.targetCount < 0 ? -chi : 0;  // a count asked for may carry more
    };
    const auto roomToRound = [&] { return static_cast<long>(cones.size()) >= conesToRound(); };
    // Relaxed to 0 (any vertex that is not a cone or on the boundary) when no vertex is farther
    // and the surface still needs cones: on a coarse polyhedron the corners, next to each other,
    // carry all the curvature.
    Eigen::VectorXd separationLengths;
    double separationLimit = options.minSeparation;
    if (options.minSeparationLength > 0.0) {
      separationLengths = edgeLengths(mesh);
      separationLimit = options.minSeparationLength;
    }
    double separation = separationLimit;
    std::vector<double> apart(mesh.n_vertices(), std::numeric_limits<double>::infinity());
    addSeparationSources(mesh, separationLengths, boundary, separationLimit, apart);
    // Rounding cuts a cone's curvature at maxQuarterTurns quarter turns, so placement does too:
    // the curvature above the cap stays in the distortion and draws more cones to where it is
    // (a sharp tip with corners of valence 3 gets several of them, not one that rounding cuts in
    // half and whose other half lands far away).
    // Only for corners of valence 3: with valence 2 the cap moved the default layouts' cones and
    // its fits folded more on some meshes (femur, cow, diplodocus), fewer on others.
    const double capCurvature = options.quantize && options.maxQuarterTurns == 1 ? kQuarter : 0.0;
    // Likewise below: rounding keeps cone angles within 4 pi (a layout's corner of valence 8), so
    // curvature beyond -4 quarter turns draws more cones to where it is, rather than going to
    // cones far away in the rounding (femur.off and turbine.off had cones of -7 quarter turns;
    // clamped in the rounding alone, their fits folded three times as much).
    const double floorCurvature = options.quantize && closed
                                      ? kLowestQuarterTurns * kQuarter
                                      : -std::numeric_limits<double>::infinity();
    std::string stop;
    for (;;) {
      const double distortion = result.distortionPerRound.back();
      if (options.targetCount >= 0) {
        if (static_cast<int>(cones.size()) == options.targetCount) {
          stop = "reached the requested count";
          break;
        }
      } else if (valid() && roomToRound() && distortion <= options.maxDistortion) {
        stop = "distortion below the threshold";
        break;
      } else if (static_cast<long>(cones.size()) >=
                 std::max(static_cast<long>(options.maxCones), conesToRound() * 3 / 2)) {
        stop = "reached the maximum number of cones";
        result.reachedMaxCones = true;
        break;
      }

      int best = -1;
      for (;;) {
        for (Eigen::Index v = 0; v < n; ++v) {
          if (apart[v] < separation || pinned[v]) continue;
          if (best < 0 || std::abs(u[v]) > std::abs(u[best])) best = static_cast<int>(v);
        }
        if (best >= 0 || separation <= 0) break;
        separation = 0;
      }
      if (best < 0) {
        stop = "no vertex is far enough from the cones and the boundary";
        break;
      }
      cones.push_back({best, 0.0});
      pinned[best] = 1;
      addSeparationSources(mesh, separationLengths, {best}, separationLimit, apart);
      greenVertices.push_back(best);
      greens.push_back(system.green(best));

      // Flat at every free vertex, u = 0 at the cones and on the boundary; each cone keeps the
      // curvature the linearized metric leaves there. That u is flat + sum_j w_j G e_j: the
      // weights w are the cones' point curvatures, fixed by u = 0 at the cones (the capacitance
      // system). Closed: the base system drops vertex 0's row, which holds again iff the weights
      // sum to the total input curvature (the rows of L sum to zero), and a constant t (last
      // unknown) replaces the gauge u_0 = 0.
      const auto m = static_cast<Eigen::Index>(cones.size());
      const Eigen::Index size = closed ? m + 1 : m;
      Eigen::MatrixXd capacitance = Eigen::MatrixXd::Zero(size, size);
      Eigen::VectorXd rhs(size);
      for (Eigen::Index i = 0; i < m; ++i) {
        for (Eigen::Index j = 0; j < m; ++j) capacitance(i, j) = greens[j][cones[i].vertex];
        if (closed) capacitance(i, m) = 1.0;
        rhs[i] = -flat[cones[i].vertex];
      }
      if (closed) {
        capacitance.row(m).head(m).setOnes();
        rhs[m] = inputCurvature.sum();
      }
      const Eigen::VectorXd weights =
          boundedCapacitanceWeights(capacitance, rhs, m, capCurvature, floorCurvature, closed);
      u = flat;
      for (Eigen::Index j = 0; j < m; ++j) u += weights[j] * greens[j];
      if (closed) u.array() += weights[m];
      double sum = 0.0;
      for (Cone& c : cones) {
        c.curvature = inputCurvature[c.vertex] + system.apply(u, c.vertex);
        sum += c.curvature;
      }
      if (closed) {
        // Gauss-Bonnet holds up to rounding; make it exact.
        const double excess =
            (sum - 2.0 * kPi * static_cast<double>(chi)) / static_cast<double>(cones.size());
        for (Cone& c : cones) c.curvature -= excess;
      }
      result.distortionPerRound.push_back(distortionOf(u, closed));
    }
    if (!roomToRound()) {
      failPlacement(options, "cone placement: " + std::to_string(cones.size()) +
                                 " cones cannot be quantized to " + std::to_string(4 * chi) +
                                 " quarter turns of at most " +
                                 std::to_string(options.maxQuarterTurns) + " each (" + stop +
                                 "); the surface has too few vertices");
    }
    if (!valid()) {
      std::ostringstream msg;
      msg << "cone placement: " << cones.size() << " cones (" << stop
          << ") cannot flatten this surface: ";
      if (cones.empty()) {
        msg << "Gauss-Bonnet needs total curvature 2 pi chi = " << 2.0 * kPi * chi;
      } else {
        const auto worst = std::max_element(
            cones.begin(), cones.end(), [](auto& a, auto& b) { return a.curvature < b.curvature; });
        msg << "the cone at vertex " << worst->vertex << " would have angle "
            << 2.0 * kPi - worst->curvature << " (below " << minAngle << ")";
      }
      failPlacement(options, msg.str());
    }
    message << cones.size() << " cones after " << result.distortionPerRound.size() - 1
            << " rounds (" << stop << ")";

    if (options.quantize && !cones.empty()) {
      const int largest = options.maxQuarterTurns;
      std::vector<int> k;
      if (closed) {
        k = roundToQuarterTurns(cones, 4 * chi, largest, options);
      } else {
        for (const Cone& c : cones)
          k.push_back(std::min(largest, static_cast<int>(std::lround(c.curvature / kQuarter))));
      }
      lowerRoundingDistortion(k, greens, flat, area, closed, largest);
      std::vector<Cone> kept;
      for (std::size_t i = 0; i < cones.size(); ++i) {
        if (k[i] == 0) continue;
        kept.push_back({cones[i].vertex, k[i] * kQuarter});
        result.quarterTurns.push_back(k[i]);
      }
      message << ", " << kept.size() << " after quantization";
      cones = std::move(kept);
    }
  }

  // The linear solve for the returned cones as curvature targets (u = 0 where held), by linearity.
  result.u = flat;
  for (const Cone& c : result.cones) {
    const auto at = std::find(greenVertices.begin(), greenVertices.end(), c.vertex);
    result.u += c.curvature * (at != greenVertices.end() ? greens[at - greenVertices.begin()]
                                                         : system.green(c.vertex));
  }
  if (closed) result.u.array() -= result.u.mean();
  result.distortion = distortionOf(result.u, closed);
  message << "; linearized distortion " << result.distortion;
  result.message = message.str();
  return result;
}

int midpointLevelsForQuarterTurnCones(const TriMesh& mesh, int maxQuarterTurns) {
  if (maxQuarterTurns < 1)
    throw InputError("cone placement: the largest quarter-turn multiple must be at least 1");
  const TopologyReport topology = analyzeTopology(mesh);
  if (!topology.closed || topology.euler <= 0 || topology.faces == 0) return 0;
  const long needed = (4 * topology.euler + maxQuarterTurns - 1) / maxQuarterTurns;
  // Each round adds a vertex per edge; an edge becomes two and each face adds three.
  long vertices = long(topology.vertices), edges = long(topology.edges),
       faces = long(topology.faces);
  int levels = 0;
  for (; vertices < needed; ++levels) {
    vertices += edges;
    edges = 2 * edges + 3 * faces;
    faces *= 4;
  }
  return levels;
}

}  // namespace mspline::structure
