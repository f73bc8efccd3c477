#include "mspline/structure/intrinsic/holonomy_quantization.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <utility>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/index_map.h"
#include "mspline/structure/core/sparse_cholesky.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"

namespace mspline::structure {

namespace {

// Without flips, steps cut this short by triangles about to degenerate count as blocked.
constexpr double kCrawlingStep = 1.0 / 64.0;

void requireClosedSurface(const IntrinsicTriangulation& tri) {
  for (int e = 0; e < tri.edgeCount(); ++e)
    if (tri.isBoundaryEdge(e))
      throw TopologyError("holonomy quantization needs a closed surface; this one has a boundary");
}

// The metric is the triangulation's own (Penner coordinates at u = 0).
Eigen::VectorXd ownLengths(const IntrinsicTriangulation& tri) {
  return tri.logLengths0().array().exp().matrix();
}

Eigen::VectorXd ownCornerAngles(const IntrinsicTriangulation& tri) {
  return intrinsicCornerAngles(tri, Eigen::VectorXd::Zero(tri.vertexCount()));
}

bool anyDegenerate(const IntrinsicTriangulation& tri) {
  const Eigen::VectorXd l = ownLengths(tri);
  for (int f = 0; f < tri.faceCount(); ++f)
    if (!satisfiesTriangleInequality(l[tri.edge(3 * f)], l[tri.edge(3 * f + 1)],
                                     l[tri.edge(3 * f + 2)]))
      return true;
  return false;
}

/// d(angle opposite h)/d(log length) of the three edges of h's face, by edge index: with A the
/// angle opposite h and B, C the next ones, dA = (cot B + cot C) dlog a - cot C dlog b - cot B
/// dlog c.
std::array<std::pair<int, double>, 3> angleGradient(const IntrinsicTriangulation& tri,
                                                    const Eigen::VectorXd& lengths, int h) {
  const int hb = tri.next(h), hc = tri.next(hb);
  const int ea = tri.edge(h), eb = tri.edge(hb), ec = tri.edge(hc);
  const double a = lengths[ea], b = lengths[eb], c = lengths[ec];
  const double area4 = fourTimesArea(a, b, c);
  MSPLINE_ASSERT(area4 > 0.0, "angle gradient of a degenerate triangle");
  const double cotB = (a * a + c * c - b * b) / area4;
  const double cotC = (a * a + b * b - c * c) / area4;
  return {{{ea, cotB + cotC}, {eb, -cotC}, {ec, -cotB}}};
}

/// One step of a dual loop: entering the face by `in`, leaving by `out`, the transported frame
/// turns by `sign` * (pi - corner angle opposite `cornerHalfedge`), plus pi for the crossing.
struct LoopStep {
  int cornerHalfedge;
  double sign;
};

LoopStep loopStep(const IntrinsicTriangulation& tri, int in, int out) {
  if (out == tri.next(in)) return {tri.prev(in), 1.0};
  MSPLINE_ASSERT(out == tri.prev(in),
                 "a dual loop must leave each face by another edge than it entered");
  return {tri.next(in), -1.0};
}

template <class Visit>
void forEachStep(const IntrinsicTriangulation& tri, const DualLoop& loop, Visit&& visit) {
  const auto& hs = loop.halfedges;
  for (std::size_t i = 0; i < hs.size(); ++i)
    visit(loopStep(tri, tri.twin(hs[(i + hs.size() - 1) % hs.size()]), hs[i]));
}

// How freely each edge's log length may move: the step minimizes sum dlog_e^2 / freedom_e, with
// freedom sin^4 of the smallest angle of the edge's triangles, so that skinny triangles barely
// change and the deformation goes where triangles can take it. With plain least norm eight.off
// stalls on degenerating triangles of its input triangulation; with sin^2 too.
Eigen::VectorXd edgeFreedom(const IntrinsicTriangulation& tri) {
  const Eigen::VectorXd angles = ownCornerAngles(tri);
  Eigen::VectorXd freedom = Eigen::VectorXd::Ones(tri.edgeCount());
  for (int f = 0; f < tri.faceCount(); ++f) {
    const double smallest = std::min({angles[3 * f], angles[3 * f + 1], angles[3 * f + 2]});
    const double s = std::sin(smallest);
    for (int k = 0; k < 3; ++k) {
      double& edgeFreedom = freedom[tri.edge(3 * f + k)];
      edgeFreedom = std::min(edgeFreedom, s * s * s * s);
    }
  }
  return freedom;
}

// Dual loops that follow flips: a loop is a cyclic chain of crossings, each naming its edge and
// whether it leaves by the edge's representative halfedge, which flips of other edges keep. After a
// flip only the paths through the flipped quadrilateral are routed again.
class RoutedLoops {
 public:
  RoutedLoops(const IntrinsicTriangulation& tri, const std::vector<DualLoop>& loops)
      : byEdge_(static_cast<std::size_t>(tri.edgeCount())) {
    for (const DualLoop& loop : loops) {
      const int first = int(edge_.size());
      const int n = int(loop.halfedges.size());
      for (int i = 0; i < n; ++i) {
        const int h = loop.halfedges[std::size_t(i)];
        const int node = add(tri.edge(h), tri.halfedge(tri.edge(h)) == h);
        next_[std::size_t(node)] = first + (i + 1) % n;
        prev_[std::size_t(node)] = first + (i + n - 1) % n;
      }
      head_.push_back(first);
    }
  }

  std::vector<DualLoop> loops(const IntrinsicTriangulation& tri) const {
    std::vector<DualLoop> out;
    for (const int first : head_) {
      DualLoop loop;
      int node = first;
      do {
        loop.halfedges.push_back(leaving(tri, node));
        node = next_[std::size_t(node)];
      } while (node != first);
      out.push_back(std::move(loop));
    }
    return out;
  }

  /// Routes the loops again after `tri` flipped edge e.
  void flipped(const IntrinsicTriangulation& tri, int e) {
    for (const int node : byEdge_[std::size_t(e)])
      if (alive_[std::size_t(node)]) remove(node);
    byEdge_[std::size_t(e)].clear();
    const int g = tri.halfedge(e);
    const int quad[2] = {g / 3, tri.twin(g) / 3};
    std::vector<int> entering;
    for (const int side : {tri.next(g), tri.prev(g), tri.next(tri.twin(g)), tri.prev(tri.twin(g))})
      for (const int node : byEdge_[std::size_t(tri.edge(side))]) {
        if (!alive_[std::size_t(node)]) continue;
        const int into = tri.twin(leaving(tri, node)) / 3;
        if (into == quad[0] || into == quad[1]) entering.push_back(node);
      }
    std::sort(entering.begin(), entering.end());
    entering.erase(std::unique(entering.begin(), entering.end()), entering.end());
    for (int x : entering) {
      // A path that leaves by the side it came in turns back: both crossings go, and the same may
      // follow for the crossings around them.
      while (alive_[std::size_t(x)]) {
        const int y = next_[std::size_t(x)];
        const int in = tri.twin(leaving(tri, x));
        const int out = leaving(tri, y);
        if (out != in || x == y) break;
        const int before = prev_[std::size_t(x)];
        remove(x);
        remove(y);
        x = before;
      }
      if (!alive_[std::size_t(x)]) continue;
      const int in = tri.twin(leaving(tri, x));
      const int out = leaving(tri, next_[std::size_t(x)]);
      if (in / 3 == out / 3) continue;
      // From one new triangle of the quadrilateral into the other, across the new diagonal.
      const int across = g / 3 == in / 3 ? g : tri.twin(g);
      MSPLINE_ASSERT(tri.twin(across) / 3 == out / 3, "a loop leaves the flipped quadrilateral");
      const int node = add(e, across == g);
      const int after = next_[std::size_t(x)];
      next_[std::size_t(x)] = node;
      prev_[std::size_t(node)] = x;
      next_[std::size_t(node)] = after;
      prev_[std::size_t(after)] = node;
    }
  }

 private:
  int add(int edge, bool forward) {
    const int node = int(edge_.size());
    edge_.push_back(edge);
    forward_.push_back(forward);
    alive_.push_back(1);
    next_.push_back(node);
    prev_.push_back(node);
    byEdge_[std::size_t(edge)].push_back(node);
    return node;
  }

  void remove(int node) {
    alive_[std::size_t(node)] = 0;
    const int before = prev_[std::size_t(node)], after = next_[std::size_t(node)];
    MSPLINE_ASSERT(after != node, "a homology loop shrank to nothing");
    next_[std::size_t(before)] = after;
    prev_[std::size_t(after)] = before;
    for (int& first : head_)
      if (first == node) first = after;
  }

  int leaving(const IntrinsicTriangulation& tri, int node) const {
    const int h = tri.halfedge(edge_[std::size_t(node)]);
    return forward_[std::size_t(node)] ? h : tri.twin(h);
  }

  std::vector<int> edge_, next_, prev_;
  std::vector<char> forward_, alive_;
  std::vector<std::vector<int>> byEdge_;
  std::vector<int> head_;
};

Eigen::VectorXd rotationsFromCornerAngles(const IntrinsicTriangulation& tri,
                                          const std::vector<DualLoop>& loops,
                                          const Eigen::VectorXd& angles) {
  Eigen::VectorXd rotation(Eigen::Index(loops.size()));
  for (std::size_t k = 0; k < loops.size(); ++k) {
    double sum = 0.0;
    forEachStep(tri, loops[k], [&](const LoopStep& step) {
      sum += kPi + step.sign * (kPi - angles[step.cornerHalfedge]);
    });
    rotation[Eigen::Index(k)] = sum;
  }
  return rotation;
}

}  // namespace

std::vector<DualLoop> homologyDualLoops(const IntrinsicTriangulation& tri) {
  requireClosedSurface(tri);
  const int nv = tri.vertexCount(), nf = tri.faceCount();
  std::vector<char> primal(std::size_t(tri.edgeCount()), 0), dual(primal.size(), 0);
  // Halfedges out of each vertex, for the breadth-first vertex tree.
  std::vector<std::vector<int>> outgoing(static_cast<std::size_t>(nv));
  for (int h = 0; h < 3 * nf; ++h) outgoing[std::size_t(tri.tail(h))].push_back(h);
  std::vector<char> seen(std::size_t(nv), 0);
  std::deque<int> queue{0};
  seen[0] = 1;
  int reached = 1;
  while (!queue.empty()) {
    const int v = queue.front();
    queue.pop_front();
    for (const int h : outgoing[std::size_t(v)]) {
      const int w = tri.tip(h);
      if (seen[std::size_t(w)]) continue;
      seen[std::size_t(w)] = 1;
      ++reached;
      primal[std::size_t(tri.edge(h))] = 1;
      queue.push_back(w);
    }
  }
  if (reached != nv)
    throw TopologyError("holonomy quantization needs a connected surface; " +
                        std::to_string(nv - reached) + " vertices are not reached");
  // toParent[f]: the halfedge of f whose twin lies in f's parent in the dual tree.
  std::vector<int> toParent(std::size_t(nf), -1), depth(std::size_t(nf), -1);
  depth[0] = 0;
  queue = {0};
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop_front();
    for (int h = 3 * f; h < 3 * f + 3; ++h) {
      const int e = tri.edge(h);
      if (primal[std::size_t(e)] || dual[std::size_t(e)]) continue;
      const int twin = tri.twin(h);
      const int g = twin / 3;
      if (depth[std::size_t(g)] >= 0) continue;
      depth[std::size_t(g)] = depth[std::size_t(f)] + 1;
      toParent[std::size_t(g)] = twin;
      dual[std::size_t(e)] = 1;
      queue.push_back(g);
    }
  }
  const auto parentFace = [&](int f) { return tri.twin(toParent[std::size_t(f)]) / 3; };
  std::vector<DualLoop> loops;
  for (int e = 0; e < tri.edgeCount(); ++e) {
    if (primal[std::size_t(e)] || dual[std::size_t(e)]) continue;
    // Cross e from f0 into f1, climb from f1 to the common ancestor, descend to f0.
    const int h0 = tri.halfedge(e);
    int up = tri.twin(h0) / 3;
    int down = h0 / 3;
    DualLoop loop{{h0}};
    std::vector<int> descent;
    while (up != down) {
      if (depth[std::size_t(up)] >= depth[std::size_t(down)]) {
        loop.halfedges.push_back(toParent[std::size_t(up)]);
        up = parentFace(up);
      } else {
        descent.push_back(tri.twin(toParent[std::size_t(down)]));
        down = parentFace(down);
      }
    }
    loop.halfedges.insert(loop.halfedges.end(), descent.rbegin(), descent.rend());
    loops.push_back(std::move(loop));
  }
  const long genus = (2 - (long(nv) - long(tri.edgeCount()) + long(nf))) / 2;
  MSPLINE_ASSERT(long(loops.size()) == 2 * genus, "tree-cotree leaves 2g edges");
  return loops;
}

Eigen::VectorXd loopRotations(const IntrinsicTriangulation& tri,
                              const std::vector<DualLoop>& loops) {
  return rotationsFromCornerAngles(tri, loops, ownCornerAngles(tri));
}

Eigen::VectorXd holonomyResiduals(const IntrinsicTriangulation& tri,
                                  const HolonomyProblem& problem) {
  const Eigen::VectorXd angles = ownCornerAngles(tri);
  const Eigen::VectorXd curvature = curvaturesFromCornerAngles(tri, angles);
  std::vector<char> excluded(std::size_t(tri.vertexCount()), 0);
  excluded[std::size_t(problem.droppedVertex)] = 1;
  const IndexMap rows(std::size_t(tri.vertexCount()), excluded);
  const Eigen::VectorXd rotation = rotationsFromCornerAngles(tri, problem.loops, angles);
  Eigen::VectorXd residual(rows.size() + rotation.size());
  residual.head(rows.size()) = rows.gather(curvature - problem.targetCurvature);
  // Parallel transport is a rotation mod 2 pi; the sums of a loop routed again after flips may
  // differ by whole turns.
  for (Eigen::Index k = 0; k < rotation.size(); ++k)
    residual[rows.size() + k] = std::remainder(rotation[k] - problem.targetRotation[k], 2.0 * kPi);
  return residual;
}

Eigen::SparseMatrix<double> holonomyJacobian(const IntrinsicTriangulation& tri,
                                             const HolonomyProblem& problem) {
  const Eigen::VectorXd lengths = ownLengths(tri);
  std::vector<char> excluded(std::size_t(tri.vertexCount()), 0);
  excluded[std::size_t(problem.droppedVertex)] = 1;
  const IndexMap rows(std::size_t(tri.vertexCount()), excluded);
  std::vector<Eigen::Triplet<double>> entries;
  // Curvature is 2 pi minus the angle sum: each angle enters its vertex's row negated.
  for (int h = 0; h < 3 * tri.faceCount(); ++h) {
    const int row = rows.unknown(std::size_t(tri.tip(tri.next(h))));
    if (row < 0) continue;
    for (const auto& [edge, d] : angleGradient(tri, lengths, h))
      entries.emplace_back(row, edge, -d);
  }
  for (std::size_t k = 0; k < problem.loops.size(); ++k) {
    const int row = rows.size() + int(k);
    forEachStep(tri, problem.loops[k], [&](const LoopStep& step) {
      for (const auto& [edge, d] : angleGradient(tri, lengths, step.cornerHalfedge))
        entries.emplace_back(row, edge, -step.sign * d);
    });
  }
  Eigen::SparseMatrix<double> jacobian(rows.size() + Eigen::Index(problem.loops.size()),
                                       Eigen::Index(tri.edgeCount()));
  jacobian.setFromTriplets(entries.begin(), entries.end());
  return jacobian;
}

HolonomyQuantizationResult quantizeHolonomy(const IntrinsicTriangulation& tri,
                                            const std::vector<Cone>& cones,
                                            const HolonomyQuantizationOptions& options) {
  HolonomyQuantizationResult result;
  HolonomyProblem problem;
  problem.loops = homologyDualLoops(tri);
  problem.targetCurvature = Eigen::VectorXd::Zero(tri.vertexCount());
  for (const auto& cone : cones) {
    if (cone.vertex < 0 || cone.vertex >= tri.vertexCount())
      throw InputError("holonomy quantization: cone vertex " + std::to_string(cone.vertex) +
                       " out of range");
    problem.targetCurvature[cone.vertex] = cone.curvature;
  }
  result.loops = problem.loops;
  result.initialRotation = loopRotations(tri, problem.loops);
  problem.targetRotation =
      (result.initialRotation / options.quantum).array().round().matrix() * options.quantum;
  result.targetRotation = problem.targetRotation;

  const auto maxAbs = [](const Eigen::VectorXd& v) {
    return v.size() == 0 ? 0.0 : v.cwiseAbs().maxCoeff();
  };

  // The metric is carried as Penner coordinates (log lengths at u = 0) of a triangulation that
  // may flip: where a step would degenerate triangles, the trial point is flipped to its Delaunay
  // triangulation by Ptolemy flips, on which it has proper triangles (Campen, Shen, Zhou and
  // Zorin 2019 take their steps so).
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(tri.vertexCount());
  IntrinsicTriangulation current = tri;
  RoutedLoops routed(current, problem.loops);
  Eigen::VectorXd residual = holonomyResiduals(current, problem);
  SparseCholesky cholesky;
  bool analyzed = false;
  int blockedInARow = 0;
  const int maxIterations = options.maxIterations + int(problem.loops.size()) / 4;
  result.message = "did not converge in " + std::to_string(maxIterations) + " steps";
  for (;;) {
    result.maxResidual = maxAbs(residual);
    if (result.maxResidual <= options.tolerance) {
      result.converged = true;
      result.message = "converged";
      break;
    }
    if (result.iterations == maxIterations) break;
    ++result.iterations;
    // Weighted least-norm Newton step: the smallest change of log lengths (in the freedom-weighted
    // norm) that zeroes the linearization. Steps must lower the residual's 2-norm, for which the
    // Newton step is a descent direction; its largest entry may grow on the way (with that as the
    // test, cheese.off's 266 loops crawled at steps of 1/64 and stopped after 30 at 0.47 rad).
    const Eigen::SparseMatrix<double> jacobian = holonomyJacobian(current, problem);
    const Eigen::SparseMatrix<double> scaled = jacobian * edgeFreedom(current).asDiagonal();
    const Eigen::SparseMatrix<double> normal = scaled * jacobian.transpose();
    if (!analyzed) {
      cholesky.analyze(normal);
      analyzed = true;
    }
    cholesky.factorize(normal);
    const Eigen::VectorXd step = scaled.transpose() * cholesky.solve(-residual);
    const Eigen::VectorXd base = current.logLengths0();
    bool accepted = false;
    bool blocked = false;  // some trial would have degenerated a triangle
    double taken = 0.0;
    for (double t = 1.0; t > 1e-8 && !accepted; t *= 0.5) {
      current.setLogLengths0(base + t * step);
      if (!anyDegenerate(current)) {
        const Eigen::VectorXd trialResidual = holonomyResiduals(current, problem);
        if (trialResidual.squaredNorm() < residual.squaredNorm()) {
          residual = trialResidual;
          taken = t;
          accepted = true;
        }
        continue;
      }
      blocked = true;
      if (!options.flips) continue;
      IntrinsicTriangulation flipped = current;
      RoutedLoops rerouted = routed;
      try {
        flipped.flipToDelaunay(zero, 1e-13, [&](int e) { rerouted.flipped(flipped, e); });
      } catch (const InternalError&) {
        continue;  // far out, rounding can make Ptolemy flips cycle: a shorter step
      }
      if (anyDegenerate(flipped)) continue;
      HolonomyProblem moved = problem;
      moved.loops = rerouted.loops(flipped);
      const Eigen::VectorXd trialResidual = holonomyResiduals(flipped, moved);
      if (trialResidual.squaredNorm() >= residual.squaredNorm()) continue;
      current = std::move(flipped);
      routed = std::move(rerouted);
      problem = std::move(moved);
      residual = trialResidual;
      analyzed = false;  // new connectivity, new pattern
      taken = t;
      accepted = true;
    }
    if (!accepted) {
      current.setLogLengths0(base);
      result.message = "the line search stalled at residual " + std::to_string(result.maxResidual);
      break;
    }
    blockedInARow = !options.flips && blocked && taken <= kCrawlingStep ? blockedInARow + 1 : 0;
    if (options.maxBlockedSteps > 0 && blockedInARow == options.maxBlockedSteps) {
      result.message = "triangles about to degenerate cut " + std::to_string(blockedInARow) +
                       " steps in a row to 1/64 or less: they block the way without flips";
      break;
    }
  }
  result.flips = current.flipCount() - tri.flipCount();
  result.loops = problem.loops;
  result.edgeLengths = ownLengths(current);
  std::vector<char> flippedHere(std::size_t(tri.edgeCount()), 0);
  for (std::size_t k = std::size_t(tri.flipCount()); k < current.flippedEdges().size(); ++k)
    flippedHere[std::size_t(current.flippedEdges()[k])] = 1;
  for (int e = 0; e < tri.edgeCount(); ++e)
    if (!flippedHere[std::size_t(e)])
      result.maxLogLengthChange = std::max(
          result.maxLogLengthChange, std::abs(current.logLengths0()[e] - tri.logLengths0()[e]));
  result.triangulation = std::move(current);
  return result;
}

}  // namespace mspline::structure
