#include "mspline/structure/intrinsic/intrinsic_triangulation.h"

#include <algorithm>
#include <cmath>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"

namespace mspline::structure {

namespace {

// The three side lengths of face f at u (side k is the edge of halfedge 3f + k), with one common
// factor removed so that large log-lengths cannot overflow; angles and cotangents are scale
// invariant.
std::array<double, 3> faceSides(const IntrinsicTriangulation& tri, int f,
                                const Eigen::VectorXd& u) {
  std::array<double, 3> x;
  for (int k = 0; k < 3; ++k) {
    const int h = 3 * f + k;
    x[k] = tri.logLengths0()[tri.edge(h)] + 0.5 * (u[tri.tail(h)] + u[tri.tip(h)]);
  }
  const double shift = *std::max_element(x.begin(), x.end());
  return {std::exp(x[0] - shift), std::exp(x[1] - shift), std::exp(x[2] - shift)};
}

// Angle sums per vertex at u.
void checkSize(const IntrinsicTriangulation& tri, const Eigen::VectorXd& u) {
  MSPLINE_ASSERT(u.size() == tri.vertexCount(), "one scale factor per vertex");
}

}  // namespace

IntrinsicTriangulation::IntrinsicTriangulation(const TriMesh& mesh)
    : IntrinsicTriangulation(mesh, edgeLengths(mesh)) {}

IntrinsicTriangulation::IntrinsicTriangulation(const TriMesh& mesh,
                                               const Eigen::VectorXd& edgeLengths) {
  MSPLINE_ASSERT(edgeLengths.size() == static_cast<Eigen::Index>(mesh.n_edges()),
                 "one length per edge");
  MSPLINE_ASSERT((edgeLengths.array() > 0.0).all(), "edge lengths must be positive");
  const std::size_t halfedges = 3 * mesh.n_faces();
  tip_.assign(halfedges, -1);
  twin_.assign(halfedges, -1);
  edge_.assign(halfedges, -1);
  // Corner-table slot of every OpenMesh halfedge that lies in a face.
  std::vector<int> slot(mesh.n_halfedges(), -1);
  for (const auto f : mesh.faces()) {
    int k = 0;
    for (auto h = mesh.halfedge_handle(f); k < 3; h = mesh.next_halfedge_handle(h), ++k) {
      const int s = 3 * f.idx() + k;
      slot[std::size_t(h.idx())] = s;
      tip_[std::size_t(s)] = mesh.to_vertex_handle(h).idx();
      edge_[std::size_t(s)] = mesh.edge_handle(h).idx();
    }
  }
  edgeHalfedge_.assign(mesh.n_edges(), -1);
  for (const auto h : mesh.halfedges()) {
    const int s = slot[std::size_t(h.idx())];
    if (s < 0) continue;
    twin_[std::size_t(s)] = slot[std::size_t(mesh.opposite_halfedge_handle(h).idx())];
    edgeHalfedge_[std::size_t(edge_[std::size_t(s)])] = s;
  }
  for (int e : edgeHalfedge_) MSPLINE_ASSERT(e >= 0, "every edge lies in a face");
  boundaryVertex_.assign(mesh.n_vertices(), 0);
  for (const auto v : mesh.vertices()) boundaryVertex_[std::size_t(v.idx())] = mesh.is_boundary(v);
  inputEdge_.assign(mesh.n_edges(), 1);
  logLength0_ = edgeLengths.array().log();
  logUnit_ = logLength0_.size() ? logLength0_.mean() : 0.0;
}

std::array<int, 2> IntrinsicTriangulation::edgeVertices(int e) const {
  const int h = halfedge(e);
  return {tail(h), tip(h)};
}

std::vector<std::array<int, 3>> IntrinsicTriangulation::faces() const {
  std::vector<std::array<int, 3>> result(static_cast<std::size_t>(faceCount()));
  for (int f = 0; f < faceCount(); ++f)
    result[static_cast<std::size_t>(f)] = {tip(3 * f + 2), tip(3 * f), tip(3 * f + 1)};
  return result;
}

Eigen::VectorXd IntrinsicTriangulation::logLengths(const Eigen::VectorXd& u) const {
  checkSize(*this, u);
  Eigen::VectorXd x(edgeCount());
  for (int e = 0; e < edgeCount(); ++e) {
    const auto v = edgeVertices(e);
    x[e] = logLength0_[e] + 0.5 * (u[v[0]] + u[v[1]]);
  }
  return x;
}

Eigen::VectorXd IntrinsicTriangulation::lengths(const Eigen::VectorXd& u) const {
  return logLengths(u).array().exp();
}

double IntrinsicTriangulation::delaunayCosineSum(int e, const Eigen::VectorXd& u) const {
  const int h = halfedge(e);
  if (twin(h) < 0) return 0.0;
  const auto logLength = [&](int g) {
    return logLength0_[edge(g)] + 0.5 * (u[tail(g)] + u[tip(g)]);
  };
  // cos of the angle opposite g in its face, by the law of cosines; one common scale removed.
  const auto cosine = [&](int g) {
    const double xe = logLength(g), xa = logLength(next(g)), xb = logLength(prev(g));
    const double m = std::max({xe, xa, xb});
    const double le = std::exp(xe - m), la = std::exp(xa - m), lb = std::exp(xb - m);
    return (la * la + lb * lb - le * le) / (2.0 * la * lb);
  };
  return cosine(h) + cosine(twin(h));
}

void IntrinsicTriangulation::flip(int e) {
  const int a0 = halfedge(e);
  const int b0 = twin(a0);
  if (b0 < 0) throw InternalError("cannot flip boundary edge " + std::to_string(e));
  if (a0 / 3 == b0 / 3)
    throw InternalError("cannot flip edge " + std::to_string(e) + ": one face on both sides");
  // Face A = (i -> j, j -> k, k -> i) in slots a0, a1, a2, face B = (j -> i, i -> l, l -> j) in b0,
  // b1, b2. Afterwards A = (l -> k, k -> i, i -> l) and B = (k -> l, l -> j, j -> k).
  const int a1 = next(a0), a2 = prev(a0), b1 = next(b0), b2 = prev(b0);
  const int k = tip(a1), l = tip(b1);
  // Ptolemy: l_e l_new = l_jk l_il + l_ki l_lj, in log space.
  const double p = logLength0_[edge(a1)] + logLength0_[edge(b1)];
  const double q = logLength0_[edge(a2)] + logLength0_[edge(b2)];
  const double m = std::max(p, q);
  logLength0_[e] = m + std::log(std::exp(p - m) + std::exp(q - m)) - logLength0_[e];

  struct Record {
    int tip, twin, edge;
    bool representative;  // the slot is halfedge(edge): it stays so, keeping edgeVertices' order
  };
  const int from[4] = {a2, b1, b2, a1};
  const int to[4] = {a1, a2, b1, b2};
  Record saved[4];
  for (int n = 0; n < 4; ++n)
    saved[n] = {tip(from[n]), twin(from[n]), edge(from[n]), halfedge(edge(from[n])) == from[n]};
  // A twin among the moved slots moves with them (loops and multiple edges of a Delta-complex).
  const auto moved = [&](int s) {
    for (int n = 0; n < 4; ++n)
      if (from[n] == s) return to[n];
    return s;
  };
  for (int n = 0; n < 4; ++n) {
    const std::size_t d = std::size_t(to[n]);
    tip_[d] = saved[n].tip;
    edge_[d] = saved[n].edge;
    twin_[d] = saved[n].twin < 0 ? -1 : moved(saved[n].twin);
    if (twin_[d] >= 0) twin_[std::size_t(twin_[d])] = to[n];
    if (saved[n].representative) edgeHalfedge_[std::size_t(saved[n].edge)] = to[n];
  }
  tip_[std::size_t(a0)] = k;
  tip_[std::size_t(b0)] = l;
  inputEdge_[std::size_t(e)] = 0;
  flippedEdges_.push_back(e);
}

void IntrinsicTriangulation::setLogLengths0(const Eigen::VectorXd& logLengths) {
  MSPLINE_ASSERT(logLengths.size() == logLength0_.size(), "one log-length per edge");
  logLength0_ = logLengths;
}

long IntrinsicTriangulation::flipToDelaunay(const Eigen::VectorXd& u, double tolerance,
                                            const std::function<void(int)>& flipped) {
  checkSize(*this, u);
  std::vector<int> queue;
  std::vector<char> queued(std::size_t(edgeCount()), 0);
  for (int e = edgeCount() - 1; e >= 0; --e) {
    if (isBoundaryEdge(e)) continue;
    queue.push_back(e);
    queued[std::size_t(e)] = 1;
  }
  const long limit = 100L * (edgeCount() + 1);
  long count = 0;
  while (!queue.empty()) {
    const int e = queue.back();
    queue.pop_back();
    queued[std::size_t(e)] = 0;
    const int h = halfedge(e);
    if (h / 3 == twin(h) / 3 || delaunayCosineSum(e, u) >= -tolerance) continue;
    if (++count > limit)
      throw InternalError("Delaunay flipping did not terminate after " + std::to_string(limit) +
                          " flips");
    flip(e);
    if (flipped) flipped(e);
    // The four sides of the flipped quadrilateral may have become non-Delaunay.
    const int g = halfedge(e);
    for (int s : {next(g), prev(g), next(twin(g)), prev(twin(g))}) {
      const int side = edge(s);
      if (!queued[std::size_t(side)] && !isBoundaryEdge(side)) {
        queue.push_back(side);
        queued[std::size_t(side)] = 1;
      }
    }
  }
  return count;
}

Eigen::VectorXd intrinsicCornerAngles(const IntrinsicTriangulation& tri, const Eigen::VectorXd& u) {
  checkSize(tri, u);
  Eigen::VectorXd angles(3 * tri.faceCount());
  for (int f = 0; f < tri.faceCount(); ++f) {
    const auto l = faceSides(tri, f, u);
    const auto angle = triangleAngles(l[0], l[1], l[2]);
    for (int k = 0; k < 3; ++k) angles[3 * f + k] = angle[k];
  }
  return angles;
}

Eigen::VectorXd curvaturesFromCornerAngles(const IntrinsicTriangulation& tri,
                                           const Eigen::VectorXd& cornerAngles) {
  MSPLINE_ASSERT(cornerAngles.size() == 3 * tri.faceCount(), "one angle per halfedge");
  Eigen::VectorXd sums = Eigen::VectorXd::Zero(tri.vertexCount());
  // The corner opposite halfedge h is at the tip of next(h).
  for (int h = 0; h < 3 * tri.faceCount(); ++h) sums[tri.tip(tri.next(h))] += cornerAngles[h];
  for (int v = 0; v < tri.vertexCount(); ++v)
    sums[v] = (tri.isBoundaryVertex(v) ? kPi : 2.0 * kPi) - sums[v];
  return sums;
}

Eigen::VectorXd intrinsicCurvatures(const IntrinsicTriangulation& tri, const Eigen::VectorXd& u) {
  return curvaturesFromCornerAngles(tri, intrinsicCornerAngles(tri, u));
}

double intrinsicEnergy(const IntrinsicTriangulation& tri, const Eigen::VectorXd& u,
                       const Eigen::VectorXd& targetCurvature, double* magnitude) {
  checkSize(tri, u);
  MSPLINE_ASSERT(targetCurvature.size() == u.size(), "one target curvature per vertex");
  // Neumaier's compensated sum: the line search must resolve decreases far below the terms.
  double sum = 0.0, compensation = 0.0, absolute = 0.0;
  const auto add = [&](double term) {
    const double t = sum + term;
    compensation += std::abs(sum) >= std::abs(term) ? (sum - t) + term : (term - t) + sum;
    sum = t;
    absolute += std::abs(term);
  };
  Eigen::VectorXd angleSum = Eigen::VectorXd::Zero(u.size());
  for (int f = 0; f < tri.faceCount(); ++f) {
    const auto l = faceSides(tri, f, u);
    const auto angle = triangleAngles(l[0], l[1], l[2]);
    double face = 0.0;
    for (int k = 0; k < 3; ++k) {
      const int h = 3 * f + k;
      face += (2.0 * angle[k] - kPi) * (tri.logLengths0()[tri.edge(h)] - tri.logUnit()) +
              2.0 * lobachevsky(angle[k]);
      angleSum[tri.tip(tri.next(h))] += angle[k];
    }
    add(face);
  }
  for (int v = 0; v < tri.vertexCount(); ++v) {
    const double theta = (tri.isBoundaryVertex(v) ? kPi : 2.0 * kPi) - targetCurvature[v];
    add((theta - angleSum[v]) * u[v]);
  }
  if (magnitude) *magnitude = absolute;
  return sum + compensation;
}

Eigen::VectorXd intrinsicGradient(const IntrinsicTriangulation& tri, const Eigen::VectorXd& u,
                                  const Eigen::VectorXd& targetCurvature) {
  MSPLINE_ASSERT(targetCurvature.size() == u.size(), "one target curvature per vertex");
  return intrinsicCurvatures(tri, u) - targetCurvature;
}

Eigen::SparseMatrix<double> intrinsicHessian(const IntrinsicTriangulation& tri,
                                             const Eigen::VectorXd& u, const IndexMap& unknowns) {
  checkSize(tri, u);
  MSPLINE_ASSERT(unknowns.count() == std::size_t(tri.vertexCount()),
                 "one index-map entry per vertex");
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(12 * std::size_t(tri.faceCount()));
  for (int f = 0; f < tri.faceCount(); ++f) {
    const auto l = faceSides(tri, f, u);
    const double area4 = fourTimesArea(l[0], l[1], l[2]);
    for (int k = 0; k < 3; ++k) {
      const double a = l[k], b = l[(k + 1) % 3], c = l[(k + 2) % 3];
      // Half the cotangent of the angle opposite side k.
      const double w = area4 > 0.0 ? (b * b + c * c - a * a) / (2.0 * area4) : 0.0;
      const int h = 3 * f + k;
      const int i = unknowns.unknown(std::size_t(tri.tail(h)));
      const int j = unknowns.unknown(std::size_t(tri.tip(h)));
      // A loop (i == j) adds w + w - w - w = 0 to the diagonal, as it should.
      if (i >= 0) triplets.emplace_back(i, i, w);
      if (j >= 0) triplets.emplace_back(j, j, w);
      if (i >= 0 && j >= 0) {
        triplets.emplace_back(i, j, -w);
        triplets.emplace_back(j, i, -w);
      }
    }
  }
  Eigen::SparseMatrix<double> hessian(unknowns.size(), unknowns.size());
  hessian.setFromTriplets(triplets.begin(), triplets.end());
  return hessian;
}

}  // namespace mspline::structure
