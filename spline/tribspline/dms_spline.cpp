#include "mspline/spline/tribspline/dms_spline.h"
#include "mspline/structure/core/constants.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <unordered_map>
#include <utility>

#include <Eigen/Geometry>

#include "mspline/structure/core/errors.h"

namespace mspline::spline {

using Eigen::Vector2d;
using structure::InputError;

namespace {

constexpr int kMaxDegree = 10;

double cross(const Vector2d& u, const Vector2d& v) {
  return u.x() * v.y() - u.y() * v.x();
}

bool finite(const Vector2d& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y());
}

double binomial(int n, int k) {
  double value = 1.0;
  for (int i = 1; i <= k; ++i) value = value * (n - k + i) / i;
  return value;
}

std::string pointText(const Vector2d& p) {
  std::ostringstream text;
  text.precision(17);
  text << "(" << p.x() << ", " << p.y() << ")";
  return text.str();
}

// Position of beta (|beta| = k) in its level: b0 descending, then b1 descending.
int levelIndex(const std::array<int, 3>& beta) {
  const int s = beta[1] + beta[2];
  return s * (s + 1) / 2 + beta[2];
}

// Every beta >= 0 with |beta| = k, in level order.
std::vector<std::array<int, 3>> levelBetas(int k) {
  std::vector<std::array<int, 3>> betas;
  for (int b0 = k; b0 >= 0; --b0)
    for (int b1 = k - b0; b1 >= 0; --b1) betas.push_back({b0, b1, k - b0 - b1});
  return betas;
}

// Checks what both the knot generator and the space need of the triangulation itself.
void checkTriangulation(const std::vector<Vector2d>& vertices,
                        const std::vector<std::array<int, 3>>& triangles) {
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (!finite(vertices[i]))
      throw InputError("DMS space: vertex " + std::to_string(i) +
                       " has a coordinate that is not finite");
  const int count = static_cast<int>(vertices.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& tri = triangles[t];
    for (int v : tri)
      if (v < 0 || v >= count)
        throw InputError("DMS space: triangle " + std::to_string(t) + " has vertex index " +
                         std::to_string(v) + " outside 0.." + std::to_string(count - 1));
    if (orientation(vertices[tri[0]], vertices[tri[1]], vertices[tri[2]]) <= 0)
      throw InputError("DMS space: triangle " + std::to_string(t) + " (vertices " +
                       std::to_string(tri[0]) + " " + std::to_string(tri[1]) + " " +
                       std::to_string(tri[2]) + ") is not counter-clockwise");
  }
}

// Counter-clockwise convex hull (Andrew's monotone chain), collinear points dropped.
std::vector<Vector2d> convexHull(std::vector<Vector2d> points) {
  std::sort(points.begin(), points.end(), [](const Vector2d& a, const Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  std::vector<Vector2d> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && orientation(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && orientation(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

// Whether the convex polygons a and b (counter-clockwise, at least 3 corners) come within tol of
// each other: no edge normal of either separates them by more than tol.
bool convexPolygonsMeet(const std::vector<Vector2d>& a, const std::vector<Vector2d>& b,
                        double tol) {
  const auto separates = [tol](const std::vector<Vector2d>& p, const std::vector<Vector2d>& q) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vector2d edge = p[(i + 1) % p.size()] - p[i];
      const Vector2d outward = Vector2d(edge.y(), -edge.x()).normalized();
      bool allOutside = true;
      for (const Vector2d& point : q)
        if (outward.dot(point - p[i]) <= tol) {
          allOutside = false;
          break;
        }
      if (allOutside) return true;
    }
    return false;
  };
  return !separates(a, b) && !separates(b, a);
}

}  // namespace

KnotClouds generateKnotClouds(const std::vector<Vector2d>& vertices,
                              const std::vector<std::array<int, 3>>& triangles, int degree,
                              const KnotCloudOptions& options) {
  if (degree < 1 || degree > kMaxDegree)
    throw InputError("DMS knot clouds: degree " + std::to_string(degree) + " is outside 1.." +
                     std::to_string(kMaxDegree));
  if (!(options.radiusFraction > 0.0 && options.radiusFraction <= 0.5))
    throw InputError("DMS knot clouds: radius fraction " + std::to_string(options.radiusFraction) +
                     " is outside (0, 0.5]");
  checkTriangulation(vertices, triangles);
  std::vector<double> radius(vertices.size(), std::numeric_limits<double>::infinity());
  for (const auto& tri : triangles) {
    const Vector2d& a = vertices[tri[0]];
    const Vector2d& b = vertices[tri[1]];
    const Vector2d& c = vertices[tri[2]];
    const double inradius =
        cross(b - a, c - a) / ((b - a).norm() + (c - b).norm() + (a - c).norm());
    for (int v : tri) radius[v] = std::min(radius[v], options.radiusFraction * inradius);
  }
  std::mt19937_64 random(options.seed);
  const auto uniform = [&random] { return static_cast<double>(random() >> 11) * 0x1.0p-53; };
  KnotClouds knots(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    knots[i].assign(degree + 1, vertices[i]);
    if (!std::isfinite(radius[i])) continue;  // no triangle: the cloud stays at the vertex
    for (int b = 1; b <= degree; ++b) {
      // Uniform in the disk: the radius goes as the square root of a uniform number.
      const double r = radius[i] * std::sqrt(uniform());
      const double angle = 2.0 * kPi * uniform();
      knots[i][b] = vertices[i] + r * Vector2d(std::cos(angle), std::sin(angle));
    }
  }
  return knots;
}

struct DmsSpace::Scratch {
  std::vector<double> nodes;
  std::vector<double> lowerGradient;
  std::vector<double> edgeValues;
  std::vector<signed char> edgeState;
  std::vector<double> zeros;
};

DmsSpace::DmsSpace(std::vector<Vector2d> vertices, std::vector<std::array<int, 3>> triangles,
                   int degree, const KnotCloudOptions& knotOptions, const DmsSpaceOptions& options)
    : DmsSpace(vertices, triangles, generateKnotClouds(vertices, triangles, degree, knotOptions),
               options) {}

DmsSpace::DmsSpace(std::vector<Vector2d> vertices, std::vector<std::array<int, 3>> triangles,
                   KnotClouds knots, const DmsSpaceOptions& options)
    : vertices_(std::move(vertices)), triangles_(std::move(triangles)), knots_(std::move(knots)) {
  if (vertices_.empty() || triangles_.empty())
    throw InputError("DMS space: the triangulation has no vertices or no triangles");
  checkTriangulation(vertices_, triangles_);
  if (knots_.size() != vertices_.size())
    throw InputError("DMS space: " + std::to_string(knots_.size()) + " knot clouds for " +
                     std::to_string(vertices_.size()) + " vertices");
  degree_ = static_cast<int>(knots_[0].size()) - 1;
  if (degree_ < 1 || degree_ > kMaxDegree)
    throw InputError("DMS space: knot cloud 0 has " + std::to_string(knots_[0].size()) +
                     " knots; the degree (knots - 1) must be in 1.." + std::to_string(kMaxDegree));
  for (std::size_t i = 0; i < knots_.size(); ++i) {
    if (static_cast<int>(knots_[i].size()) != degree_ + 1)
      throw InputError("DMS space: knot cloud " + std::to_string(i) + " has " +
                       std::to_string(knots_[i].size()) +
                       " knots, expected degree + 1 = " + std::to_string(degree_ + 1));
    for (const Vector2d& knot : knots_[i])
      if (!finite(knot))
        throw InputError("DMS space: knot cloud " + std::to_string(i) +
                         " has a coordinate that is not finite");
    if (knots_[i][0] != vertices_[i])
      throw InputError("DMS space: knot t_{" + std::to_string(i) +
                       ",0} = " + pointText(knots_[i][0]) + " is not vertex " + std::to_string(i) +
                       " = " + pointText(vertices_[i]));
  }
  perTriangle_ = (degree_ + 1) * (degree_ + 2) / 2;
  schemeNodes_ = (degree_ + 1) * (degree_ + 2) * (degree_ + 3) / 6;
  for (int k = 0; k <= degree_; ++k) levelStart_.push_back(k * (k + 1) * (k + 2) / 6);
  buildEdges();
  buildTriangleSchemes(options);
  buildHulls();
  buildLocator();
  buildNeighbourhoods();
}

void DmsSpace::buildEdges() {
  const int n = degree_;
  std::unordered_map<std::uint64_t, int> edgeOf;
  // Per edge: triangles using it from its lower to its higher vertex, and the other way.
  std::vector<std::array<int, 2>> users;
  triangleEdges_.resize(triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const auto& tri = triangles_[t];
    for (int j = 0; j < 3; ++j) {
      const int from = tri[(j + 1) % 3];
      const int to = tri[(j + 2) % 3];
      const int low = std::min(from, to);
      const int high = std::max(from, to);
      const std::uint64_t key = (std::uint64_t(low) << 32) | std::uint64_t(high);
      auto [it, inserted] = edgeOf.emplace(key, static_cast<int>(edgeVertices_.size()));
      if (inserted) {
        edgeVertices_.push_back({low, high});
        users.push_back({-1, -1});
      }
      int& user = users[it->second][from == low ? 0 : 1];
      if (user >= 0)
        throw InputError("DMS space: triangles " + std::to_string(user) + " and " +
                         std::to_string(t) + " both use edge " + std::to_string(from) + " -> " +
                         std::to_string(to) + " (overlapping or inconsistently oriented)");
      user = static_cast<int>(t);
      triangleEdges_[t][j] = it->second;
    }
  }
  // Knots t_{low,n}, t_{high,n}, t_{low,n-1}, ..., t_{low,0}, t_{high,0} (see edgeNode below).
  for (const auto& [low, high] : edgeVertices_) {
    std::vector<Vector2d> knots;
    for (int b = n; b >= 0; --b) {
      knots.push_back(knots_[low][b]);
      knots.push_back(knots_[high][b]);
    }
    edgeGraphs_.emplace_back(std::move(knots), vertices_[low]);
  }
}

void DmsSpace::buildTriangleSchemes(const DmsSpaceOptions& options) {
  const int n = degree_;
  // The edge set {t_{low,0..a}, t_{high,0..b}} in the knot order of buildEdges.
  const auto edgeNode = [n, this](int edge, int a, int b) {
    std::uint64_t mask = 0;
    for (int c = 0; c <= a; ++c) mask |= std::uint64_t(1) << (2 * (n - c));
    for (int c = 0; c <= b; ++c) mask |= std::uint64_t(1) << (2 * (n - c) + 1);
    return edgeGraphs_[edge].add(mask);
  };
  children_.resize(triangles_.size() * (schemeNodes_ - 1) * 3);
  ownChildren_.assign(schemeNodes_, 0);
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const auto& tri = triangles_[t];
    const Vector2d& origin = vertices_[tri[0]];
    const double area = cross(vertices_[tri[1]] - origin, vertices_[tri[2]] - origin) / 2;
    const auto corner = [&](const std::array<int, 3>& beta, int j) {
      return Vector2d(knots_[tri[j]][beta[j]] - origin);
    };
    const auto knotName = [&](const std::array<int, 3>& beta, int j) {
      return "t_{" + std::to_string(tri[j]) + "," + std::to_string(beta[j]) + "}";
    };
    // det W_beta^I, checked against the conditions at the top of dms_spline.h.
    const auto knotDet = [&](const std::array<int, 3>& beta) {
      const double det =
          cross(corner(beta, 1) - corner(beta, 0), corner(beta, 2) - corner(beta, 0));
      const bool ccw = orientation(knots_[tri[0]][beta[0]], knots_[tri[1]][beta[1]],
                                   knots_[tri[2]][beta[2]]) > 0;
      if (!ccw || det / 2 < options.minKnotTriangleRatio * area)
        throw InputError(
            "DMS space: knot triangle [" + knotName(beta, 0) + ", " + knotName(beta, 1) + ", " +
            knotName(beta, 2) + "] of triangle " + std::to_string(t) +
            (ccw ? " is nearly flat (area below minKnotTriangleRatio of the triangle's)"
                 : " is not counter-clockwise"));
      return det;
    };
    knotDet({0, 0, 0});
    for (int k = 1; k <= n; ++k) {
      for (const auto& beta : levelBetas(k)) {
        const double det = knotDet(beta);
        const double scale = det / ((k + 1) * (k + 2));
        const int node = levelStart_[k] + levelIndex(beta);
        for (int j = 0; j < 3; ++j) {
          Child& child = children_[((t * (schemeNodes_ - 1)) + node - 1) * 3 + j];
          double childScale = 0.0;
          std::array<int, 3> lower = beta;
          --lower[j];
          if (lower[j] >= 0) {
            child.source = 0;
            child.index = levelStart_[k - 1] + levelIndex(lower);
            childScale = knotDet(lower) / (k * (k + 1));
          } else {
            // t_{ij,0} removed: the knots of the edge opposite j, t_{i(j+1),0..b(j+1)} and
            // t_{i(j+2),0..b(j+2)}.
            const int edge = triangleEdges_[t][j];
            const int first = tri[(j + 1) % 3];
            const int a = beta[(j + 1) % 3];
            const int b = beta[(j + 2) % 3];
            const bool lowFirst = edgeVertices_[edge][0] == first;
            child.source = 1 + j;
            child.index = lowFirst ? edgeNode(edge, a, b) : edgeNode(edge, b, a);
            childScale = edgeGraphs_[edge].node(child.index).scale;
          }
          if (child.index == 0 && child.source != 0) {
            child.a = child.bx = child.by = 0.0;  // knots on one line: the zero spline
            continue;
          }
          // alpha_j = scale (k + 2) / (k childScale) lambda_j(x | W_beta^I), with
          // lambda_j(y) = (cross(u, v) + cross(y, u - v)) / det for the other two corners u, v.
          const double factor = scale * (k + 2) / (k * childScale * det);
          const Vector2d u = corner(beta, (j + 1) % 3);
          const Vector2d v = corner(beta, (j + 2) % 3);
          child.a = factor * cross(u, v);
          child.bx = factor * (u - v).y();
          child.by = -factor * (u - v).x();
        }
        // The triangle's own children first: without an edge set near x the others are zero.
        Child* first = &children_[((t * (schemeNodes_ - 1)) + node - 1) * 3];
        std::stable_partition(first, first + 3, [](const Child& c) { return c.source == 0; });
        if (t == 0)
          ownChildren_[node] = static_cast<int>((beta[0] > 0) + (beta[1] > 0) + (beta[2] > 0));
      }
    }
  }
  // The graphs are complete: every edge set of the schemes is in.
  for (auto& graph : edgeGraphs_) {
    graph.shrink();
    maxEdgeNodes_ = std::max(maxEdgeNodes_, graph.size());
  }
}

DmsSpace::Hull DmsSpace::makeHull(std::vector<Vector2d> points) {
  Hull hull;
  hull.minX = hull.minY = std::numeric_limits<double>::infinity();
  hull.maxX = hull.maxY = -std::numeric_limits<double>::infinity();
  for (const Vector2d& p : points) {
    hull.minX = std::min(hull.minX, p.x());
    hull.maxX = std::max(hull.maxX, p.x());
    hull.minY = std::min(hull.minY, p.y());
    hull.maxY = std::max(hull.maxY, p.y());
  }
  // The support is closed and a value at its boundary may be a limit from inside, so the test
  // is widened by far more than rounding.
  const double tol = 1e-9 * std::max(hull.maxX - hull.minX + hull.maxY - hull.minY, 1e-300);
  hull.minX -= tol;
  hull.minY -= tol;
  hull.maxX += tol;
  hull.maxY += tol;
  hull.firstPlane = hull.endPlane = static_cast<int>(planes_.size());
  const std::vector<Vector2d> corners = convexHull(std::move(points));
  if (corners.size() >= 3) {
    for (std::size_t i = 0; i < corners.size(); ++i) {
      const Vector2d edge = corners[(i + 1) % corners.size()] - corners[i];
      const Vector2d outward = Vector2d(edge.y(), -edge.x()).normalized();
      planes_.push_back({outward.x(), outward.y(), outward.dot(corners[i]) + tol});
    }
  }
  hull.endPlane = static_cast<int>(planes_.size());
  return hull;
}

inline bool DmsSpace::inHull(const Hull& hull, double x, double y) const {
  if (x < hull.minX || x > hull.maxX || y < hull.minY || y > hull.maxY) return false;
  for (int p = hull.firstPlane; p < hull.endPlane; ++p)
    if (planes_[p][0] * x + planes_[p][1] * y > planes_[p][2]) return false;
  return true;
}

void DmsSpace::buildHulls() {
  for (const auto& [low, high] : edgeVertices_) {
    std::vector<Vector2d> points = knots_[low];
    points.insert(points.end(), knots_[high].begin(), knots_[high].end());
    edgeHulls_.push_back(makeHull(std::move(points)));
  }
}

void DmsSpace::buildLocator() {
  Vector2d low = Vector2d::Constant(std::numeric_limits<double>::infinity());
  Vector2d high = -low;
  for (const auto& tri : triangles_)
    for (int v : tri) {
      low = low.cwiseMin(vertices_[v]);
      high = high.cwiseMax(vertices_[v]);
    }
  const Vector2d size = (high - low).cwiseMax(1e-300);
  // About one triangle per cell.
  gridCell_ = std::max(std::sqrt(size.x() * size.y() / triangles_.size()),
                       std::max(size.x(), size.y()) / 4096.0);
  gridLow_ = low;
  gridColumns_ = std::max(1, static_cast<int>(std::ceil(size.x() / gridCell_)));
  gridRows_ = std::max(1, static_cast<int>(std::ceil(size.y() / gridCell_)));
  const auto column = [this](double x) {
    return std::clamp(static_cast<int>(std::floor((x - gridLow_.x()) / gridCell_)), 0,
                      gridColumns_ - 1);
  };
  const auto row = [this](double y) {
    return std::clamp(static_cast<int>(std::floor((y - gridLow_.y()) / gridCell_)), 0,
                      gridRows_ - 1);
  };
  std::vector<std::vector<int>> cells(static_cast<std::size_t>(gridColumns_) * gridRows_);
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    Vector2d a = vertices_[triangles_[t][0]], b = a;
    for (int v : triangles_[t]) {
      a = a.cwiseMin(vertices_[v]);
      b = b.cwiseMax(vertices_[v]);
    }
    for (int r = row(a.y()); r <= row(b.y()); ++r)
      for (int c = column(a.x()); c <= column(b.x()); ++c)
        cells[static_cast<std::size_t>(r) * gridColumns_ + c].push_back(static_cast<int>(t));
  }
  gridStart_.assign(1, 0);
  for (const auto& cell : cells) {
    gridTriangles_.insert(gridTriangles_.end(), cell.begin(), cell.end());
    gridStart_.push_back(static_cast<int>(gridTriangles_.size()));
  }
}

int DmsSpace::locate(const Vector2d& x) const {
  const Vector2d high = gridLow_ + gridCell_ * Vector2d(gridColumns_, gridRows_);
  if (!finite(x) || x.x() < gridLow_.x() || x.y() < gridLow_.y() || x.x() > high.x() ||
      x.y() > high.y())
    return -1;
  const int c = std::min(static_cast<int>((x.x() - gridLow_.x()) / gridCell_), gridColumns_ - 1);
  const int r = std::min(static_cast<int>((x.y() - gridLow_.y()) / gridCell_), gridRows_ - 1);
  const int cell = r * gridColumns_ + c;
  int closure = -1;
  for (int k = gridStart_[cell]; k < gridStart_[cell + 1]; ++k) {
    const auto& tri = triangles_[gridTriangles_[k]];
    const Vector2d& a = vertices_[tri[0]];
    const Vector2d& b = vertices_[tri[1]];
    const Vector2d& d = vertices_[tri[2]];
    if (perturbedSide(a, b, x) > 0 && perturbedSide(b, d, x) > 0 && perturbedSide(d, a, x) > 0)
      return gridTriangles_[k];
    if (closure < 0 && orientation(a, b, x) >= 0 && orientation(b, d, x) >= 0 &&
        orientation(d, a, x) >= 0)
      closure = gridTriangles_[k];
  }
  return closure;
}

void DmsSpace::buildNeighbourhoods() {
  const int count = numTriangles();
  std::vector<std::vector<Vector2d>> supports(count);
  for (int t = 0; t < count; ++t) {
    std::vector<Vector2d> points;
    for (int v : triangles_[t]) points.insert(points.end(), knots_[v].begin(), knots_[v].end());
    supports[t] = convexHull(std::move(points));
  }
  // Clamped before the conversion: a knot far outside the grid (a model file may hold any
  // finite knot) would not fit in an int.
  const auto cellRange = [this](double low, double high, double origin, int cells) {
    const auto cell = [&](double x) {
      return static_cast<int>(std::clamp(std::floor((x - origin) / gridCell_), 0.0, cells - 1.0));
    };
    return std::array<int, 2>{cell(low), cell(high)};
  };
  std::vector<std::vector<int>> influencing(count);
  std::vector<int> seen(count, -1);
  for (int source = 0; source < count; ++source) {
    const std::vector<Vector2d>& support = supports[source];
    Vector2d low = support[0], high = support[0];
    for (const Vector2d& p : support) {
      low = low.cwiseMin(p);
      high = high.cwiseMax(p);
    }
    const double tol = 1e-9 * (high - low).sum();
    const auto columns = cellRange(low.x() - tol, high.x() + tol, gridLow_.x(), gridColumns_);
    const auto rows = cellRange(low.y() - tol, high.y() + tol, gridLow_.y(), gridRows_);
    for (int r = rows[0]; r <= rows[1]; ++r)
      for (int c = columns[0]; c <= columns[1]; ++c) {
        const int cell = r * gridColumns_ + c;
        for (int k = gridStart_[cell]; k < gridStart_[cell + 1]; ++k) {
          const int target = gridTriangles_[k];
          if (seen[target] == source) continue;
          seen[target] = source;
          const std::vector<Vector2d> corners = {vertices_[triangles_[target][0]],
                                                 vertices_[triangles_[target][1]],
                                                 vertices_[triangles_[target][2]]};
          if (target == source || convexPolygonsMeet(support, corners, tol))
            influencing[target].push_back(source);
        }
      }
  }

  neighbourStart_.assign(1, 0);
  edgeStart_.assign(1, 0);
  std::vector<int> slotOf(edgeVertices_.size(), -1);
  for (int target = 0; target < count; ++target) {
    // T's barycentric coordinates, lambda_j(y) = (cross(u, v) + cross(y, u - v)) / det with u, v
    // the other corners relative to the first.
    const auto& tri = triangles_[target];
    const Vector2d& origin = vertices_[tri[0]];
    const std::array<Vector2d, 3> corner = {Vector2d::Zero(), Vector2d(vertices_[tri[1]] - origin),
                                            Vector2d(vertices_[tri[2]] - origin)};
    const double det = cross(corner[1], corner[2]);
    std::array<double, 9> frame{};
    for (int j = 0; j < 3; ++j) {
      const Vector2d& u = corner[(j + 1) % 3];
      const Vector2d& v = corner[(j + 2) % 3];
      frame[3 * j] = cross(u, v) / det;
      frame[3 * j + 1] = (u - v).y() / det;
      frame[3 * j + 2] = -(u - v).x() / det;
    }
    frames_.push_back(frame);
    // Upper bounds of the coordinates over a point set, widened far beyond rounding.
    const auto bounds = [&](const std::vector<Vector2d>& points) {
      std::array<double, 3> upper;
      upper.fill(-std::numeric_limits<double>::infinity());
      for (const Vector2d& p : points)
        for (int j = 0; j < 3; ++j)
          upper[j] = std::max(upper[j], frame[3 * j] + frame[3 * j + 1] * (p - origin).x() +
                                            frame[3 * j + 2] * (p - origin).y());
      for (double& u : upper) u += 1e-9;
      return upper;
    };

    auto& list = influencing[target];
    std::sort(list.begin(), list.end());
    std::rotate(list.begin(), std::find(list.begin(), list.end(), target),
                std::find(list.begin(), list.end(), target) + 1);
    const int firstEdge = static_cast<int>(edgeList_.size());
    for (int source : list) {
      std::array<int, 3> slots{};
      for (int j = 0; j < 3; ++j) {
        const int edge = triangleEdges_[source][j];
        if (slotOf[edge] < 0) {
          slotOf[edge] = static_cast<int>(edgeList_.size()) - firstEdge;
          edgeList_.push_back(edge);
          std::vector<Vector2d> knots = knots_[edgeVertices_[edge][0]];
          knots.insert(knots.end(), knots_[edgeVertices_[edge][1]].begin(),
                       knots_[edgeVertices_[edge][1]].end());
          edgeBounds_.push_back(bounds(knots));
        }
        slots[j] = slotOf[edge];
      }
      neighbours_.push_back(source);
      neighbourEdgeSlots_.push_back(slots);
      neighbourBounds_.push_back(bounds(supports[source]));
    }
    for (int k = firstEdge; k < static_cast<int>(edgeList_.size()); ++k) slotOf[edgeList_[k]] = -1;
    maxEdgeSlots_ = std::max(maxEdgeSlots_, static_cast<int>(edgeList_.size()) - firstEdge);
    neighbourStart_.push_back(static_cast<int>(neighbours_.size()));
    edgeStart_.push_back(static_cast<int>(edgeList_.size()));
  }
}

int DmsSpace::basisIndex(int triangle, const std::array<int, 3>& beta) const {
  if (triangle < 0 || triangle >= numTriangles() || beta[0] < 0 || beta[1] < 0 || beta[2] < 0 ||
      beta[0] + beta[1] + beta[2] != degree_)
    throw InputError("DMS space: no basis function for triangle " + std::to_string(triangle) +
                     " and beta (" + std::to_string(beta[0]) + ", " + std::to_string(beta[1]) +
                     ", " + std::to_string(beta[2]) + ")");
  return triangle * perTriangle_ + levelIndex(beta);
}

BasisId DmsSpace::basisId(int index) const {
  if (index < 0 || index >= numBasis())
    throw InputError("DMS space: basis index " + std::to_string(index) + " is outside 0.." +
                     std::to_string(numBasis() - 1));
  BasisId id;
  id.triangle = index / perTriangle_;
  id.beta = levelBetas(degree_)[index % perTriangle_];
  return id;
}

std::vector<Vector2d> DmsSpace::knotSet(int index) const {
  const BasisId id = basisId(index);
  std::vector<Vector2d> knots;
  for (int j = 0; j < 3; ++j)
    for (int b = 0; b <= id.beta[j]; ++b) knots.push_back(knots_[triangles_[id.triangle][j]][b]);
  return knots;
}

double DmsSpace::normalization(int index) const {
  const BasisId id = basisId(index);
  const auto& tri = triangles_[id.triangle];
  const Vector2d& p = knots_[tri[0]][id.beta[0]];
  const Vector2d& q = knots_[tri[1]][id.beta[1]];
  const Vector2d& r = knots_[tri[2]][id.beta[2]];
  return std::abs(cross(q - p, r - p)) / ((degree_ + 1) * (degree_ + 2));
}

std::vector<Vector2d> DmsSpace::blossomArguments(int index) const {
  const BasisId id = basisId(index);
  std::vector<Vector2d> arguments;
  for (int j = 0; j < 3; ++j)
    for (int b = 0; b < id.beta[j]; ++b) arguments.push_back(knots_[triangles_[id.triangle][j]][b]);
  return arguments;
}

std::vector<int> DmsSpace::influencingTriangles(int triangle) const {
  if (triangle < 0 || triangle >= numTriangles())
    throw InputError("DMS space: triangle " + std::to_string(triangle) + " is outside 0.." +
                     std::to_string(numTriangles() - 1));
  return {neighbours_.begin() + neighbourStart_[triangle],
          neighbours_.begin() + neighbourStart_[triangle + 1]};
}

template <int Derivatives, class Visitor>
void DmsSpace::visitBasis(int triangle, const Vector2d& x, Scratch& scratch,
                          Visitor&& visit) const {
  double* nodes = scratch.nodes.data();
  signed char* state = scratch.edgeState.data();
  const int edgeBegin = edgeStart_[triangle];
  std::fill(state, state + (edgeStart_[triangle + 1] - edgeBegin), 0);
  // x in T's barycentric coordinates screens the supports.
  const std::array<double, 9>& frame = frames_[triangle];
  const Vector2d& first = vertices_[triangles_[triangle][0]];
  const double fx = x.x() - first.x();
  const double fy = x.y() - first.y();
  const std::array<double, 3> lambda = {frame[0] + frame[1] * fx + frame[2] * fy,
                                        frame[3] + frame[4] * fx + frame[5] * fy,
                                        frame[6] + frame[7] * fx + frame[8] * fy};
  const auto within = [&lambda](const std::array<double, 3>& upper) {
    return lambda[0] <= upper[0] && lambda[1] <= upper[1] && lambda[2] <= upper[2];
  };
  // Clearly inside T (beyond any rounding of lambda): no other triangle holds x.
  const bool interior = lambda[0] > 1e-9 && lambda[1] > 1e-9 && lambda[2] > 1e-9;
  for (int c = neighbourStart_[triangle]; c < neighbourStart_[triangle + 1]; ++c) {
    const int source = neighbours_[c];
    if (source != triangle && !within(neighbourBounds_[c])) continue;
    // The edge sets, once per edge and point, where the two clouds' hull holds x.
    const double* from[4] = {nodes, nullptr, nullptr, nullptr};
    bool anyEdge = false;
    for (int j = 0; j < 3; ++j) {
      const int slot = neighbourEdgeSlots_[c][j];
      double* values = scratch.edgeValues.data() + static_cast<std::size_t>(slot) * maxEdgeNodes_;
      if (state[slot] == 0) {
        const int edge = edgeList_[edgeBegin + slot];
        state[slot] = 1;
        if (within(edgeBounds_[edgeBegin + slot]) && inHull(edgeHulls_[edge], x.x(), x.y())) {
          edgeGraphs_[edge].values(x, values);
          state[slot] = 2;
        }
      }
      from[1 + j] = state[slot] == 2 ? values : scratch.zeros.data();
      anyEdge = anyEdge || state[slot] == 2;
    }
    const auto& tri = triangles_[source];
    const Vector2d& origin = vertices_[tri[0]];
    const bool inside = interior ? source == triangle
                                 : perturbedSide(origin, vertices_[tri[1]], x) > 0 &&
                                       perturbedSide(vertices_[tri[1]], vertices_[tri[2]], x) > 0 &&
                                       perturbedSide(vertices_[tri[2]], origin, x) > 0;
    if (!inside && !anyEdge) continue;  // every node is zero
    visitScheme<Derivatives>(source, x, inside, from, anyEdge, scratch, visit);
  }
}

template <int Derivatives, class Visitor>
void DmsSpace::visitScheme(int source, const Vector2d& x, bool inside, const double* const* from,
                           bool anyEdge, Scratch& scratch, Visitor&& visit) const {
  const int n = degree_;
  const int top = levelStart_[n];
  const int lower = levelStart_[n - 1];
  double* nodes = scratch.nodes.data();
  const auto& tri = triangles_[source];
  const Vector2d& origin = vertices_[tri[0]];
  nodes[0] = inside ? 1.0 : 0.0;
  const double dx = x.x() - origin.x();
  const double dy = x.y() - origin.y();
  // Node k >= 1's coefficients start at children[3 (k - 1)].
  const Child* children =
      children_.data() + static_cast<std::size_t>(source) * (schemeNodes_ - 1) * 3;
  const int* own = ownChildren_.data();
  for (int node = 1; node < top; ++node) {
    const Child* ch = children + (node - 1) * 3;
    double v = 0.0;
    for (int j = 0, used = anyEdge ? 3 : own[node]; j < used; ++j)
      v += (ch[j].a + ch[j].bx * dx + ch[j].by * dy) * from[ch[j].source][ch[j].index];
    nodes[node] = v;
  }
  if constexpr (Derivatives >= 2) {
    // Gradients of level n - 1 (zero at level 0).
    for (int node = lower; node < top; ++node) {
      double gx = 0.0, gy = 0.0;
      if (node > 0) {
        const Child* ch = children + (node - 1) * 3;
        for (int j = 0; j < 3; ++j) {
          const double w = from[ch[j].source][ch[j].index];
          gx += ch[j].bx * w;
          gy += ch[j].by * w;
        }
      }
      scratch.lowerGradient[2 * (node - lower)] = (n - 1) * gx;
      scratch.lowerGradient[2 * (node - lower) + 1] = (n - 1) * gy;
    }
  }
  const int firstIndex = source * perTriangle_ - top;
  for (int node = top; node < schemeNodes_; ++node) {
    const Child* ch = children + (node - 1) * 3;
    double v = 0.0, gx = 0.0, gy = 0.0, hxx = 0.0, hxy = 0.0, hyy = 0.0;
    for (int j = 0, used = anyEdge ? 3 : own[node]; j < used; ++j) {
      const double w = from[ch[j].source][ch[j].index];
      v += (ch[j].a + ch[j].bx * dx + ch[j].by * dy) * w;
      if constexpr (Derivatives >= 1) {
        gx += ch[j].bx * w;
        gy += ch[j].by * w;
      }
      if constexpr (Derivatives >= 2) {
        double cx = 0.0, cy = 0.0;
        if (ch[j].source == 0) {
          cx = scratch.lowerGradient[2 * (ch[j].index - lower)];
          cy = scratch.lowerGradient[2 * (ch[j].index - lower) + 1];
        } else if (from[ch[j].source] != scratch.zeros.data()) {
          const Vector2d g = edgeGraphs_[triangleEdges_[source][ch[j].source - 1]].gradient(
              ch[j].index, from[ch[j].source]);
          cx = g.x();
          cy = g.y();
        }
        hxx += ch[j].bx * cx;
        hxy += (ch[j].bx * cy + ch[j].by * cx) / 2;
        hyy += ch[j].by * cy;
      }
    }
    visit(firstIndex + node, v, n * gx, n * gy, n * hxx, n * hxy, n * hyy);
  }
}

inline void DmsSpace::checkArguments(int derivatives, int triangle) const {
  if (derivatives < 0 || derivatives > 2)
    throw InputError("DMS space: derivatives must be 0, 1 or 2, got " +
                     std::to_string(derivatives));
  if (triangle < 0 || triangle >= numTriangles())
    throw InputError("DMS space: triangle " + std::to_string(triangle) + " is outside 0.." +
                     std::to_string(numTriangles() - 1));
}

DmsSpace::Scratch& DmsSpace::scratch() const {
  // Per thread, grown to the largest space evaluated on it: no allocation per point.
  static thread_local Scratch scratch;
  const auto grow = [](auto& vector, std::size_t size) {
    if (vector.size() < size) vector.resize(size);
  };
  grow(scratch.nodes, schemeNodes_);
  grow(scratch.lowerGradient, 2 * perTriangle_);
  grow(scratch.edgeValues, static_cast<std::size_t>(maxEdgeSlots_) * maxEdgeNodes_);
  grow(scratch.edgeState, maxEdgeSlots_);
  grow(scratch.zeros, maxEdgeNodes_);
  return scratch;
}

template <class Visitor>
void DmsSpace::dispatch(int derivatives, int triangle, const Vector2d& x, Visitor&& visit) const {
  checkArguments(derivatives, triangle);
  Scratch& buffers = scratch();
  if (derivatives == 0)
    visitBasis<0>(triangle, x, buffers, visit);
  else if (derivatives == 1)
    visitBasis<1>(triangle, x, buffers, visit);
  else
    visitBasis<2>(triangle, x, buffers, visit);
}

inline std::array<double, 3> DmsSpace::barycentric(int triangle, const Vector2d& x) const {
  const std::array<double, 9>& frame = frames_[triangle];
  const Vector2d& first = vertices_[triangles_[triangle][0]];
  const double fx = x.x() - first.x();
  const double fy = x.y() - first.y();
  return {frame[0] + frame[1] * fx + frame[2] * fy, frame[3] + frame[4] * fx + frame[5] * fy,
          frame[6] + frame[7] * fx + frame[8] * fy};
}

inline bool DmsSpace::inEdgeHull(int triangle, int j, const std::array<double, 3>& lambda,
                                 const Vector2d& x) const {
  // Screened by T's coordinates first (T is the first of its own influencing triangles).
  const auto& upper =
      edgeBounds_[edgeStart_[triangle] + neighbourEdgeSlots_[neighbourStart_[triangle]][j]];
  return lambda[0] <= upper[0] && lambda[1] <= upper[1] && lambda[2] <= upper[2] &&
         inHull(edgeHulls_[triangleEdges_[triangle][j]], x.x(), x.y());
}

BivariatePolynomial DmsSpace::trianglePolynomials(int triangle) const {
  checkArguments(0, triangle);
  const int n = degree_;
  const int monomials = BivariatePolynomial::monomialCount(n);
  // The scheme's recurrence on polynomials: nodes[0] = 1, every other node the sum over its own
  // children of (a + bx x + by y) times the child (the edge sets vanish here).
  std::vector<double> nodes(static_cast<std::size_t>(schemeNodes_) * monomials, 0.0);
  nodes[0] = 1.0;
  const Child* children =
      children_.data() + static_cast<std::size_t>(triangle) * (schemeNodes_ - 1) * 3;
  for (int node = 1; node < schemeNodes_; ++node) {
    const Child* ch = children + (node - 1) * 3;
    double* to = nodes.data() + static_cast<std::size_t>(node) * monomials;
    for (int j = 0; j < ownChildren_[node]; ++j) {
      const double* child = nodes.data() + static_cast<std::size_t>(ch[j].index) * monomials;
      for (int a = 0; a < n; ++a)
        for (int b = 0; a + b < n; ++b) {
          const double c = child[BivariatePolynomial::monomialIndex(a, b)];
          to[BivariatePolynomial::monomialIndex(a, b)] += ch[j].a * c;
          to[BivariatePolynomial::monomialIndex(a + 1, b)] += ch[j].bx * c;
          to[BivariatePolynomial::monomialIndex(a, b + 1)] += ch[j].by * c;
        }
    }
  }
  BivariatePolynomial polynomial;
  polynomial.degree = n;
  polynomial.coefficients.resize(monomials, perTriangle_);
  for (int k = 0; k < perTriangle_; ++k)
    for (int m = 0; m < monomials; ++m)
      polynomial.coefficients(m, k) =
          nodes[static_cast<std::size_t>(levelStart_[n] + k) * monomials + m];
  return polynomial;
}

bool DmsSpace::triangleBasisAt(int triangle, const Vector2d& x, TriangleBasis& out,
                               int derivatives) const {
  checkArguments(derivatives, triangle);
  const auto& tri = triangles_[triangle];
  const std::array<double, 3> lambda = barycentric(triangle, x);
  // Inside the half-open triangle: the coordinates decide where they are clearly positive or
  // negative (beyond any rounding), the exact predicates elsewhere.
  bool inside = false;
  if (lambda[0] > 1e-9 && lambda[1] > 1e-9 && lambda[2] > 1e-9)
    inside = true;
  else if (lambda[0] >= -1e-9 && lambda[1] >= -1e-9 && lambda[2] >= -1e-9)
    inside = perturbedSide(vertices_[tri[0]], vertices_[tri[1]], x) > 0 &&
             perturbedSide(vertices_[tri[1]], vertices_[tri[2]], x) > 0 &&
             perturbedSide(vertices_[tri[2]], vertices_[tri[0]], x) > 0;
  // The edge sets where the two clouds' hull holds x.
  const bool edges[3] = {inEdgeHull(triangle, 0, lambda, x), inEdgeHull(triangle, 1, lambda, x),
                         inEdgeHull(triangle, 2, lambda, x)};
  const bool anyEdge = edges[0] || edges[1] || edges[2];
  if (!inside && !anyEdge) return false;
  Scratch& buffers = scratch();
  const double* from[4] = {buffers.nodes.data(), buffers.zeros.data(), buffers.zeros.data(),
                           buffers.zeros.data()};
  for (int j = 0; j < 3; ++j)
    if (edges[j]) {
      double* values = buffers.edgeValues.data() + static_cast<std::size_t>(j) * maxEdgeNodes_;
      edgeGraphs_[triangleEdges_[triangle][j]].values(x, values);
      from[1 + j] = values;
    }
  out.value.resize(perTriangle_);
  out.gradient.resize(derivatives >= 1 ? 2 * perTriangle_ : 0);
  out.hessian.resize(derivatives >= 2 ? 3 * perTriangle_ : 0);
  const int first = triangle * perTriangle_;
  const auto write = [&](int index, double v, double gx, double gy, double hxx, double hxy,
                         double hyy) {
    const int k = index - first;
    out.value[k] = v;
    if (derivatives >= 1) {
      out.gradient[2 * k] = gx;
      out.gradient[2 * k + 1] = gy;
    }
    if (derivatives >= 2) {
      out.hessian[3 * k] = hxx;
      out.hessian[3 * k + 1] = hxy;
      out.hessian[3 * k + 2] = hyy;
    }
  };
  if (derivatives == 0)
    visitScheme<0>(triangle, x, inside, from, anyEdge, buffers, write);
  else if (derivatives == 1)
    visitScheme<1>(triangle, x, inside, from, anyEdge, buffers, write);
  else
    visitScheme<2>(triangle, x, inside, from, anyEdge, buffers, write);
  return true;
}

void DmsSpace::basisAt(int triangle, const Vector2d& x, BasisValues& out, int derivatives) const {
  out.index.clear();
  out.value.clear();
  out.gradient.clear();
  out.hessian.clear();
  dispatch(derivatives, triangle, x,
           [&](int index, double v, double gx, double gy, double hxx, double hxy, double hyy) {
             if (v == 0.0 && gx == 0.0 && gy == 0.0 && hxx == 0.0 && hxy == 0.0 && hyy == 0.0)
               return;
             out.index.push_back(index);
             out.value.push_back(v);
             if (derivatives >= 1) out.gradient.emplace_back(gx, gy);
             if (derivatives >= 2)
               out.hessian.push_back((Eigen::Matrix2d() << hxx, hxy, hxy, hyy).finished());
           });
}

namespace {

// Sums of control rows weighted by value and derivatives: position, du, dv, duu, duv, dvv.
struct Accumulator {
  explicit Accumulator(int dimensions)
      : dims(dimensions), sums(6 * static_cast<std::size_t>(dimensions), 0.0) {}
  void reset() { std::fill(sums.begin(), sums.end(), 0.0); }
  double* part(int k) { return sums.data() + static_cast<std::size_t>(k) * dims; }
  int dims;
  std::vector<double> sums;
};

Eigen::Vector3d unitNormal(const double* du, const double* dv) {
  const Eigen::Vector3d normal =
      Eigen::Vector3d(du[0], du[1], du[2]).cross(Eigen::Vector3d(dv[0], dv[1], dv[2]));
  const double length = normal.norm();
  return length > 0.0 ? Eigen::Vector3d(normal / length) : Eigen::Vector3d::Zero();
}

}  // namespace

SplinePoint DmsSpace::evaluate(const Eigen::MatrixXd& control, int triangle, const Vector2d& x,
                               int derivatives) const {
  if (control.rows() != numBasis())
    throw InputError("DMS space: " + std::to_string(control.rows()) + " control points for " +
                     std::to_string(numBasis()) + " basis functions");
  if (triangle < 0) {
    triangle = locate(x);
    if (triangle < 0)
      throw InputError("DMS space: point " + pointText(x) + " lies outside the triangulation");
  }
  const int dims = static_cast<int>(control.cols());
  Accumulator sum(dims);
  dispatch(derivatives, triangle, x,
           [&](int index, double v, double gx, double gy, double hxx, double hxy, double hyy) {
             const std::array<double, 6> weight = {v, gx, gy, hxx, hxy, hyy};
             for (int k = 0; k <= (derivatives == 0 ? 0 : derivatives == 1 ? 2 : 5); ++k)
               for (int c = 0; c < dims; ++c) sum.part(k)[c] += weight[k] * control(index, c);
           });
  SplinePoint point;
  const auto vector = [&](int k) { return Eigen::Map<const Eigen::VectorXd>(sum.part(k), dims); };
  point.position = vector(0);
  if (derivatives >= 1) {
    point.du = vector(1);
    point.dv = vector(2);
    if (dims == 3) point.normal = unitNormal(sum.part(1), sum.part(2));
  }
  if (derivatives >= 2) {
    point.duu = vector(3);
    point.duv = vector(4);
    point.dvv = vector(5);
  }
  return point;
}

SplineSamples DmsSpace::evaluateBatch(const Eigen::MatrixXd& control,
                                      const std::vector<int>& triangles,
                                      const Eigen::MatrixX2d& points, int derivatives) const {
  if (control.rows() != numBasis())
    throw InputError("DMS space: " + std::to_string(control.rows()) + " control points for " +
                     std::to_string(numBasis()) + " basis functions");
  if (!triangles.empty() && static_cast<Eigen::Index>(triangles.size()) != points.rows())
    throw InputError("DMS space: " + std::to_string(triangles.size()) + " triangles for " +
                     std::to_string(points.rows()) + " points");
  if (derivatives < 0 || derivatives > 2)
    throw InputError("DMS space: derivatives must be 0, 1 or 2, got " +
                     std::to_string(derivatives));
  const int dims = static_cast<int>(control.cols());
  const Eigen::Index count = points.rows();
  // Control points row by row, so that a basis function's coordinates are adjacent.
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows = control;
  SplineSamples samples;
  samples.position.resize(count, dims);
  if (derivatives >= 1) {
    samples.du.resize(count, dims);
    samples.dv.resize(count, dims);
    if (dims == 3) samples.normal.resize(count, 3);
  }
  if (derivatives >= 2) {
    samples.duu.resize(count, dims);
    samples.duv.resize(count, dims);
    samples.dvv.resize(count, dims);
  }
  // Points grouped by triangle (a counting sort): consecutive points then share the
  // triangles' coefficients in cache, which in random order cost more than the arithmetic.
  std::vector<int> located(count);
  std::vector<int> start(numTriangles() + 1, 0);
  for (Eigen::Index k = 0; k < count; ++k) {
    int triangle = triangles.empty() ? -1 : triangles[k];
    if (triangle >= numTriangles())
      throw InputError("DMS space: point " + std::to_string(k) + " has triangle " +
                       std::to_string(triangle) + " outside 0.." +
                       std::to_string(numTriangles() - 1));
    if (triangle < 0) {
      triangle = locate(points.row(k).transpose());
      if (triangle < 0)
        throw InputError("DMS space: point " + std::to_string(k) + " " +
                         pointText(points.row(k).transpose()) + " lies outside the triangulation");
    }
    located[k] = triangle;
    ++start[triangle + 1];
  }
  for (int t = 0; t < numTriangles(); ++t) start[t + 1] += start[t];
  std::vector<int> order(count);
  for (Eigen::Index k = 0; k < count; ++k) order[start[located[k]]++] = static_cast<int>(k);

  // In chunks: gather the chunk's points, evaluate them into a contiguous buffer, scatter the
  // results; the gathers and scatters, free of dependencies, overlap their cache misses.
  const int parts = derivatives == 0 ? 1 : derivatives == 1 ? 3 : 6;
  const int width = parts * dims;
  constexpr Eigen::Index kChunk = 1024;
  std::vector<Vector2d> chunkPoints(std::min(count, kChunk));
  std::vector<double> results(chunkPoints.size() * width);
  Eigen::MatrixXd* outputs[6] = {&samples.position, &samples.du,  &samples.dv,
                                 &samples.duu,      &samples.duv, &samples.dvv};
  for (Eigen::Index begin = 0; begin < count; begin += kChunk) {
    const Eigen::Index end = std::min(count, begin + kChunk);
    for (Eigen::Index i = begin; i < end; ++i)
      chunkPoints[i - begin] = points.row(order[i]).transpose();
    for (Eigen::Index i = begin; i < end; ++i) {
      double* sum = results.data() + (i - begin) * width;
      std::fill(sum, sum + width, 0.0);
      dispatch(derivatives, located[order[i]], chunkPoints[i - begin],
               [&](int index, double v, double gx, double gy, double hxx, double hxy, double hyy) {
                 const double* c = rows.data() + static_cast<std::size_t>(index) * dims;
                 const std::array<double, 6> weight = {v, gx, gy, hxx, hxy, hyy};
                 for (int p = 0; p < parts; ++p)
                   for (int d = 0; d < dims; ++d) sum[p * dims + d] += weight[p] * c[d];
               });
    }
    for (Eigen::Index i = begin; i < end; ++i) {
      const int k = order[i];
      const double* sum = results.data() + (i - begin) * width;
      for (int p = 0; p < parts; ++p)
        for (int d = 0; d < dims; ++d) (*outputs[p])(k, d) = sum[p * dims + d];
      if (derivatives >= 1 && dims == 3)
        samples.normal.row(k) = unitNormal(sum + dims, sum + 2 * dims).transpose();
    }
  }
  return samples;
}

Eigen::VectorXd BivariatePolynomial::operator()(const Vector2d& x) const {
  Eigen::VectorXd value = Eigen::VectorXd::Zero(coefficients.cols());
  for (int a = 0; a <= degree; ++a)
    for (int b = 0; a + b <= degree; ++b)
      value += coefficients.row(monomialIndex(a, b)).transpose() *
               (std::pow(x.x(), a) * std::pow(x.y(), b));
  return value;
}

Eigen::VectorXd BivariatePolynomial::blossom(const std::vector<Vector2d>& arguments) const {
  const int n = static_cast<int>(arguments.size());
  if (n < degree)
    throw InputError("polynomial blossom: " + std::to_string(n) +
                     " arguments for a polynomial of degree " + std::to_string(degree));
  if (coefficients.rows() != monomialCount(degree))
    throw InputError("polynomial blossom: " + std::to_string(coefficients.rows()) +
                     " coefficient rows for degree " + std::to_string(degree) + ", expected " +
                     std::to_string(monomialCount(degree)));
  // e[a][b] = sum over disjoint index sets A, B (|A| = a, |B| = b) of prod_A u.x prod_B u.y: the
  // coefficient of s^a t^b in prod_i (1 + s u_i.x + t u_i.y), updated argument by argument.
  const int d = degree;
  std::vector<double> e((d + 1) * (d + 1), 0.0);
  e[0] = 1.0;
  for (const Vector2d& u : arguments)
    for (int a = d; a >= 0; --a)
      for (int b = d - a; b >= 0; --b) {
        double& term = e[a * (d + 1) + b];
        if (a > 0) term += u.x() * e[(a - 1) * (d + 1) + b];
        if (b > 0) term += u.y() * e[a * (d + 1) + b - 1];
      }
  // The blossom of x^a y^b averages over the n! / (a! b! (n-a-b)!) such products.
  Eigen::VectorXd value = Eigen::VectorXd::Zero(coefficients.cols());
  for (int a = 0; a <= d; ++a)
    for (int b = 0; a + b <= d; ++b) {
      const double count = binomial(n, a) * binomial(n - a, b);
      value += coefficients.row(monomialIndex(a, b)).transpose() * (e[a * (d + 1) + b] / count);
    }
  return value;
}

Eigen::MatrixXd controlPointsFromBlossom(const DmsSpace& space, const Blossom& blossom) {
  Eigen::MatrixXd control;
  for (int k = 0; k < space.numBasis(); ++k) {
    const Eigen::VectorXd value = blossom(space.blossomArguments(k));
    if (k == 0) control.resize(space.numBasis(), value.size());
    if (value.size() != control.cols())
      throw InputError("DMS control points: the blossom returned " + std::to_string(value.size()) +
                       " coordinates for basis function " + std::to_string(k) + " but " +
                       std::to_string(control.cols()) + " before");
    control.row(k) = value.transpose();
  }
  return control;
}

Eigen::MatrixXd controlPointsOfPolynomial(const DmsSpace& space,
                                          const BivariatePolynomial& polynomial) {
  if (polynomial.degree > space.degree())
    throw InputError("DMS control points: a polynomial of degree " +
                     std::to_string(polynomial.degree) + " is not in a space of degree " +
                     std::to_string(space.degree()));
  return controlPointsFromBlossom(space, [&polynomial](const std::vector<Vector2d>& arguments) {
    return polynomial.blossom(arguments);
  });
}

}  // namespace mspline::spline
