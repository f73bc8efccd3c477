#include "mspline/structure/ricci/holonomy_quantization.h"

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
#include "mspline/structure/topology/homotopy_basis.h"

namespace mspline::structure {

namespace {

void requireClosedSurface(const TriMesh& mesh) {
  requireConnectedManifold(mesh);
  for (const auto h : mesh.halfedges())
    if (mesh.is_boundary(h))
      throw TopologyError("holonomy quantization needs a closed surface; this one has a boundary");
}

void checkLengths(const TriMesh& mesh, const Eigen::VectorXd& lengths) {
  if (lengths.size() != Eigen::Index(mesh.n_edges()))
    throw InputError("holonomy quantization: " + std::to_string(lengths.size()) +
                     " edge lengths for a mesh with " + std::to_string(mesh.n_edges()) + " edges");
}

TriMesh::HalfedgeHandle handle(int h) {
  return TriMesh::HalfedgeHandle(h);
}

/// d(angle opposite h)/d(log length) of the three edges of h's face, by edge index: with A the
/// angle opposite h and B, C the next ones, dA = (cot B + cot C) dlog a - cot C dlog b - cot B
/// dlog c.
std::array<std::pair<int, double>, 3> angleGradient(const TriMesh& mesh,
                                                    const Eigen::VectorXd& lengths, int h) {
  const auto ha = handle(h);
  const auto hb = mesh.next_halfedge_handle(ha);
  const auto hc = mesh.next_halfedge_handle(hb);
  const int ea = mesh.edge_handle(ha).idx(), eb = mesh.edge_handle(hb).idx(),
            ec = mesh.edge_handle(hc).idx();
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

LoopStep loopStep(const TriMesh& mesh, int in, int out) {
  const auto g = handle(in);
  if (out == mesh.next_halfedge_handle(g).idx()) return {mesh.prev_halfedge_handle(g).idx(), 1.0};
  MSPLINE_ASSERT(out == mesh.prev_halfedge_handle(g).idx(),
                 "a dual loop must leave each face by another edge than it entered");
  return {mesh.next_halfedge_handle(g).idx(), -1.0};
}

template <class Visit>
void forEachStep(const TriMesh& mesh, const DualLoop& loop, Visit&& visit) {
  const auto& hs = loop.halfedges;
  for (std::size_t i = 0; i < hs.size(); ++i) {
    const int in = mesh.opposite_halfedge_handle(handle(hs[(i + hs.size() - 1) % hs.size()])).idx();
    visit(loopStep(mesh, in, hs[i]));
  }
}

// How freely each edge's log length may move: the step minimizes sum dlog_e^2 / freedom_e, with
// freedom sin^4 of the smallest angle of the edge's triangles, so that skinny triangles (the
// overlay has many) barely change and the deformation goes where triangles can take it. With
// plain least norm eight.off stalls on degenerating triangles; with sin^2 too.
Eigen::VectorXd edgeFreedom(const TriMesh& mesh, const Eigen::VectorXd& lengths) {
  const Eigen::VectorXd angles = cornerAngles(mesh, lengths);
  Eigen::VectorXd freedom = Eigen::VectorXd::Ones(lengths.size());
  for (const auto f : mesh.faces()) {
    double smallest = kPi;
    for (const auto h : mesh.fh_range(f)) smallest = std::min(smallest, angles[h.idx()]);
    const double s = std::sin(smallest);
    for (const auto e : mesh.fe_range(f))
      freedom[e.idx()] = std::min(freedom[e.idx()], s * s * s * s);
  }
  return freedom;
}

}  // namespace

std::vector<DualLoop> homologyDualLoops(const TriMesh& mesh) {
  requireClosedSurface(mesh);
  const std::size_t nv = mesh.n_vertices(), nf = mesh.n_faces();
  std::vector<char> primal(mesh.n_edges(), 0), dual(mesh.n_edges(), 0);
  std::vector<char> seen(nv, 0);
  std::deque<int> queue{0};
  seen[0] = 1;
  while (!queue.empty()) {
    const auto v = TriMesh::VertexHandle(queue.front());
    queue.pop_front();
    for (const auto h : mesh.voh_range(v)) {
      const int w = mesh.to_vertex_handle(h).idx();
      if (seen[std::size_t(w)]) continue;
      seen[std::size_t(w)] = 1;
      primal[std::size_t(mesh.edge_handle(h).idx())] = 1;
      queue.push_back(w);
    }
  }
  // toParent[f]: the halfedge of f whose opposite lies in f's parent in the dual tree.
  std::vector<int> toParent(nf, -1), depth(nf, -1);
  depth[0] = 0;
  queue = {0};
  while (!queue.empty()) {
    const auto f = TriMesh::FaceHandle(queue.front());
    queue.pop_front();
    for (const auto h : mesh.fh_range(f)) {
      const auto e = mesh.edge_handle(h);
      if (primal[std::size_t(e.idx())]) continue;
      const auto opposite = mesh.opposite_halfedge_handle(h);
      const int g = mesh.face_handle(opposite).idx();
      if (depth[std::size_t(g)] >= 0) continue;
      depth[std::size_t(g)] = depth[std::size_t(f.idx())] + 1;
      toParent[std::size_t(g)] = opposite.idx();
      dual[std::size_t(e.idx())] = 1;
      queue.push_back(g);
    }
  }
  const auto parentFace = [&](int f) {
    return mesh.face_handle(mesh.opposite_halfedge_handle(handle(toParent[std::size_t(f)]))).idx();
  };
  std::vector<DualLoop> loops;
  for (const auto e : mesh.edges()) {
    if (primal[std::size_t(e.idx())] || dual[std::size_t(e.idx())]) continue;
    // Cross e from f0 into f1, climb from f1 to the common ancestor, descend to f0.
    const auto h0 = mesh.halfedge_handle(e, 0);
    int up = mesh.face_handle(mesh.opposite_halfedge_handle(h0)).idx();
    int down = mesh.face_handle(h0).idx();
    DualLoop loop{{h0.idx()}};
    std::vector<int> descent;
    while (up != down) {
      if (depth[std::size_t(up)] >= depth[std::size_t(down)]) {
        loop.halfedges.push_back(toParent[std::size_t(up)]);
        up = parentFace(up);
      } else {
        descent.push_back(mesh.opposite_halfedge_handle(handle(toParent[std::size_t(down)])).idx());
        down = parentFace(down);
      }
    }
    loop.halfedges.insert(loop.halfedges.end(), descent.rbegin(), descent.rend());
    loops.push_back(std::move(loop));
  }
  const long genus = (2 - (long(nv) - long(mesh.n_edges()) + long(nf))) / 2;
  MSPLINE_ASSERT(long(loops.size()) == 2 * genus, "tree-cotree leaves 2g edges");
  return loops;
}

Eigen::VectorXd loopRotations(const TriMesh& mesh, const Eigen::VectorXd& lengths,
                              const std::vector<DualLoop>& loops) {
  checkLengths(mesh, lengths);
  const Eigen::VectorXd angles = cornerAngles(mesh, lengths);
  Eigen::VectorXd rotation(Eigen::Index(loops.size()));
  for (std::size_t k = 0; k < loops.size(); ++k) {
    double sum = 0.0;
    forEachStep(mesh, loops[k], [&](const LoopStep& step) {
      sum += kPi + step.sign * (kPi - angles[step.cornerHalfedge]);
    });
    rotation[Eigen::Index(k)] = sum;
  }
  return rotation;
}

Eigen::VectorXd holonomyResiduals(const TriMesh& mesh, const Eigen::VectorXd& lengths,
                                  const HolonomyProblem& problem) {
  const Eigen::VectorXd curvature = vertexCurvatures(mesh, lengths);
  std::vector<char> excluded(mesh.n_vertices(), 0);
  excluded[std::size_t(problem.droppedVertex)] = 1;
  const IndexMap rows(mesh.n_vertices(), excluded);
  const Eigen::VectorXd rotation = loopRotations(mesh, lengths, problem.loops);
  Eigen::VectorXd residual(rows.size() + rotation.size());
  residual.head(rows.size()) = rows.gather(curvature - problem.targetCurvature);
  residual.tail(rotation.size()) = rotation - problem.targetRotation;
  return residual;
}

Eigen::SparseMatrix<double> holonomyJacobian(const TriMesh& mesh, const Eigen::VectorXd& lengths,
                                             const HolonomyProblem& problem) {
  checkLengths(mesh, lengths);
  std::vector<char> excluded(mesh.n_vertices(), 0);
  excluded[std::size_t(problem.droppedVertex)] = 1;
  const IndexMap rows(mesh.n_vertices(), excluded);
  std::vector<Eigen::Triplet<double>> entries;
  // Curvature is 2 pi minus the angle sum: each angle enters its vertex's row negated.
  for (const auto h : mesh.halfedges()) {
    if (mesh.is_boundary(h)) continue;
    const int row =
        rows.unknown(std::size_t(mesh.to_vertex_handle(mesh.next_halfedge_handle(h)).idx()));
    if (row < 0) continue;
    for (const auto& [edge, d] : angleGradient(mesh, lengths, h.idx()))
      entries.emplace_back(row, edge, -d);
  }
  for (std::size_t k = 0; k < problem.loops.size(); ++k) {
    const int row = rows.size() + int(k);
    forEachStep(mesh, problem.loops[k], [&](const LoopStep& step) {
      for (const auto& [edge, d] : angleGradient(mesh, lengths, step.cornerHalfedge))
        entries.emplace_back(row, edge, -step.sign * d);
    });
  }
  Eigen::SparseMatrix<double> jacobian(rows.size() + Eigen::Index(problem.loops.size()),
                                       Eigen::Index(mesh.n_edges()));
  jacobian.setFromTriplets(entries.begin(), entries.end());
  return jacobian;
}

HolonomyQuantizationResult quantizeHolonomy(const TriMesh& mesh, const Eigen::VectorXd& lengths,
                                            const std::vector<Cone>& cones,
                                            const HolonomyQuantizationOptions& options) {
  checkLengths(mesh, lengths);
  HolonomyQuantizationResult result;
  HolonomyProblem problem;
  problem.loops = homologyDualLoops(mesh);
  problem.targetCurvature = Eigen::VectorXd::Zero(Eigen::Index(mesh.n_vertices()));
  for (const auto& cone : cones) {
    if (cone.vertex < 0 || cone.vertex >= int(mesh.n_vertices()))
      throw InputError("holonomy quantization: cone vertex " + std::to_string(cone.vertex) +
                       " out of range");
    problem.targetCurvature[cone.vertex] = cone.curvature;
  }
  result.loops = problem.loops;
  result.initialRotation = loopRotations(mesh, lengths, problem.loops);
  problem.targetRotation =
      (result.initialRotation / options.quantum).array().round().matrix() * options.quantum;
  result.targetRotation = problem.targetRotation;

  const auto maxAbs = [](const Eigen::VectorXd& v) {
    return v.size() == 0 ? 0.0 : v.cwiseAbs().maxCoeff();
  };
  Eigen::VectorXd logLengths = lengths.array().log().matrix();
  Eigen::VectorXd current = lengths;
  Eigen::VectorXd residual = holonomyResiduals(mesh, current, problem);
  SparseCholesky cholesky;
  bool analyzed = false;
  result.message = "did not converge in " + std::to_string(options.maxIterations) + " steps";
  for (;;) {
    result.maxResidual = maxAbs(residual);
    if (result.maxResidual <= options.tolerance) {
      result.converged = true;
      result.message = "converged";
      break;
    }
    if (result.iterations == options.maxIterations) break;
    ++result.iterations;
    // Weighted least-norm Newton step: the smallest change of log lengths (in the freedom-weighted
    // norm) that zeroes the linearization.
    const Eigen::SparseMatrix<double> jacobian = holonomyJacobian(mesh, current, problem);
    const Eigen::VectorXd freedom = edgeFreedom(mesh, current);
    const Eigen::SparseMatrix<double> scaled = jacobian * freedom.asDiagonal();
    const Eigen::SparseMatrix<double> normal = scaled * jacobian.transpose();
    if (!analyzed) {
      cholesky.analyze(normal);
      analyzed = true;
    }
    cholesky.factorize(normal);
    const Eigen::VectorXd step = scaled.transpose() * cholesky.solve(-residual);
    bool accepted = false;
    for (double t = 1.0; t > 1e-8 && !accepted; t *= 0.5) {
      const Eigen::VectorXd trialLog = logLengths + t * step;
      const Eigen::VectorXd trial = trialLog.array().exp().matrix();
      if (!degenerateFaces(mesh, trial).empty()) continue;
      const Eigen::VectorXd trialResidual = holonomyResiduals(mesh, trial, problem);
      if (maxAbs(trialResidual) >= result.maxResidual) continue;
      logLengths = trialLog;
      current = trial;
      residual = trialResidual;
      accepted = true;
    }
    if (!accepted) {
      result.message = "the line search stalled at residual " + std::to_string(result.maxResidual);
      break;
    }
  }
  result.edgeLengths = current;
  result.maxLogLengthChange = maxAbs(logLengths - lengths.array().log().matrix());
  return result;
}

}  // namespace mspline::structure
