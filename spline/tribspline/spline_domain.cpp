#include "mspline/spline/tribspline/spline_domain.h"
#include "mspline/structure/core/constants.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/index_map.h"
#include "mspline/structure/core/sparse_cholesky.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"

namespace mspline::spline {

namespace {

using structure::InputError;
using structure::RigidMotion;

std::string faceName(int f) {
  return "domain face " + std::to_string(f);
}

/// The motion placing face g (its side `gs` glued to side `fs` of face f, which `fPlacement`
/// places) into the same frame as f.
RigidMotion glue(const SplineDomain& domain, int f, const RigidMotion& fPlacement, int fs, int g,
                 int gs) {
  const auto fc = canonicalCorners(domain, f);
  const auto gc = canonicalCorners(domain, g);
  // The shared side runs f: fs -> fs+1 and g: gs -> gs+1 in opposite directions.
  const Eigen::Vector2d a = fPlacement(fc[std::size_t((fs + 1) % 3)]);
  const Eigen::Vector2d b = fPlacement(fc[std::size_t(fs)]);
  const Eigen::Vector2d from = gc[std::size_t((gs + 1) % 3)] - gc[std::size_t(gs)];
  const Eigen::Vector2d to = b - a;
  RigidMotion motion;
  motion.angle = std::atan2(to.y(), to.x()) - std::atan2(from.y(), from.x());
  motion.translation = Eigen::Vector2d::Zero();
  motion.translation = a - motion(gc[std::size_t(gs)]);
  return motion;
}

/// Adds face g with `placement` to the chart of `home`, unless the chart has it at that place
/// already.
void place(const SplineDomain& domain, HomeChart& chart, int g, const RigidMotion& placement) {
  const auto corners = canonicalCorners(domain, g);
  const auto& lengths = domain.sideLengths[std::size_t(g)];
  const double tolerance = 1e-9 * (lengths[0] + lengths[1] + lengths[2]);
  for (int existing : chart.findAll(g)) {
    bool same = true;
    for (const auto& corner : corners)
      same &=
          (chart.placement[std::size_t(existing)](corner) - placement(corner)).norm() <= tolerance;
    if (same) return;
  }
  chart.faces.push_back(g);
  chart.placement.push_back(placement);
}

}  // namespace

void validateDomain(const SplineDomain& domain) {
  const std::size_t count = domain.faces.size();
  if (domain.sideLengths.size() != count || domain.neighbour.size() != count ||
      domain.neighbourSide.size() != count)
    throw InputError("spline domain: per-face arrays of different sizes");
  for (std::size_t f = 0; f < count; ++f) {
    const auto& l = domain.sideLengths[f];
    for (int k = 0; k < 3; ++k) {
      const int v = domain.faces[f][std::size_t(k)];
      if (v < 0 || v >= domain.vertexCount())
        throw InputError("spline domain: " + faceName(int(f)) + " has vertex " + std::to_string(v) +
                         " out of range");
      const int g = domain.neighbour[f][std::size_t(k)];
      const int gs = domain.neighbourSide[f][std::size_t(k)];
      if (g < 0 || g >= int(count) || gs < 0 || gs > 2 ||
          domain.neighbour[std::size_t(g)][std::size_t(gs)] != int(f) ||
          domain.neighbourSide[std::size_t(g)][std::size_t(gs)] != k)
        throw InputError("spline domain: the neighbour across side " + std::to_string(k) + " of " +
                         faceName(int(f)) + " does not point back");
      const double other = domain.sideLengths[std::size_t(g)][std::size_t(gs)];
      if (!(std::abs(other - l[std::size_t(k)]) <= 1e-9 * std::max(other, l[std::size_t(k)])))
        throw InputError("spline domain: side " + std::to_string(k) + " of " + faceName(int(f)) +
                         " has two lengths");
    }
    if (!(l[0] > 0 && l[1] > 0 && l[2] > 0 && l[0] < l[1] + l[2] && l[1] < l[2] + l[0] &&
          l[2] < l[0] + l[1]))
      throw InputError("spline domain: " + faceName(int(f)) + " violates the triangle inequality");
  }
}

SplineDomain domainFromMesh(const structure::TriMesh& mesh, const Eigen::VectorXd& lengths,
                            double coneTolerance) {
  if (lengths.size() != Eigen::Index(mesh.n_edges()))
    throw InputError("spline domain: " + std::to_string(lengths.size()) + " lengths for " +
                     std::to_string(mesh.n_edges()) + " edges");
  for (const auto h : mesh.halfedges())
    if (mesh.is_boundary(h))
      throw InputError("spline domain: the surface has a boundary; only closed surfaces for now");
  // Position of every halfedge in its face's sequence from halfedge_handle(f).
  std::vector<int> slot(mesh.n_halfedges(), -1);
  for (const auto f : mesh.faces()) {
    auto h = mesh.halfedge_handle(f);
    for (int k = 0; k < 3; ++k, h = mesh.next_halfedge_handle(h)) slot[std::size_t(h.idx())] = k;
  }
  SplineDomain domain;
  for (const auto f : mesh.faces()) {
    std::array<int, 3> corners{}, neighbours{}, sides{};
    std::array<double, 3> sideLengths{};
    auto h = mesh.halfedge_handle(f);
    for (int k = 0; k < 3; ++k, h = mesh.next_halfedge_handle(h)) {
      const auto opposite = mesh.opposite_halfedge_handle(h);
      corners[std::size_t(k)] = mesh.from_vertex_handle(h).idx();
      sideLengths[std::size_t(k)] = lengths[mesh.edge_handle(h).idx()];
      neighbours[std::size_t(k)] = mesh.face_handle(opposite).idx();
      sides[std::size_t(k)] = slot[std::size_t(opposite.idx())];
    }
    domain.faces.push_back(corners);
    domain.sideLengths.push_back(sideLengths);
    domain.neighbour.push_back(neighbours);
    domain.neighbourSide.push_back(sides);
  }
  const Eigen::VectorXd curvature = structure::vertexCurvatures(mesh, lengths);
  domain.cone.resize(mesh.n_vertices());
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v)
    domain.cone[v] = std::abs(curvature[Eigen::Index(v)]) > coneTolerance;
  return domain;
}

SplineDomain domainFromCoarse(const structure::CoarseTriangulation& coarse) {
  SplineDomain domain;
  domain.faces = coarse.faces;
  domain.sideLengths = coarse.sideLengths;
  domain.neighbour = coarse.neighbour;
  domain.neighbourSide = coarse.neighbourSide;
  domain.cone = coarse.isCone;
  validateDomain(domain);
  return domain;
}

namespace {

// Angles of a face at corners 0, 1, 2 (corner k faces side k + 1), by the half-angle formula.
std::array<double, 3> faceAngles(const std::array<double, 3>& l) {
  const auto opposite = structure::triangleAngles(l[0], l[1], l[2]);
  return {opposite[1], opposite[2], opposite[0]};
}

Eigen::VectorXd domainCurvatures(const SplineDomain& domain) {
  Eigen::VectorXd curvature = Eigen::VectorXd::Constant(domain.vertexCount(), 2.0 * kPi);
  for (int f = 0; f < domain.faceCount(); ++f) {
    const auto angle = faceAngles(domain.sideLengths[std::size_t(f)]);
    for (int k = 0; k < 3; ++k)
      curvature[domain.faces[std::size_t(f)][std::size_t(k)]] -= angle[std::size_t(k)];
  }
  return curvature;
}

}  // namespace

DomainPolish polishDomainMetric(SplineDomain& domain) {
  validateDomain(domain);
  const int n = domain.vertexCount();
  // Targets: 0 away from cones, the present curvature at cones. Their sum must equal the present
  // total (Gauss-Bonnet, up to the rounding of the angle sums); the difference is spread over all
  // vertices, where it is far below the tolerance, rather than left to the one vertex whose scale
  // is held fixed.
  const Eigen::VectorXd present = domainCurvatures(domain);
  Eigen::VectorXd target = Eigen::VectorXd::Zero(n);
  for (int v = 0; v < n; ++v)
    if (domain.cone[std::size_t(v)]) target[v] = present[v];
  target.array() += (present.sum() - target.sum()) / n;
  DomainPolish polish;
  const std::vector<std::array<double, 3>> original = domain.sideLengths;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
  // Vertex 0 fixes the scale; the others are unknowns.
  std::vector<char> excluded(std::size_t(n), 0);
  excluded[0] = 1;
  const structure::IndexMap unknowns(std::size_t(n), excluded);
  structure::SparseCholesky cholesky;
  for (;;) {
    const Eigen::VectorXd error = domainCurvatures(domain) - target;
    const double worst = error.cwiseAbs().maxCoeff();
    if (polish.iterations == 0) polish.initialError = worst;
    polish.finalError = worst;
    if (worst <= 1e-14 || polish.iterations == 5) break;
    ++polish.iterations;
    // dK_v/du_w = -sum of d(angle at v)/du_w; d(angle at i)/du_j = cot(angle at k) / 2.
    std::vector<Eigen::Triplet<double>> entries;
    for (int f = 0; f < domain.faceCount(); ++f) {
      const auto angle = faceAngles(domain.sideLengths[std::size_t(f)]);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          if (i == j) continue;
          const int k = 3 - i - j;
          const double d = 0.5 / std::tan(angle[std::size_t(k)]);
          const int vi = domain.faces[std::size_t(f)][std::size_t(i)];
          const int vj = domain.faces[std::size_t(f)][std::size_t(j)];
          entries.emplace_back(vi, vj, -d);
          entries.emplace_back(vi, vi, d);
        }
    }
    Eigen::SparseMatrix<double> jacobian(n, n);
    jacobian.setFromTriplets(entries.begin(), entries.end());
    const Eigen::SparseMatrix<double> system = unknowns.restrict(jacobian);
    cholesky.compute(system);
    Eigen::VectorXd step = Eigen::VectorXd::Zero(n);
    unknowns.scatter(cholesky.solve(-unknowns.gather(error)), step);
    u += step;
    for (int f = 0; f < domain.faceCount(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = domain.faces[std::size_t(f)][std::size_t(k)];
        const int b = domain.faces[std::size_t(f)][std::size_t((k + 1) % 3)];
        domain.sideLengths[std::size_t(f)][std::size_t(k)] =
            original[std::size_t(f)][std::size_t(k)] * std::exp(0.5 * (u[a] + u[b]));
      }
  }
  if (!(polish.finalError <= 1e-13))
    throw structure::SolverError(
        "spline domain: flattening the domain's metric left a "
        "curvature error of " +
        std::to_string(polish.finalError));
  return polish;
}

std::array<Eigen::Vector2d, 3> canonicalCorners(const SplineDomain& domain, int face) {
  const auto& l = domain.sideLengths[std::size_t(face)];
  // Side 0 joins corners 0 and 1, side 2 corners 2 and 0.
  const double x = (l[0] * l[0] + l[2] * l[2] - l[1] * l[1]) / (2.0 * l[0]);
  const double y = std::sqrt(std::max(0.0, l[2] * l[2] - x * x));
  return {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(l[0], 0.0), Eigen::Vector2d(x, y)};
}

Eigen::Vector3d frameBarycentric(const SplineDomain& domain, int face, const Eigen::Vector2d& x) {
  const auto corners = canonicalCorners(domain, face);
  const auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
    return u.x() * v.y() - u.y() * v.x();
  };
  // Corner 0 is the origin: lambda_j(x) = (cross(u, v) + cross(x, u - v)) / det, u and v the
  // other two corners.
  const double det = cross(corners[1], corners[2]);
  Eigen::Vector3d lambda;
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector2d& u = corners[std::size_t((j + 1) % 3)];
    const Eigen::Vector2d& v = corners[std::size_t((j + 2) % 3)];
    lambda[j] = (cross(u, v) + cross(x, u - v)) / det;
  }
  return lambda;
}

int HomeChart::find(int face) const {
  for (std::size_t k = 0; k < faces.size(); ++k)
    if (faces[k] == face) return int(k);
  return -1;
}

std::vector<int> HomeChart::findAll(int face) const {
  std::vector<int> found;
  for (std::size_t k = 0; k < faces.size(); ++k)
    if (faces[k] == face) found.push_back(int(k));
  return found;
}

std::vector<HomeChart> buildHomeCharts(const SplineDomain& domain) {
  validateDomain(domain);
  std::vector<HomeChart> charts(domain.faces.size());
  for (int home = 0; home < domain.faceCount(); ++home) {
    HomeChart& chart = charts[std::size_t(home)];
    place(domain, chart, home, RigidMotion{});
    for (int corner = 0; corner < 3; ++corner) {
      const int v = domain.faces[std::size_t(home)][std::size_t(corner)];
      if (domain.cone[std::size_t(v)]) {
        // No fan around a cone: only the faces across the two sides at it.
        for (int side : {corner, (corner + 2) % 3})
          place(domain, chart, domain.neighbour[std::size_t(home)][std::size_t(side)],
                glue(domain, home, RigidMotion{}, side,
                     domain.neighbour[std::size_t(home)][std::size_t(side)],
                     domain.neighbourSide[std::size_t(home)][std::size_t(side)]));
        continue;
      }
      // Turn around v across the side that ends at v, face by face, back to the home face.
      std::vector<std::pair<int, RigidMotion>> fan;
      int f = home, at = corner;
      RigidMotion placement;
      for (int steps = 0;; ++steps) {
        if (steps > 10000)
          throw InputError("spline domain: the fan around vertex " + std::to_string(v) +
                           " does not close");
        const int side = (at + 2) % 3;
        const int g = domain.neighbour[std::size_t(f)][std::size_t(side)];
        const int gs = domain.neighbourSide[std::size_t(f)][std::size_t(side)];
        placement = glue(domain, f, placement, side, g, gs);
        f = g;
        at = gs;
        if (f == home && at == corner) break;
        fan.emplace_back(f, placement);
      }
      // Around a flat vertex the fan closes up: the development comes back to the identity.
      const auto corners = canonicalCorners(domain, home);
      const auto& l = domain.sideLengths[std::size_t(home)];
      for (const auto& c : corners)
        if ((placement(c) - c).norm() > 1e-9 * (l[0] + l[1] + l[2]))
          throw InputError("spline domain: vertex " + std::to_string(v) +
                           " is not flat but is not marked as a cone");
      for (const auto& [g, motion] : fan) place(domain, chart, g, motion);
    }
  }
  return charts;
}

}  // namespace mspline::spline
