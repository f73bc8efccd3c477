#include "mspline/structure/ricci/vertex_scaling_energy.h"

#include <algorithm>
#include <cmath>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/exact_scale.h"

namespace mspline::structure {

namespace {

constexpr double kLog2 = 0.693147180559945309417;

// Two power series of the Clausen integral Cl2(t) = -int_0^t log|2 sin(s/2)| ds on [0, pi], split
// at 2 pi / 3 where both converge like 9^-k, so 16 terms reach double precision on either side:
//   t <= 2 pi / 3:     Cl2(t) = t - t log t + t * sum_k zeta(2k) / (k (2k + 1)) (t / 2 pi)^(2k),
//   x = pi - t < pi/3: Cl2(t) = x log 2 - x * sum_k lambda(2k) / (k (2k + 1)) (x / pi)^(2k),
// the second from integrating log(2 cos(s/2)) = log 2 - sum_k lambda(2k) / k (s / pi)^(2k), with
// lambda(s) = (1 - 2^-s) zeta(s).
constexpr int kClausenTerms = 16;

struct ClausenCoefficients {
  std::array<double, kClausenTerms> small;   // zeta(2k) / (k (2k + 1))
  std::array<double, kClausenTerms> nearPi;  // lambda(2k) / (k (2k + 1))
};

ClausenCoefficients clausenCoefficients() {
  ClausenCoefficients c{};
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
    const double denominator = k * (2.0 * k + 1.0);
    c.small[k - 1] = zeta / denominator;
    c.nearPi[k - 1] = (1.0 - std::pow(2.0, -2.0 * k)) * zeta / denominator;
  }
  return c;
}

const ClausenCoefficients& coefficients() {
  static const ClausenCoefficients c = clausenCoefficients();
  return c;
}

// Cl2(t) for t in [0, pi].
double clausenReduced(double t, const ClausenCoefficients& c) {
  if (t <= 2.0 * kPi / 3.0) {
    if (t == 0.0) return 0.0;
    const double q = (t / (2.0 * kPi)) * (t / (2.0 * kPi));
    double sum = 0.0;
    for (int k = kClausenTerms - 1; k >= 0; --k) sum = (sum + c.small[k]) * q;
    return t - t * std::log(t) + t * sum;
  }
  const double x = kPi - t;
  const double q = (x / kPi) * (x / kPi);
  double sum = 0.0;
  for (int k = kClausenTerms - 1; k >= 0; --k) sum = (sum + c.nearPi[k]) * q;
  return x * kLog2 - x * sum;
}

double clausen(double t) {
  const ClausenCoefficients& c = coefficients();
  // Odd and 2 pi-periodic: reduce to (-pi, pi], then to [0, pi].
  if (!(std::abs(t) <= kPi)) t = std::remainder(t, 2.0 * kPi);
  return t < 0.0 ? -clausenReduced(-t, c) : clausenReduced(t, c);
}

// L(alpha) for a triangle angle alpha in [0, pi]: Cl2(2 alpha) / 2 with Cl2 odd and 2 pi-periodic.
double lobachevskyOfAngle(double alpha, const ClausenCoefficients& c) {
  const double t = 2.0 * alpha;
  return t <= kPi ? 0.5 * clausenReduced(t, c) : -0.5 * clausenReduced(2.0 * kPi - t, c);
}

// The three side lengths of a face in the metric at u, with one common factor removed (angles and
// cotangents are scale invariant), so that large |u| cannot overflow. Side k is the edge of
// halfedge h[k], with h[1] = next(h[0]) and h[2] = next(h[1]); h[k] runs from vertex[k] to
// vertex[(k + 1) % 3], so the corner opposite side k is vertex[(k + 2) % 3].
struct FaceSides {
  std::array<TriMesh::HalfedgeHandle, 3> h;
  std::array<int, 3> edge;
  std::array<int, 3> vertex;
  std::array<double, 3> length;
};

FaceSides faceConnectivity(const TriMesh& mesh, TriMesh::FaceHandle f) {
  FaceSides s;
  s.h[0] = mesh.halfedge_handle(f);
  s.h[1] = mesh.next_halfedge_handle(s.h[0]);
  s.h[2] = mesh.next_halfedge_handle(s.h[1]);
  for (int k = 0; k < 3; ++k) {
    s.edge[k] = mesh.edge_handle(s.h[k]).idx();
    s.vertex[(k + 1) % 3] = mesh.to_vertex_handle(s.h[k]).idx();
  }
  return s;
}

FaceSides faceSides(const TriMesh& mesh, TriMesh::FaceHandle f, const Eigen::VectorXd& inputLengths,
                    const Eigen::VectorXd& u) {
  FaceSides s = faceConnectivity(mesh, f);
  std::array<double, 3> exponent;
  for (int k = 0; k < 3; ++k) exponent[k] = 0.5 * (u[s.vertex[k]] + u[s.vertex[(k + 1) % 3]]);
  const double shift = std::max(exponent[0], std::max(exponent[1], exponent[2]));
  for (int k = 0; k < 3; ++k) s.length[k] = inputLengths[s.edge[k]] * std::exp(exponent[k] - shift);
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
    for (int k = 0; k < 3; ++k) sums[s.vertex[(k + 2) % 3]] += angle[k];
  }
  return sums;
}

Eigen::VectorXd curvaturesFromAngleSums(const TriMesh& mesh, const Eigen::VectorXd& sums) {
  Eigen::VectorXd k(sums.size());
  for (const auto v : mesh.vertices())
    k[v.idx()] = (mesh.is_boundary(v) ? kPi : 2.0 * kPi) - sums[v.idx()];
  return k;
}

// The Laplacian with the given edge weights, restricted to the unknowns and assembled directly in
// compressed form: every edge between unknowns gives two off-diagonal entries (explicit zeros
// included, so the pattern depends on the mesh only), and every vertex with an edge a diagonal.
Eigen::SparseMatrix<double> laplacianFromEdgeWeights(const TriMesh& mesh,
                                                     const std::vector<double>& weight,
                                                     const IndexMap& unknowns) {
  const int n = unknowns.size();
  std::vector<std::array<int, 2>> ends(mesh.n_edges());
  std::vector<int> count(static_cast<std::size_t>(n) + 1, 0);
  std::vector<double> diagonal(static_cast<std::size_t>(n), 0.0);
  std::vector<char> hasDiagonal(static_cast<std::size_t>(n), 0);
  for (const auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    const int i = unknowns.unknown(static_cast<std::size_t>(mesh.from_vertex_handle(h).idx()));
    const int j = unknowns.unknown(static_cast<std::size_t>(mesh.to_vertex_handle(h).idx()));
    ends[e.idx()] = {i, j};
    const double w = weight[e.idx()];
    for (int v : {i, j}) {
      if (v < 0) continue;
      diagonal[v] += w;
      hasDiagonal[v] = 1;
    }
    if (i >= 0 && j >= 0 && i != j) {
      ++count[i + 1];
      ++count[j + 1];
    }
  }
  for (int k = 0; k < n; ++k) count[k + 1] += count[k] + hasDiagonal[k];
  // Column k gets its entries in [count[k], count[k + 1]), unsorted, then sorted by row with
  // duplicate rows (two edges joining the same vertices) merged.
  std::vector<std::pair<int, double>> entry(static_cast<std::size_t>(count[n]));
  std::vector<int> fill(count.begin(), count.end() - 1);
  for (int k = 0; k < n; ++k)
    if (hasDiagonal[k]) entry[fill[k]++] = {k, diagonal[k]};
  for (std::size_t e = 0; e < ends.size(); ++e) {
    const auto [i, j] = ends[e];
    if (i < 0 || j < 0 || i == j) continue;
    entry[fill[i]++] = {j, -weight[e]};
    entry[fill[j]++] = {i, -weight[e]};
  }
  Eigen::SparseMatrix<double> matrix(n, n);
  matrix.resizeNonZeros(count[n]);
  int* outer = matrix.outerIndexPtr();
  int* inner = matrix.innerIndexPtr();
  double* value = matrix.valuePtr();
  int written = 0;
  for (int k = 0; k < n; ++k) {
    outer[k] = written;
    const auto first = entry.begin() + count[k], last = entry.begin() + count[k + 1];
    std::sort(first, last, [](const auto& x, const auto& y) { return x.first < y.first; });
    for (auto it = first; it != last; ++it) {
      if (written > outer[k] && inner[written - 1] == it->first) {
        value[written - 1] += it->second;
      } else {
        inner[written] = it->first;
        value[written] = it->second;
        ++written;
      }
    }
  }
  outer[n] = written;
  matrix.resizeNonZeros(written);
  return matrix;
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
  // differences accurate even for needles (z << x). Equal sides give equal angles, so ties may be
  // broken either way.
  const std::array<double, 3> side = {a, b, c};
  std::array<int, 3> order = {0, 1, 2};
  if (side[order[0]] < side[order[1]]) std::swap(order[0], order[1]);
  if (side[order[1]] < side[order[2]]) std::swap(order[1], order[2]);
  if (side[order[0]] < side[order[1]]) std::swap(order[0], order[1]);
  // Angles have no unit: sides scaled by a power of two (exact) keep the products below finite
  // and normal at any unit.
  const double unit = exactUnitScale(side[order[0]]);
  const double x = side[order[0]] * unit, y = side[order[1]] * unit, z = side[order[2]] * unit;
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
  OpenMesh::Vec3d edge;
  for (const auto e : mesh.edges()) {
    mesh.calc_edge_vector(e, edge);
    lengths[e.idx()] = exactScaledNorm(edge[0], edge[1], edge[2]);
  }
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
  const Eigen::VectorXd logLength = inputLengths.array().log();
  const Eigen::VectorXd relativeLog = logLength.array() - logLength.mean();
  const ClausenCoefficients& c = coefficients();
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
    for (int k = 0; k < 3; ++k) l0[k] = inputLengths[s.edge[k]];
    const auto angle0 = triangleAngles(l0[0], l0[1], l0[2]);
    double face = 0.0;
    for (int k = 0; k < 3; ++k) {
      face += 2.0 * (angle[k] - angle0[k]) * relativeLog[s.edge[k]] +
              2.0 * (lobachevskyOfAngle(angle[k], c) - lobachevskyOfAngle(angle0[k], c));
      angleSum[s.vertex[(k + 2) % 3]] += angle[k];
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
  // Half the cotangent of the angle opposite each side, summed per edge: (cot a + cot b) / 2.
  std::vector<double> weight(mesh.n_edges(), 0.0);
  for (const auto f : mesh.faces()) {
    const FaceSides s = faceSides(mesh, f, inputLengths, u);
    // A cotangent has no unit: computed on sides scaled by a power of two (exact).
    const double unit = exactUnitScale(std::max({s.length[0], s.length[1], s.length[2]}));
    const std::array<double, 3> l = {s.length[0] * unit, s.length[1] * unit, s.length[2] * unit};
    const double area4 = fourTimesArea(l[0], l[1], l[2]);
    if (area4 == 0.0) continue;
    for (int k = 0; k < 3; ++k) {
      const double a = l[k], b = l[(k + 1) % 3], c = l[(k + 2) % 3];
      // (b^2 + c^2 - a^2) / (4 area) / 2.
      weight[s.edge[k]] += (b * b + c * c - a * a) / (2.0 * area4);
    }
  }
  return laplacianFromEdgeWeights(mesh, weight, unknowns);
}

double fourTimesArea(double a, double b, double c) {
  if (a < b) std::swap(a, b);
  if (a < c) std::swap(a, c);
  if (b < c) std::swap(b, c);
  // The product of four lengths, on sides scaled by a power of two (exact) so that it neither
  // overflows nor underflows; the area is scaled back.
  const double unit = exactUnitScale(a);
  a *= unit, b *= unit, c *= unit;
  const double p = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
  return p > 0.0 ? std::sqrt(p) / unit / unit : 0.0;
}

}  // namespace mspline::structure
