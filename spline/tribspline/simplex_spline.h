#pragma once
// Bivariate simplex splines M(x | V) (Micchelli 1979; de Boor 1976): for m = n + 3 knots V in the
// plane, the density of sum_j s_j v_j when s is uniform on the standard (m-1)-simplex, i.e.
// vol_{m-3}(slice of a simplex over x) / vol_{m-1}(simplex). M is a piecewise polynomial of
// degree n = m - 3 with breaks on the segments between knots, supported in the convex hull of V,
// and its integral is 1.
//
// Evaluation by Micchelli's stable recurrence: for three affinely independent knots w0, w1, w2 of
// V and x = sum_j lambda_j w_j with sum_j lambda_j = 1,
//   M(x | V) = (n + 2) / n * sum_j lambda_j M(x | V \ {w_j})            (n >= 1),
//   D_d M(x | V) = (n + 2) * sum_j mu_j M(x | V \ {w_j}),   d = sum_j mu_j w_j, sum_j mu_j = 0,
// ending at M(x | triangle) = indicator / area. (The factor n + 2 = m - 1 belongs to the
// normalization of integral 1; both formulas follow from the Dirichlet density of the same
// splines for knots at three points, which the tests check.) Knot sets met on the way that lie on
// a line are measures, not functions; their coefficient lambda_j vanishes on that line (both
// other points of W lie on it), so they count as 0, and so does M for knots all on one line.
//
// Half-open convention: every value is the limit at x + eps (1, eps) as eps -> 0+, i.e. the
// polynomial piece of the open cell of the knot-line arrangement that this perturbation enters.
// It is decided by exact orientation tests (no number is added), so that the same point is on
// the same side of a line wherever the line is tested: partitions of unity then hold on knot
// lines too. Derivatives are those of that piece.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/core/errors.h"

namespace mspline::spline {

template <class Scalar>
using Point2 = Eigen::Matrix<Scalar, 2, 1>;

namespace detail {

template <class Scalar>
inline void twoSum(Scalar a, Scalar b, Scalar& sum, Scalar& error) {
  sum = a + b;
  const Scalar bVirtual = sum - a;
  const Scalar aVirtual = sum - bVirtual;
  error = (a - aVirtual) + (b - bVirtual);
}

// The determinant of (a - c, b - c) as an expansion: each of its six products is split into two
// floats by fma and the twelve are summed into a non-overlapping expansion (Shewchuk's
// grow-expansion), exactly. Returns the expansion's sum (non-zero with the exact sign whenever
// the determinant is non-zero) and writes the exact sign.
// Out of line: the filter in orientationDeterminant rarely fails, and inlining it there everywhere
// would bloat the callers' loops.
template <class Scalar>
[[gnu::noinline]] Scalar exactDeterminant(const Point2<Scalar>& a, const Point2<Scalar>& b,
                                          const Point2<Scalar>& c, int& sign) {
  const std::array<std::array<Scalar, 2>, 6> products = {{{a.x(), b.y()},
                                                          {-a.x(), c.y()},
                                                          {-c.x(), b.y()},
                                                          {-a.y(), b.x()},
                                                          {a.y(), c.x()},
                                                          {c.y(), b.x()}}};
  std::array<Scalar, 12> expansion{};
  int length = 0;
  const auto grow = [&](Scalar q) {
    for (int i = 0; i < length; ++i) twoSum(q, expansion[i], q, expansion[i]);
    expansion[length++] = q;
  };
  for (const auto& [u, v] : products) {
    const Scalar product = u * v;
    grow(std::fma(u, v, -product));
    grow(product);
  }
  sign = 0;
  Scalar sum = 0;
  // Smallest components first; the largest non-zero one carries the sign.
  for (int i = 0; i < length; ++i) {
    sum += expansion[i];
    if (expansion[i] != 0) sign = expansion[i] > 0 ? 1 : -1;
  }
  return sum != 0 ? sum : Scalar(sign) * std::numeric_limits<Scalar>::denorm_min();
}

}  // namespace detail

/// det(b - a, c - a) with the exact sign: the floating-point value where a filter certifies its
/// sign, else from exact expansion arithmetic (then non-zero exactly when the points are not
/// collinear, so it can divide). `sign` receives the exact sign.
template <class Scalar>
inline Scalar orientationDeterminant(const Point2<Scalar>& a, const Point2<Scalar>& b,
                                     const Point2<Scalar>& c, int& sign) {
  static_assert(std::is_floating_point_v<Scalar>, "exact predicates need IEEE floating point");
  // Shewchuk's orient2d error bound (3 + 16 eps) eps with eps half the machine epsilon.
  constexpr Scalar eps = std::numeric_limits<Scalar>::epsilon() / 2;
  constexpr Scalar bound = (3 + 16 * eps) * eps;
  const Scalar left = (a.x() - c.x()) * (b.y() - c.y());
  const Scalar right = (a.y() - c.y()) * (b.x() - c.x());
  const Scalar det = left - right;
  if (std::abs(det) > bound * (std::abs(left) + std::abs(right))) {
    sign = det > 0 ? 1 : -1;
    return det;
  }
  return detail::exactDeterminant(a, b, c, sign);
}

/// Exact sign of the orientation of (a, b, c): +1 counter-clockwise, -1 clockwise, 0 collinear.
template <class Scalar>
int orientation(const Point2<Scalar>& a, const Point2<Scalar>& b, const Point2<Scalar>& c) {
  int sign = 0;
  orientationDeterminant(a, b, c, sign);
  return sign;
}

/// The side of the directed line a -> b that x + eps (1, eps) lies on for all small eps > 0: +1
/// left, -1 right; 0 only when a == b. Exact, and antisymmetric in (a, b).
template <class Scalar>
int perturbedSide(const Point2<Scalar>& a, const Point2<Scalar>& b, const Point2<Scalar>& x) {
  if (const int side = orientation(a, b, x)) return side;
  // On the line: orient(a, b, x + eps e1 + eps^2 e2) = -eps (b - a).y + eps^2 (b - a).x.
  if (b.y() != a.y()) return b.y() < a.y() ? 1 : -1;
  if (b.x() != a.x()) return b.x() > a.x() ? 1 : -1;
  return 0;
}

/// Whether x + eps (1, eps) lies inside the triangle (a, b, c) of either orientation for all small
/// eps > 0 (the half-open triangle). False for a degenerate triangle.
template <class Scalar>
bool inHalfOpenTriangle(const Point2<Scalar>& a, const Point2<Scalar>& b, const Point2<Scalar>& c,
                        const Point2<Scalar>& x) {
  const int sign = orientation(a, b, c);
  return sign != 0 && perturbedSide(a, b, x) == sign && perturbedSide(b, c, x) == sign &&
         perturbedSide(c, a, x) == sign;
}

/// The simplex splines of several subsets of one knot array, sharing their common lower-degree
/// splines: a graph whose nodes are knot subsets, each evaluated from three children by the
/// recurrence. Node 0 is the zero spline (knots on one line). Nodes come after their children,
/// so one pass in node order evaluates all of them.
///
/// Node values are normalized: value = scale * M(x | knots), scale = |det W| / ((n + 1)(n + 2))
/// with W the node's three recurrence knots (for a triangle, n = 0: its area, so the value is
/// the indicator). These are the DMS normalizations, and the recurrence's coefficients then stay
/// of the order of barycentric coordinates.
template <class Scalar>
class SimplexSplineGraph {
 public:
  using Point = Point2<Scalar>;
  using Mask = std::uint64_t;
  static constexpr int kMaxKnots = 64;

  struct Node {
    /// Degree n = number of knots - 3; -1 for the zero node.
    int degree = -1;
    /// value = scale * M(x | knots).
    Scalar scale = 0;
    /// degree >= 1: the nodes of the knots without w_j (0 when those lie on a line);
    /// degree 0: the triangle's three knots, counter-clockwise.
    std::array<int, 3> child{0, 0, 0};
    /// degree 0: its sides child[j] -> child[j + 1] as knot lines: line side[j] >> 1 of the
    /// graph, reversed where bit 0 is set (x is inside when it is left of all three sides).
    std::array<int, 3> side{0, 0, 0};
    /// degree >= 1: value = sum_j alpha_j(x) value(child_j) with
    /// alpha_j(x) = a_j + bx_j (x - origin).x + by_j (x - origin).y, a multiple of lambda_j.
    std::array<Scalar, 3> a{0, 0, 0};
    std::array<Scalar, 3> bx{0, 0, 0};
    std::array<Scalar, 3> by{0, 0, 0};
  };

  /// Coefficients are stored relative to `origin`, a point near the knots.
  SimplexSplineGraph(std::vector<Point> knots, const Point& origin)
      : knots_(std::move(knots)), origin_(origin), nodes_(1) {
    if (knots_.size() > kMaxKnots)
      throw structure::InputError("simplex spline: at most 64 knots, got " +
                                  std::to_string(knots_.size()));
    for (const Point& knot : knots_)
      if (!std::isfinite(knot.x()) || !std::isfinite(knot.y()))
        throw structure::InputError("simplex spline: a knot coordinate is not finite");
  }

  /// Adds the spline of the knots whose bits are set in `mask` (at least 3) and returns its node.
  int add(Mask mask) {
    const int count = popcount(mask);
    if (count < 3 || (knots_.size() < kMaxKnots && (mask >> knots_.size()) != 0))
      throw structure::InputError("simplex spline: a knot set needs at least 3 of the knots");
    if (const auto it = memo_.find(mask); it != memo_.end()) return it->second;
    const int node = build(mask, count);
    memo_.emplace(mask, node);
    return node;
  }

  /// Frees what only add() needs (the table of the sets added so far) and trims the storage, for
  /// graphs that are complete. add() still works afterwards, but builds its nodes anew instead of
  /// sharing them with the sets added before.
  void shrink() {
    std::unordered_map<Mask, int>().swap(memo_);
    nodes_.shrink_to_fit();
    lines_.shrink_to_fit();
  }

  int size() const { return static_cast<int>(nodes_.size()); }
  const Node& node(int index) const { return nodes_[index]; }

  /// Writes the value of every node at x (half-open convention) to values[0 .. size()).
  void values(const Point& x, Scalar* values) const {
    values[0] = 0;
    const Scalar dx = x.x() - origin_.x();
    const Scalar dy = x.y() - origin_.y();
    // The side of x of each knot line, decided once per line however many triangles share it:
    // +1 or -1 (perturbedSide of its knots in order), 0 until needed.
    std::array<signed char, kMaxKnots*(kMaxKnots - 1) / 2> sides;
    std::fill_n(sides.begin(), lines_.size(), static_cast<signed char>(0));
    const auto leftOf = [&](int side) {
      signed char& known = sides[side >> 1];
      if (known == 0) {
        const auto& [from, to] = lines_[side >> 1];
        known = static_cast<signed char>(perturbedSide(knots_[from], knots_[to], x));
      }
      return (side & 1 ? -known : known) > 0;
    };
    for (std::size_t i = 1; i < nodes_.size(); ++i) {
      const Node& n = nodes_[i];
      if (n.degree == 0) {
        values[i] =
            leftOf(n.side[0]) && leftOf(n.side[1]) && leftOf(n.side[2]) ? Scalar(1) : Scalar(0);
      } else {
        Scalar v = 0;
        for (int j = 0; j < 3; ++j)
          v += (n.a[j] + n.bx[j] * dx + n.by[j] * dy) * values[n.child[j]];
        values[i] = v;
      }
    }
  }

  /// Gradient of a node's value from the values of its children: degree * sum_j grad(alpha_j)
  /// value(child_j) (the derivative formula; alpha_j's gradient is constant).
  Point gradient(int index, const Scalar* values) const {
    const Node& n = nodes_[index];
    Point g = Point::Zero();
    if (n.degree < 1) return g;
    for (int j = 0; j < 3; ++j) g += Point(n.bx[j], n.by[j]) * values[n.child[j]];
    return g * Scalar(n.degree);
  }

  /// Hessian of a node's value: degree * sum_j grad(alpha_j) grad(child_j)^T, symmetrized.
  Eigen::Matrix<Scalar, 2, 2> hessian(int index, const Scalar* values) const {
    const Node& n = nodes_[index];
    Eigen::Matrix<Scalar, 2, 2> h = Eigen::Matrix<Scalar, 2, 2>::Zero();
    if (n.degree < 2) return h;
    for (int j = 0; j < 3; ++j)
      h += Point(n.bx[j], n.by[j]) * gradient(n.child[j], values).transpose();
    h *= Scalar(n.degree);
    return (h + h.transpose()) / 2;
  }

 private:
  static int popcount(Mask mask) {
    int count = 0;
    for (; mask; mask &= mask - 1) ++count;
    return count;
  }

  // The first knot, the first one elsewhere, the first one off their line; w[2] < 0 when all
  // knots lie on one line.
  std::array<int, 3> earliestTriple(Mask mask) const {
    std::array<int, 3> w{-1, -1, -1};
    for (int k = 0; k < static_cast<int>(knots_.size()) && w[2] < 0; ++k) {
      if (!((mask >> k) & 1)) continue;
      if (w[0] < 0) {
        w[0] = k;
      } else if (w[1] < 0) {
        if (knots_[k] != knots_[w[0]]) w[1] = k;
      } else if (orientation(knots_[w[0]], knots_[w[1]], knots_[k]) != 0) {
        w[2] = k;
      }
    }
    return w;
  }

  // W: the largest triangle among the knots. Every knot then lies in the triangle whose edge
  // midpoints are W's corners, so points of the knots' hull have barycentric coordinates in
  // [-1, 1] and the recurrence amplifies rounding errors little (an arbitrary W can be thin:
  // the DMS edge sets lost 1e-11 that way).
  std::array<int, 3> largestTriple(Mask mask) const {
    std::vector<int> members;
    for (int k = 0; k < static_cast<int>(knots_.size()); ++k)
      if ((mask >> k) & 1) members.push_back(k);
    std::array<int, 3> best{-1, -1, -1};
    Scalar largest = 0;
    for (std::size_t i = 0; i < members.size(); ++i)
      for (std::size_t j = i + 1; j < members.size(); ++j)
        for (std::size_t k = j + 1; k < members.size(); ++k) {
          const Point u = knots_[members[j]] - knots_[members[i]];
          const Point v = knots_[members[k]] - knots_[members[i]];
          const Scalar area = std::abs(u.x() * v.y() - u.y() * v.x());
          if (area > largest) {
            largest = area;
            best = {members[i], members[j], members[k]};
          }
        }
    // A rounded area can be non-zero for collinear knots: the exact test decides.
    if (best[0] < 0 || orientation(knots_[best[0]], knots_[best[1]], knots_[best[2]]) == 0)
      return earliestTriple(mask);
    return best;
  }

  int build(Mask mask, int count) {
    const std::array<int, 3> w = largestTriple(mask);
    if (w[2] < 0) return 0;  // all knots on one line

    const Point p = knots_[w[0]] - origin_;
    const Point q = knots_[w[1]] - origin_;
    const Point r = knots_[w[2]] - origin_;
    const auto cross = [](const Point& u, const Point& v) { return u.x() * v.y() - u.y() * v.x(); };
    // Accurate even for nearly collinear knots, where a rounded determinant could vanish.
    int sign = 0;
    const Scalar det = orientationDeterminant(knots_[w[0]], knots_[w[1]], knots_[w[2]], sign);
    Node node;
    node.degree = count - 3;
    const Scalar k = Scalar(node.degree);
    node.scale = std::abs(det) / ((k + 1) * (k + 2));
    if (node.degree == 0) {
      node.child =
          sign > 0 ? std::array<int, 3>{w[0], w[1], w[2]} : std::array<int, 3>{w[0], w[2], w[1]};
      for (int j = 0; j < 3; ++j) node.side[j] = lineSide(node.child[j], node.child[(j + 1) % 3]);
      nodes_.push_back(node);
      return size() - 1;
    }
    // lambda_j(y) = cross(w_{j+1} - y, w_{j+2} - y) / det
    //             = (cross(w_{j+1}, w_{j+2}) + cross(y, w_{j+1} - w_{j+2})) / det.
    const std::array<Point, 3> corner = {p, q, r};
    for (int j = 0; j < 3; ++j) {
      const int child = add(mask & ~(Mask(1) << w[j]));
      node.child[j] = child;
      if (child == 0) continue;
      const Scalar factor = node.scale * (k + 2) / (k * nodes_[child].scale * det);
      const Point& u = corner[(j + 1) % 3];
      const Point& v = corner[(j + 2) % 3];
      node.a[j] = factor * cross(u, v);
      node.bx[j] = factor * (u - v).y();
      node.by[j] = -factor * (u - v).x();
    }
    nodes_.push_back(node);
    return size() - 1;
  }

  // The directed side from knot `from` to knot `to` (distinct) as a Node::side code; adds the line.
  int lineSide(int from, int to) {
    const std::array<int, 2> key = {std::min(from, to), std::max(from, to)};
    const auto it = std::find(lines_.begin(), lines_.end(), key);
    const int index = static_cast<int>(it - lines_.begin());
    if (it == lines_.end()) lines_.push_back(key);
    return 2 * index + (from > to ? 1 : 0);
  }

  std::vector<Point> knots_;
  Point origin_;
  std::vector<Node> nodes_;
  /// The knot pairs (lower index first) that the triangle nodes' sides lie on.
  std::vector<std::array<int, 2>> lines_;
  std::unordered_map<Mask, int> memo_;
};

/// M(x | knots) with integral 1 (half-open convention), and optionally its gradient and Hessian.
/// 3 to 64 knots, repeated and collinear ones allowed; all knots on one line give 0.
/// Throws InputError for fewer than 3 or more than 64 knots, or a coordinate that is not finite.
template <class Scalar>
Scalar simplexSpline(const Point2<Scalar>& x, const std::vector<Point2<Scalar>>& knots,
                     Point2<Scalar>* gradient = nullptr,
                     Eigen::Matrix<Scalar, 2, 2>* hessian = nullptr) {
  if (knots.size() < 3)
    throw structure::InputError("simplex spline: needs at least 3 knots, got " +
                                std::to_string(knots.size()));
  SimplexSplineGraph<Scalar> graph(knots, knots.front());
  const int top =
      graph.add(knots.size() == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << knots.size()) - 1);
  if (gradient) gradient->setZero();
  if (hessian) hessian->setZero();
  if (top == 0) return 0;
  std::vector<Scalar> values(graph.size());
  graph.values(x, values.data());
  const Scalar scale = graph.node(top).scale;
  if (gradient) *gradient = graph.gradient(top, values.data()) / scale;
  if (hessian) *hessian = graph.hessian(top, values.data()) / scale;
  return values[top] / scale;
}

}  // namespace mspline::spline
