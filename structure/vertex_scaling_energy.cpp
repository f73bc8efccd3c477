#include "structure/vertex_scaling_energy.h"

#include <algorithm>
#include <cmath>

#include "structure/errors.h"

namespace mspline::structure {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Coefficients c_k = zeta(2k) / (k (2k + 1)) of the Clausen series
//   Cl2(t) = t - t log t + t * sum_k c_k (t / 2 pi)^(2k),  0 < t <= pi,
// where (t / 2 pi)^2 <= 1/4 makes 30 terms enough for double precision.
constexpr int kClausenTerms = 30;

std::array<double, kClausenTerms> clausenCoefficients() {
  std::array<double, kClausenTerms> c{};
  for (int k = 1; k <= kClausenTerms; ++k) {
    double zeta;
    if (k == 1) {
      zeta = kPi * kPi / 6.0;
    } else if (k == 2) {
      zeta = std::pow(kPi, 4) / 90.0;
    } else {
      // The tail beyond n = 1000 is below 1e-15 for 2k >= 6, and its coefficient is tiny.
      zeta = 0.0;
      for (int n = 1000; n >= 1; --n) zeta += std::pow(static_cast<double>(n), -2.0 * k);
    }
    c[k - 1] = zeta / (k * (2.0 * k + 1.0));
  }
  return c;
}

// Clausen integral Cl2(t) = -int_0^t log|2 sin(s/2)| ds for t in [0, pi].
double clausenReduced(double t) {
  static const std::array<double, kClausenTerms> c = clausenCoefficients();
  if (t == 0.0) return 0.0;
  const double q = (t / (2.0 * kPi)) * (t / (2.0 * kPi));
  double sum = 0.0;
  for (int k = kClausenTerms - 1; k >= 0; --k) sum = (sum + c[k]) * q;
  return t - t * std::log(t) + t * sum;
}

double clausen(double t) {
  // Odd and 2 pi-periodic: reduce to (-pi, pi], then to [0, pi].
  t = std::remainder(t, 2.0 * kPi);
  return t < 0.0 ? -clausenReduced(-t) : clausenReduced(t);
}

// Kahan's stable Heron formula, times 4; 0 for lengths violating the triangle inequality.
double fourTimesArea(double a, double b, double c) {
  if (a < b) std::swap(a, b);
  if (a < c) std::swap(a, c);
  if (b < c) std::swap(b, c);
  const double p = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
  return p > 0.0 ? std::sqrt(p) : 0.0;
}

// The three side lengths of a face in the metric at u, with one common factor removed (angles and
// cotangents are scale invariant), so that large |u| cannot overflow. Side k is the edge of
// halfedge h[k], with h[1] = next(h[0]) and h[2] = next(h[1]).
struct FaceSides {
  std::array<TriMesh::HalfedgeHandle, 3> h;
  std::array<double, 3> length;
};

FaceSides faceSides(const TriMesh& mesh, TriMesh::FaceHandle f, const Eigen::VectorXd& inputLengths,
                    const Eigen::VectorXd& u) {
  FaceSides s;
  s.h[0] = mesh.halfedge_handle(f);
  s.h[1] = mesh.next_halfedge_handle(s.h[0]);
  s.h[2] = mesh.next_halfedge_handle(s.h[1]);
  std::array<double, 3> exponent;
  for (int k = 0; k < 3; ++k) {
    const double l0 = inputLengths[mesh.edge_handle(s.h[k]).idx()];
    exponent[k] =
        0.5 * (u[mesh.from_vertex_handle(s.h[k]).idx()] + u[mesh.to_vertex_handle(s.h[k]).idx()]);
    s.length[k] = l0;
  }
  const double shift = *std::max_element(exponent.begin(), exponent.end());
  for (int k = 0; k < 3; ++k) s.length[k] *= std::exp(exponent[k] - shift);
  return s;
}

void checkSizes(const TriMesh& mesh, const Eigen::VectorXd& inputLengths,
                const Eigen::VectorXd& u) {
  MSPLINE_ASSERT(inputLengths.size() == static_cast<Eigen::Index>(mesh.n_edges()),
                 "one input length per edge");
  MSPLINE_ASSERT(u.size() == static_cast<Eigen::Index>(mesh.n_vertices()),
                 "one scale factor per vertex");
}

// Angle sum per vertex at u.
Eigen::VectorXd angleSums(const TriMesh& mesh, const Eigen::VectorXd& inputLengths,
                          const Eigen::VectorXd& u) {
  Eigen::VectorXd sums = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices()));
  for (const auto f : mesh.faces()) {
    const FaceSides s = faceSides(mesh, f, inputLengths, u);
    const auto angle = triangleAngles(s.length[0], s.length[1], s.length[2]);
    // The corner opposite h[k] is the vertex h[k+1] points to.
    for (int k = 0; k < 3; ++k) sums[mesh.to_vertex_handle(s.h[(k + 1) % 3]).idx()] += angle[k];
  }
  return sums;
}

Eigen::VectorXd curvaturesFromAngleSums(const TriMesh& mesh, const Eigen::VectorXd& sums) {
  Eigen::VectorXd k(sums.size());
  for (const auto v : mesh.vertices())
    k[v.idx()] = (mesh.is_boundary(v) ? kPi : 2.0 * kPi) - sums[v.idx()];
  return k;
}

}  // namespace

double lobachevsky(double x) {
  return 0.5 * clausen(2.0 * x);
}

bool satisfiesTriangleInequality(double a, double b, double c) {
  if (a < b) std::swap(a, b);
  if (a < c) std::swap(a, c);
  if (b < c) std::swap(b, c);
  return c > 0.0 && c - (a - b) > 0.0;
}

std::array<double, 3> triangleAngles(double a, double b, double c) {
  // Order the sides x >= y >= z and use Kahan's parenthesization, which keeps the three
  // differences accurate even for needles (z << x).
  const std::array<double, 3> side = {a, b, c};
  std::array<int, 3> order = {0, 1, 2};
  std::sort(order.begin(), order.end(), [&](int i, int j) { return side[i] > side[j]; });
  const double x = side[order[0]], y = side[order[1]], z = side[order[2]];
  std::array<double, 3> angle{};
  const double px = z - (x - y);  // y + z - x
  if (px < 0.0) {
    // Only the longest side can break the triangle inequality.
    angle[order[0]] = kPi;
    return angle;
  }
  const double py = z + (x - y);  // x + z - y
  const double pz = x + (y - z);  // x + y - z
  const double s = x + (y + z);
  // tan(A/2) = sqrt(pb pc / (s pa)), written with atan2 so that pa = 0 gives A = pi.
  angle[order[0]] = 2.0 * std::atan2(std::sqrt(py * pz), std::sqrt(s * px));
  angle[order[1]] = 2.0 * std::atan2(std::sqrt(px * pz), std::sqrt(s * py));
  angle[order[2]] = 2.0 * std::atan2(std::sqrt(px * py), std::sqrt(s * pz));
  return angle;
}

Eigen::VectorXd edgeLengths(const TriMesh& mesh) {
  Eigen::VectorXd lengths(static_cast<Eigen::Index>(mesh.n_edges()));
  for (const auto e : mesh.edges()) lengths[e.idx()] = mesh.calc_edge_length(e);
  return lengths;
}

Eigen::VectorXd scaledEdgeLengths(const TriMesh& mesh, const Eigen::VectorXd& inputLengths,
                                  const Eigen::VectorXd& u) {
  checkSizes(mesh, inputLengths, u);
  Eigen::VectorXd lengths(inputLengths.size());
  for (const auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    lengths[e.idx()] =
        std::exp(0.5 * (u[mesh.from_vertex_handle(h).idx()] + u[mesh.to_vertex_handle(h).idx()])) *
        inputLengths[e.idx()];
  }
  return lengths;
}

std::vector<int> degenerateFaces(const TriMesh& mesh, const Eigen::VectorXd& lengths) {
  std::vector<int> faces;
  for (const auto f : mesh.faces()) {
    std::array<double, 3> l;
    int k = 0;
    for (const auto h : mesh.fh_range(f)) l[k++] = lengths[mesh.edge_handle(h).idx()];
    if (!satisfiesTriangleInequality(l[0], l[1], l[2])) faces.push_back(f.idx());
  }
  return faces;
}

Eigen::VectorXd cornerAngles(const TriMesh& mesh, const Eigen::VectorXd& lengths) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices()));
  checkSizes(mesh, lengths, zero);
  Eigen::VectorXd angles = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_halfedges()));
  for (const auto f : mesh.faces()) {
    const FaceSides s = faceSides(mesh, f, lengths, zero);
    const auto angle = triangleAngles(s.length[0], s.length[1], s.length[2]);
    for (int k = 0; k < 3; ++k) angles[s.h[k].idx()] = angle[k];
  }
  return angles;
}

Eigen::VectorXd vertexCurvatures(const TriMesh& mesh, const Eigen::VectorXd& lengths) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices()));
  checkSizes(mesh, lengths, zero);
  return curvaturesFromAngleSums(mesh, angleSums(mesh, lengths, zero));
}

double vertexScalingEnergy(const TriMesh& mesh, const Eigen::VectorXd& inputLengths,
                           const Eigen::VectorXd& u, const Eigen::VectorXd& targetCurvature) {
  checkSizes(mesh, inputLengths, u);
  MSPLINE_ASSERT(targetCurvature.size() == u.size(), "one target curvature per vertex");
  // E(u) = sum_i Theta_i u_i + sum_faces [ sum_k (2 alpha_k - pi) log l_k + 2 L(alpha_k) ], with
  // Theta_i the target angle sum; its u_i-derivative is Theta_i - (angle sum at i) = K_i -
  // target_i. Expanding log l_k = log l0_k + (u_i + u_j) / 2, the u-linear parts collect into
  //   E(u) = sum_i (K_i(u) - target_i) u_i + sum_faces [ sum_k (2 alpha_k - pi) log l0_k
  //          + 2 L(alpha_k) ],
  // whose first sum vanishes at the solution. Each face term is taken relative to its value at
  // u = 0 (so E(0) = 0), and log l0 in units of the mean log length (the angle changes sum to 0 per
  // face, so this unit does not change E). Small terms and a compensated (Neumaier) sum keep the
  // rounding of E far below the decreases the line search must resolve.
  const double logUnit = inputLengths.array().log().mean();
  double sum = 0.0, compensation = 0.0;
  const auto add = [&](double term) {
    const double t = sum + term;
    compensation += std::abs(sum) >= std::abs(term) ? (sum - t) + term : (term - t) + sum;
    sum = t;
  };
  Eigen::VectorXd angleSum = Eigen::VectorXd::Zero(u.size());
  for (const auto f : mesh.faces()) {
    const FaceSides s = faceSides(mesh, f, inputLengths, u);
    const auto angle = triangleAngles(s.length[0], s.length[1], s.length[2]);
    std::array<double, 3> l0;
    for (int k = 0; k < 3; ++k) l0[k] = inputLengths[mesh.edge_handle(s.h[k]).idx()];
    const auto angle0 = triangleAngles(l0[0], l0[1], l0[2]);
    double face = 0.0;
    for (int k = 0; k < 3; ++k) {
      face += 2.0 * (angle[k] - angle0[k]) * (std::log(l0[k]) - logUnit) +
              2.0 * (lobachevsky(angle[k]) - lobachevsky(angle0[k]));
      angleSum[mesh.to_vertex_handle(s.h[(k + 1) % 3]).idx()] += angle[k];
    }
    add(face);
  }
  for (const auto v : mesh.vertices()) {
    const double theta = (mesh.is_boundary(v) ? kPi : 2.0 * kPi) - targetCurvature[v.idx()];
    add((theta - angleSum[v.idx()]) * u[v.idx()]);
  }
  return sum + compensation;
}

Eigen::VectorXd vertexScalingGradient(const TriMesh& mesh, const Eigen::VectorXd& inputLengths,
                                      const Eigen::VectorXd& u,
                                      const Eigen::VectorXd& targetCurvature) {
  checkSizes(mesh, inputLengths, u);
  MSPLINE_ASSERT(targetCurvature.size() == u.size(), "one target curvature per vertex");
  return curvaturesFromAngleSums(mesh, angleSums(mesh, inputLengths, u)) - targetCurvature;
}

Eigen::SparseMatrix<double> vertexScalingHessian(const TriMesh& mesh,
                                                 const Eigen::VectorXd& inputLengths,
                                                 const Eigen::VectorXd& u) {
  return vertexScalingHessian(mesh, inputLengths, u, IndexMap(mesh.n_vertices(), {}));
}

Eigen::SparseMatrix<double> vertexScalingHessian(const TriMesh& mesh,
                                                 const Eigen::VectorXd& inputLengths,
                                                 const Eigen::VectorXd& u,
                                                 const IndexMap& unknowns) {
  checkSizes(mesh, inputLengths, u);
  MSPLINE_ASSERT(unknowns.count() == mesh.n_vertices(), "one index-map entry per vertex");
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(12 * mesh.n_faces());
  for (const auto f : mesh.faces()) {
    const FaceSides s = faceSides(mesh, f, inputLengths, u);
    const auto& l = s.length;
    const double area4 = fourTimesArea(l[0], l[1], l[2]);
    for (int k = 0; k < 3; ++k) {
      const double a = l[k], b = l[(k + 1) % 3], c = l[(k + 2) % 3];
      // Half the cotangent of the angle opposite side k: (b^2 + c^2 - a^2) / (4 area) / 2.
      const double w = area4 > 0.0 ? (b * b + c * c - a * a) / (2.0 * area4) : 0.0;
      const int i = unknowns.unknown(mesh.from_vertex_handle(s.h[k]).idx());
      const int j = unknowns.unknown(mesh.to_vertex_handle(s.h[k]).idx());
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
