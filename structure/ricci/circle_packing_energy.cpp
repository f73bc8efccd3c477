#include "mspline/structure/ricci/circle_packing_energy.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"

namespace mspline::structure {

namespace {

// Gauss-Legendre rule on [0, 1]; 16 nodes integrate the energy's 1-form along a segment to
// near machine precision wherever the angles are smooth along it.
constexpr int kQuadratureNodes = 16;

struct Quadrature {
  std::array<double, kQuadratureNodes> node;
  std::array<double, kQuadratureNodes> weight;
};

Quadrature gaussLegendre() {
  Quadrature q{};
  const int n = kQuadratureNodes;
  for (int i = 0; i < n; ++i) {
    // Newton's iteration on P_n from the classical initial guess for its i-th root.
    double x = std::cos(kPi * (i + 0.75) / (n + 0.5));
    double derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      derivative = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / derivative;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    q.node[i] = 0.5 * (1.0 - x);
    q.weight[i] = 1.0 / ((1.0 - x * x) * derivative * derivative);
  }
  return q;
}

// l^2 = a^2 + b^2 + 2 eta a b, written without cancellation for eta < 0.
double packedLength(double a, double b, double eta) {
  const double square = eta >= 0.0 ? a * a + b * b + 2.0 * eta * a * b
                                   : (a - b) * (a - b) + 2.0 * (1.0 + eta) * a * b;
  return std::sqrt(std::max(square, 0.0));
}

// One face: side k is the edge of halfedge h[k] (h[1] = next(h[0]), h[2] = next(h[1])), and
// corner k, the vertex opposite side k, is to(h[k+1]); side k joins corners k+1 and k+2. Radii and
// lengths carry a common factor removed (angles and dtheta/du are scale invariant), so that large
// |u| cannot overflow.
struct FaceCircles {
  std::array<TriMesh::HalfedgeHandle, 3> h;
  std::array<int, 3> corner;
  std::array<double, 3> radius;
  std::array<double, 3> eta;
  std::array<double, 3> length;
};

FaceCircles faceCircles(const TriMesh& mesh, TriMesh::FaceHandle f,
                        const CirclePackingMetric& metric, const Eigen::VectorXd& u) {
  FaceCircles s;
  s.h[0] = mesh.halfedge_handle(f);
  s.h[1] = mesh.next_halfedge_handle(s.h[0]);
  s.h[2] = mesh.next_halfedge_handle(s.h[1]);
  for (int k = 0; k < 3; ++k) {
    s.corner[k] = mesh.to_vertex_handle(s.h[(k + 1) % 3]).idx();
    s.eta[k] = metric.eta[mesh.edge_handle(s.h[k]).idx()];
  }
  const double shift = std::max({u[s.corner[0]], u[s.corner[1]], u[s.corner[2]]});
  for (int k = 0; k < 3; ++k)
    s.radius[k] = metric.radius[s.corner[k]] * std::exp(u[s.corner[k]] - shift);
  for (int k = 0; k < 3; ++k)
    s.length[k] = packedLength(s.radius[(k + 1) % 3], s.radius[(k + 2) % 3], s.eta[k]);
  return s;
}

void checkSizes(const TriMesh& mesh, const CirclePackingMetric& metric, const Eigen::VectorXd& u) {
  MSPLINE_ASSERT(metric.radius.size() == static_cast<Eigen::Index>(mesh.n_vertices()),
                 "one radius per vertex");
  MSPLINE_ASSERT(metric.eta.size() == static_cast<Eigen::Index>(mesh.n_edges()),
                 "one eta per edge");
  MSPLINE_ASSERT(u.size() == static_cast<Eigen::Index>(mesh.n_vertices()),
                 "one scale factor per vertex");
}

// Mean over the faces at each vertex of the radius of the face's tangent circle there.
Eigen::VectorXd tangentRadii(const TriMesh& mesh, const Eigen::VectorXd& lengths) {
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices()));
  Eigen::VectorXd count = Eigen::VectorXd::Zero(sum.size());
  for (const auto f : mesh.faces()) {
    std::array<TriMesh::HalfedgeHandle, 3> h;
    h[0] = mesh.halfedge_handle(f);
    h[1] = mesh.next_halfedge_handle(h[0]);
    h[2] = mesh.next_halfedge_handle(h[1]);
    std::array<double, 3> l;
    for (int k = 0; k < 3; ++k) l[k] = lengths[mesh.edge_handle(h[k]).idx()];
    if (!satisfiesTriangleInequality(l[0], l[1], l[2])) {
      throw InputError("circle packing needs non-degenerate triangles; face " +
                       std::to_string(f.idx()) + " violates the strict triangle inequality");
    }
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.to_vertex_handle(h[(k + 1) % 3]).idx();
      sum[v] += 0.5 * (l[(k + 1) % 3] + l[(k + 2) % 3] - l[k]);
      count[v] += 1.0;
    }
  }
  for (Eigen::Index v = 0; v < sum.size(); ++v) {
    if (count[v] == 0.0) throw InputError("circle packing needs every vertex on a face");
  }
  return sum.cwiseQuotient(count);
}

// eta_ij solving l^2 = r_i^2 + r_j^2 + 2 eta r_i r_j for the input lengths.
Eigen::VectorXd exactEta(const TriMesh& mesh, const Eigen::VectorXd& lengths,
                         const Eigen::VectorXd& radius) {
  Eigen::VectorXd eta(lengths.size());
  for (const auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    const double a = radius[mesh.from_vertex_handle(h).idx()];
    const double b = radius[mesh.to_vertex_handle(h).idx()];
    const double l = lengths[e.idx()];
    // (l^2 - (a - b)^2) / (2ab) - 1 avoids the cancellation in l^2 - a^2 - b^2 near eta = -1.
    eta[e.idx()] = (l - (a - b)) * (l + (a - b)) / (2.0 * a * b) - 1.0;
  }
  return eta;
}

Eigen::VectorXd angleSums(const TriMesh& mesh, const CirclePackingMetric& metric,
                          const Eigen::VectorXd& u) {
  Eigen::VectorXd sums = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices()));
  for (const auto f : mesh.faces()) {
    const FaceCircles s = faceCircles(mesh, f, metric, u);
    const auto angle = triangleAngles(s.length[0], s.length[1], s.length[2]);
    for (int k = 0; k < 3; ++k) sums[s.corner[k]] += angle[k];
  }
  return sums;
}

}  // namespace

CirclePackingMetric thurstonPackingMetric(const TriMesh& mesh) {
  const Eigen::VectorXd lengths = edgeLengths(mesh);
  CirclePackingMetric metric;
  metric.radius = tangentRadii(mesh, lengths);
  metric.eta = exactEta(mesh, lengths, metric.radius).cwiseMax(0.0).cwiseMin(1.0);
  return metric;
}

CirclePackingMetric inversiveDistanceMetric(const TriMesh& mesh) {
  const Eigen::VectorXd lengths = edgeLengths(mesh);
  CirclePackingMetric metric;
  metric.radius = tangentRadii(mesh, lengths);
  metric.eta = exactEta(mesh, lengths, metric.radius);
  for (const auto e : mesh.edges()) {
    if (metric.eta[e.idx()] < -1.0) {
      throw InputError("inversive distance " + std::to_string(metric.eta[e.idx()]) +
                       " < -1 at edge " + std::to_string(e.idx()) +
                       ": the initial circles of its ends are nested");
    }
  }
  return metric;
}

Eigen::VectorXd circlePackingEdgeLengths(const TriMesh& mesh, const CirclePackingMetric& metric,
                                         const Eigen::VectorXd& u) {
  checkSizes(mesh, metric, u);
  Eigen::VectorXd lengths(static_cast<Eigen::Index>(mesh.n_edges()));
  for (const auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    const int i = mesh.from_vertex_handle(h).idx();
    const int j = mesh.to_vertex_handle(h).idx();
    lengths[e.idx()] = packedLength(metric.radius[i] * std::exp(u[i]),
                                    metric.radius[j] * std::exp(u[j]), metric.eta[e.idx()]);
  }
  return lengths;
}

double circlePackingEnergy(const TriMesh& mesh, const CirclePackingMetric& metric,
                           const Eigen::VectorXd& u, const Eigen::VectorXd& targetCurvature) {
  checkSizes(mesh, metric, u);
  MSPLINE_ASSERT(targetCurvature.size() == u.size(), "one target curvature per vertex");
  // The 1-form sum_i (K_i - target_i) du_i is closed (its derivative, the Hessian, is symmetric),
  // so the energy is its integral along any path from 0; the straight segment and Gauss-Legendre
  // quadrature suffice because the energy only serves the line search, which compares values
  // whose differences are far above the quadrature error. A closed form is not needed.
  static const Quadrature rule = gaussLegendre();
  double energy = 0.0;
  for (int n = 0; n < kQuadratureNodes; ++n) {
    const Eigen::VectorXd gradient =
        circlePackingGradient(mesh, metric, rule.node[n] * u, targetCurvature);
    energy += rule.weight[n] * gradient.dot(u);
  }
  return energy;
}

Eigen::VectorXd circlePackingGradient(const TriMesh& mesh, const CirclePackingMetric& metric,
                                      const Eigen::VectorXd& u,
                                      const Eigen::VectorXd& targetCurvature) {
  checkSizes(mesh, metric, u);
  MSPLINE_ASSERT(targetCurvature.size() == u.size(), "one target curvature per vertex");
  const Eigen::VectorXd sums = angleSums(mesh, metric, u);
  Eigen::VectorXd gradient(sums.size());
  for (const auto v : mesh.vertices()) {
    gradient[v.idx()] =
        (mesh.is_boundary(v) ? kPi : 2.0 * kPi) - sums[v.idx()] - targetCurvature[v.idx()];
  }
  return gradient;
}

Eigen::SparseMatrix<double> circlePackingHessian(const TriMesh& mesh,
                                                 const CirclePackingMetric& metric,
                                                 const Eigen::VectorXd& u) {
  return circlePackingHessian(mesh, metric, u, IndexMap(mesh.n_vertices(), {}));
}

Eigen::SparseMatrix<double> circlePackingHessian(const TriMesh& mesh,
                                                 const CirclePackingMetric& metric,
                                                 const Eigen::VectorXd& u,
                                                 const IndexMap& unknowns) {
  checkSizes(mesh, metric, u);
  MSPLINE_ASSERT(unknowns.count() == mesh.n_vertices(), "one index-map entry per vertex");
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(9 * mesh.n_faces());
  for (const auto f : mesh.faces()) {
    const FaceCircles s = faceCircles(mesh, f, metric, u);
    const auto& l = s.length;
    const auto& r = s.radius;
    const double area4 = fourTimesArea(l[0], l[1], l[2]);
    // dtheta/du = (dtheta/dl)(dl/du). The derivative cosine law gives
    //   dtheta_a/dl_a = l_a / (2A),  dtheta_a/dl_b = -l_a cos(theta_c) / (2A)  (b != a, c third),
    // and differentiating eq. 7, dl_b/du_p = (r_p^2 + eta_b r_p r_q) / l_b for the ends p, q of
    // side b.
    std::array<std::array<double, 3>, 3> dThetaDu{};
    if (area4 > 0.0) {
      const auto angle = triangleAngles(l[0], l[1], l[2]);
      const double twiceArea = 0.5 * area4;
      std::array<std::array<double, 3>, 3> dLengthDu{};
      for (int b = 0; b < 3; ++b) {
        const int p = (b + 1) % 3, q = (b + 2) % 3;
        dLengthDu[b][p] = (r[p] * r[p] + s.eta[b] * r[p] * r[q]) / l[b];
        dLengthDu[b][q] = (r[q] * r[q] + s.eta[b] * r[p] * r[q]) / l[b];
      }
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
          const double dThetaDl = l[a] / twiceArea * (a == b ? 1.0 : -std::cos(angle[3 - a - b]));
          for (int p = 0; p < 3; ++p) dThetaDu[a][p] += dThetaDl * dLengthDu[b][p];
        }
      }
    }
    // K_a = 2 pi - (angle sum), so the face adds -dtheta_a/du_p to dK_a/du_p.
    for (int a = 0; a < 3; ++a) {
      const int i = unknowns.unknown(s.corner[a]);
      if (i < 0) continue;
      for (int p = 0; p < 3; ++p) {
        const int j = unknowns.unknown(s.corner[p]);
        if (j >= 0) triplets.emplace_back(i, j, -dThetaDu[a][p]);
      }
    }
  }
  Eigen::SparseMatrix<double> hessian(unknowns.size(), unknowns.size());
  hessian.setFromTriplets(triplets.begin(), triplets.end());
  return hessian;
}

}  // namespace mspline::structure
