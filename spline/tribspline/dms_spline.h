#pragma once
// Triangular B-splines of Dahmen, Micchelli and Seidel (DMS splines; "Blossoming begets B-spline
// bases built better by B-patches", Math. Comp. 1992) over a planar triangulation: the planar
// core that manifold splines evaluate chart by chart.
//
// Knot clouds. Vertex i of a degree-n space carries the knots t_{i,0} = vertex i, t_{i,1}, ...,
// t_{i,n}. For a triangle I = (i0, i1, i2) and beta = (b0, b1, b2) >= 0 let
//   V_beta^I = {t_{i0,0..b0}, t_{i1,0..b1}, t_{i2,0..b2}} (|beta| + 3 knots),
//   W_beta^I = [t_{i0,b0}, t_{i1,b1}, t_{i2,b2}] (the knot triangle).
// The basis is N_beta^I = |det W_beta^I| / ((n + 1)(n + 2)) * M(. | V_beta^I), |beta| = n, with
// M the simplex spline of integral 1 (simplex_spline.h): (n+1)(n+2)/2 functions per triangle.
//
// What the knots must satisfy (DmsSpace checks it and throws InputError otherwise): the
// triangles are counter-clockwise and every knot triangle W_beta^I with beta >= 0, |beta| <= n
// is counter-clockwise too, with at least minKnotTriangleRatio of I's area. That is all that the
// partition of unity and the polynomial reproduction rest on: removing t_{ij,bj} from V_beta^I
// leaves V_{beta-e_j}^I, so Micchelli's recurrence with W = W_beta^I descends triangle by
// triangle; where bj = 0 it leaves the knots of the edge opposite i_j, a set the neighbour
// across that edge meets with the opposite sign, so those terms cancel for polar-form control
// points. DMS also ask that the interiors of a triangle's knot triangles share a point (Omega_I
// not empty), which their proof of linear independence uses; generateKnotClouds gives that too
// (each triangle's incenter lies inside all of its knot triangles). Repeated knots and collinear
// knots are allowed; the space is C^{n-1} where every knot set is in general position, and loses
// smoothness across lines holding three knots of one set (vertices on a common line count).
//
// Where it is a partition of unity and reproduces polynomials: on the triangulated domain
// outside the convex hulls of the two knot clouds of each boundary edge (whose edge terms have
// no neighbour to cancel).
//
// Half-open convention: every value is the limit at x + eps (1, eps), eps -> 0+, decided by
// exact orientation tests (see simplex_spline.h), so that the partition of unity holds exactly on
// knot lines and triangle edges as well. locate() uses the same rule.
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/tribspline/simplex_spline.h"

namespace mspline::spline {

/// knots[i][b] = t_{i,b}, b = 0 .. n; knots[i][0] is vertex i.
using KnotClouds = std::vector<std::vector<Eigen::Vector2d>>;

struct KnotCloudOptions {
  /// t_{i,1..n} are uniform in the disk of radius radiusFraction * (smallest inradius of the
  /// triangles at vertex i) around vertex i. Below 0.58 (required: in (0, 0.5]) every knot
  /// triangle of a triangle contains its incenter: moving the corners of a triangle of inradius
  /// r by less than f r keeps the incenter inside while f^2 + 2 sqrt(2) f < 2. Larger clouds
  /// overlap more triangles: smoother-looking but slower to evaluate.
  double radiusFraction = 0.3;
  /// Seed of the random generator (std::mt19937_64); the same seed gives the same clouds.
  std::uint64_t seed = 1;
};

/// Random knot clouds satisfying the conditions above for the given triangulation (see
/// KnotCloudOptions). Isolated vertices get t_{i,b} = vertex i. Throws InputError for a degree
/// below 1, a radius fraction outside (0, 0.5], or a triangle that DmsSpace would reject.
KnotClouds generateKnotClouds(const std::vector<Eigen::Vector2d>& vertices,
                              const std::vector<std::array<int, 3>>& triangles, int degree,
                              const KnotCloudOptions& options = {});

struct DmsSpaceOptions {
  /// Every knot triangle W_beta^I must have at least this fraction of the area of I: nearly flat
  /// knot triangles make the recurrence's barycentric coordinates huge.
  double minKnotTriangleRatio = 1e-6;
};

/// Basis function N_beta^I.
struct BasisId {
  int triangle = -1;
  std::array<int, 3> beta{0, 0, 0};
};

/// The basis functions that may be non-zero at a point (all others vanish there).
struct BasisValues {
  std::vector<int> index;
  std::vector<double> value;
  /// With derivatives >= 1 (else empty): (d/dx, d/dy).
  std::vector<Eigen::Vector2d> gradient;
  /// With derivatives >= 2 (else empty).
  std::vector<Eigen::Matrix2d> hessian;
};

/// The basis functions of one triangle T at a point: entry k belongs to N_{T * perTriangle + k}
/// (perTriangle = (n + 1)(n + 2) / 2), zeros included.
struct TriangleBasis {
  std::vector<double> value;
  /// With derivatives >= 1 (else empty): d/dx, d/dy of function k at 2 k, 2 k + 1.
  std::vector<double> gradient;
  /// With derivatives >= 2 (else empty): d2/dx2, d2/dxdy, d2/dy2 of function k at 3 k .. 3 k + 2.
  std::vector<double> hessian;
};

/// A spline and its derivatives at one point (control points of any dimension d).
struct SplinePoint {
  Eigen::VectorXd position;
  /// With derivatives >= 1 (else empty): d/dx and d/dy of the position.
  Eigen::VectorXd du;
  Eigen::VectorXd dv;
  /// With derivatives >= 2 (else empty).
  Eigen::VectorXd duu;
  Eigen::VectorXd duv;
  Eigen::VectorXd dvv;
  /// For d = 3 and derivatives >= 1: du x dv normalized (zero where du, dv are parallel).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
};

/// A spline at many points: row k belongs to point k. Matrices not asked for are empty.
struct SplineSamples {
  Eigen::MatrixXd position;
  Eigen::MatrixXd du;
  Eigen::MatrixXd dv;
  Eigen::MatrixXd duu;
  Eigen::MatrixXd duv;
  Eigen::MatrixXd dvv;
  /// d = 3 and derivatives >= 1: one unit normal per row (3 columns).
  Eigen::MatrixXd normal;
};

struct BivariatePolynomial;

/// The DMS spline space of a planar triangulation with knot clouds: its basis, point location
/// and spline evaluation. Immutable after construction; evaluation from several threads at once
/// is safe.
///
/// Evaluation at a point of triangle T visits only the triangles whose basis supports (the
/// convex hull of their three knot clouds) meet T, skips those whose support cannot hold the
/// point (bounds on T's barycentric coordinates), and runs per triangle a de Casteljau-like
/// scheme over beta with precomputed affine coefficients: O(n^3) work, plus the knot sets of
/// edges whose two clouds' hull holds the point. Batches are evaluated grouped by triangle.
class DmsSpace {
 public:
  /// The space of degree `degree` with clouds from generateKnotClouds(..., knotOptions).
  DmsSpace(std::vector<Eigen::Vector2d> vertices, std::vector<std::array<int, 3>> triangles,
           int degree = 3, const KnotCloudOptions& knotOptions = {},
           const DmsSpaceOptions& options = {});
  /// The space with the given clouds; its degree is knots[i].size() - 1 (one for all vertices,
  /// from 1 to 10). Throws InputError naming the first violated condition (see the top of this
  /// file), an index out of range, a coordinate that is not finite, or an edge that two triangles
  /// use in the same direction.
  DmsSpace(std::vector<Eigen::Vector2d> vertices, std::vector<std::array<int, 3>> triangles,
           KnotClouds knots, const DmsSpaceOptions& options = {});

  int degree() const { return degree_; }
  int numVertices() const { return static_cast<int>(vertices_.size()); }
  int numTriangles() const { return static_cast<int>(triangles_.size()); }
  /// (n + 1)(n + 2) / 2.
  int basisPerTriangle() const { return perTriangle_; }
  int numBasis() const { return perTriangle_ * numTriangles(); }
  const std::vector<Eigen::Vector2d>& vertices() const { return vertices_; }
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }
  const KnotClouds& knots() const { return knots_; }

  /// Index of N_beta^I: I * basisPerTriangle() + the position of beta in the order
  /// (n,0,0), (n-1,1,0), (n-1,0,1), (n-2,2,0), ... (b0 descending, then b1 descending).
  int basisIndex(int triangle, const std::array<int, 3>& beta) const;
  BasisId basisId(int index) const;
  /// V_beta^I (n + 3 knots).
  std::vector<Eigen::Vector2d> knotSet(int index) const;
  /// |det W_beta^I| / ((n + 1)(n + 2)): N_beta^I = normalization * M(. | V_beta^I).
  double normalization(int index) const;
  /// U_beta^I = {t_{i0,0..b0-1}, t_{i1,0..b1-1}, t_{i2,0..b2-1}} (n knots): the control point of
  /// N_beta^I that reproduces a polynomial is its blossom at U_beta^I.
  std::vector<Eigen::Vector2d> blossomArguments(int index) const;
  /// The triangles whose basis functions can be non-zero somewhere in triangle T (T first).
  std::vector<int> influencingTriangles(int triangle) const;

  /// The triangle whose half-open part holds x; else (x on the domain's boundary, the
  /// perturbation leaving it) a triangle whose closure holds x; else -1.
  int locate(const Eigen::Vector2d& x) const;

  /// The basis functions that may be non-zero at x, which must lie in the closed triangle T,
  /// with derivatives up to `derivatives` (0, 1 or 2). Reuses `out`'s storage.
  void basisAt(int triangle, const Eigen::Vector2d& x, BasisValues& out, int derivatives = 0) const;

  /// The basis functions of triangle T alone (its neighbours' left out) at any point x of the
  /// plane, for callers that evaluate each triangle's functions where its own chart puts the point
  /// (manifold splines: a one-triangle space per face). Returns false where x lies outside all
  /// their supports (`out` then unchanged); else fills `out`, reusing its storage.
  bool triangleBasisAt(int triangle, const Eigen::Vector2d& x, TriangleBasis& out,
                       int derivatives = 0) const;

  /// Inside triangle T and away from its edges' knot clouds the recurrence meets no edge set, and
  /// T's basis functions are polynomials there (B-patches): column k of the result is
  /// N_{T * basisPerTriangle() + k} as a polynomial in x - (T's first vertex), which holds where
  /// T's barycentric coordinates exceed 1e-9 and x is outside the convex hulls of the knot clouds
  /// of T's edges (knots()[i] and knots()[j] for the edge between vertices i and j).
  BivariatePolynomial trianglePolynomials(int triangle) const;

  /// The spline sum_k control.row(k) N_k at x in the closed triangle T (triangle < 0: located),
  /// with derivatives up to `derivatives` (0, 1 or 2). control has numBasis() rows.
  SplinePoint evaluate(const Eigen::MatrixXd& control, int triangle, const Eigen::Vector2d& x,
                       int derivatives = 1) const;
  /// The same at every row of `points`; triangles[k] is the triangle of point k (negative:
  /// located; an empty vector locates all). Throws InputError for a point outside the domain or
  /// a triangle index too large.
  SplineSamples evaluateBatch(const Eigen::MatrixXd& control, const std::vector<int>& triangles,
                              const Eigen::MatrixX2d& points, int derivatives = 1) const;

 private:
  /// One coefficient of the per-triangle scheme: value += (a + bx dx + by dy) * source[index],
  /// with (dx, dy) = x - the triangle's first vertex. source 0: the triangle's own nodes;
  /// 1 + j: the graph of the edge opposite local vertex j (whose node 0 is the zero spline).
  struct Child {
    double a;
    double bx;
    double by;
    std::int32_t source;
    std::int32_t index;
  };
  /// A convex region containing a support: bounding box and half-planes nx x + ny y <= c.
  struct Hull {
    double minX, maxX, minY, maxY;
    int firstPlane, endPlane;
  };
  struct Scratch;

  void buildEdges();
  void buildTriangleSchemes(const DmsSpaceOptions& options);
  void buildHulls();
  void buildLocator();
  void buildNeighbourhoods();
  Hull makeHull(std::vector<Eigen::Vector2d> points);
  bool inHull(const Hull& hull, double x, double y) const;
  /// Calls visit(index, value, gradient, hessian) for the basis functions of the triangles whose
  /// support holds x (Derivatives: 0, 1 or 2; unused outputs are zero).
  template <int Derivatives, class Visitor>
  void visitBasis(int triangle, const Eigen::Vector2d& x, Scratch& scratch, Visitor&& visit) const;
  /// Triangle `source`'s scheme at x: nodes[0] = inside (the half-open triangle holds x), and
  /// from[0] = scratch.nodes, from[1 + j] the values of the graph of the edge opposite local
  /// vertex j (scratch.zeros where its hull does not hold x; anyEdge: some does). Calls visit as
  /// visitBasis does.
  template <int Derivatives, class Visitor>
  void visitScheme(int source, const Eigen::Vector2d& x, bool inside, const double* const* from,
                   bool anyEdge, Scratch& scratch, Visitor&& visit) const;
  template <class Visitor>
  void dispatch(int derivatives, int triangle, const Eigen::Vector2d& x, Visitor&& visit) const;
  /// T's barycentric coordinates at x (frames_).
  std::array<double, 3> barycentric(int triangle, const Eigen::Vector2d& x) const;
  /// Whether the hull of the clouds of T's edge opposite local vertex j holds x (lambda: T's
  /// barycentric coordinates at x).
  bool inEdgeHull(int triangle, int j, const std::array<double, 3>& lambda,
                  const Eigen::Vector2d& x) const;
  /// InputError for derivatives outside 0..2 or a triangle out of range.
  void checkArguments(int derivatives, int triangle) const;
  /// This thread's evaluation buffers, grown for this space.
  Scratch& scratch() const;

  int degree_ = 0;
  int perTriangle_ = 0;
  /// Nodes per triangle scheme: all beta with |beta| <= n, level by level.
  int schemeNodes_ = 0;
  std::vector<Eigen::Vector2d> vertices_;
  std::vector<std::array<int, 3>> triangles_;
  KnotClouds knots_;

  /// Edge e joins edgeVertices_[e][0] < edgeVertices_[e][1]; triangleEdges_[I][j] is the edge
  /// opposite local vertex j.
  std::vector<std::array<int, 2>> edgeVertices_;
  std::vector<std::array<int, 3>> triangleEdges_;
  /// Per edge: the simplex splines of the knot sets of its two clouds.
  std::vector<SimplexSplineGraph<double>> edgeGraphs_;
  int maxEdgeNodes_ = 0;

  /// Triangle I's scheme: children_[(I * (schemeNodes_ - 1) + node - 1) * 3 + j], node >= 1.
  std::vector<Child> children_;
  /// First node of level k (|beta| = k) in a scheme; level n holds the basis functions.
  std::vector<int> levelStart_;
  /// Per scheme node: how many of its children (listed first) are nodes of the same scheme.
  std::vector<int> ownChildren_;

  /// Per edge: the convex hull of its two clouds, the support of its knot sets.
  std::vector<Hull> edgeHulls_;
  std::vector<std::array<double, 3>> planes_;
  /// Per triangle T: its barycentric coordinates lambda_j(x) = c_j + gx_j dx + gy_j dy, with
  /// (dx, dy) = x - T's first vertex, as (c_j, gx_j, gy_j) for j = 0, 1, 2. Supports are
  /// screened by upper bounds on them (neighbourBounds_, edgeBounds_): three comparisons.
  std::vector<std::array<double, 9>> frames_;

  /// Uniform grid over the vertices' bounding box: cell -> triangles whose bounding box meets it.
  Eigen::Vector2d gridLow_ = Eigen::Vector2d::Zero();
  double gridCell_ = 1.0;
  int gridColumns_ = 1;
  int gridRows_ = 1;
  std::vector<int> gridStart_;
  std::vector<int> gridTriangles_;

  /// Per triangle T: its influencing triangles neighbourStart_[T] .. neighbourStart_[T + 1) in
  /// neighbours_, with per influencing triangle the slots of its three edges in T's edge list
  /// (neighbourEdgeSlots_), and T's edge list edgeStart_[T] .. edgeStart_[T + 1) in edgeList_.
  std::vector<int> neighbourStart_;
  std::vector<int> neighbours_;
  std::vector<std::array<int, 3>> neighbourEdgeSlots_;
  /// Per entry of neighbours_ / edgeList_: the largest barycentric coordinates (in T's frame)
  /// over the influencing triangle's support / the edge's hull (plus a margin).
  std::vector<std::array<double, 3>> neighbourBounds_;
  std::vector<int> edgeStart_;
  std::vector<int> edgeList_;
  std::vector<std::array<double, 3>> edgeBounds_;
  int maxEdgeSlots_ = 0;
};

/// A vector-valued polynomial of total degree <= degree in monomial form.
struct BivariatePolynomial {
  int degree = 0;
  /// Row monomialIndex(a, b) holds the coefficient of x^a y^b (a + b <= degree); a column per
  /// dimension.
  Eigen::MatrixXd coefficients;

  /// Monomials ordered by total degree, then by the power of y: 1, x, y, x^2, xy, y^2, ...
  static int monomialIndex(int a, int b) { return (a + b) * (a + b + 1) / 2 + b; }
  static int monomialCount(int degree) { return (degree + 1) * (degree + 2) / 2; }

  Eigen::VectorXd operator()(const Eigen::Vector2d& x) const;
  /// The blossom (polar form) of degree arguments.size() >= degree: symmetric, affine in each
  /// argument, equal to the polynomial when all arguments are x.
  Eigen::VectorXd blossom(const std::vector<Eigen::Vector2d>& arguments) const;
};

/// A polynomial of degree <= n given by its blossom (n arguments), any dimension.
using Blossom = std::function<Eigen::VectorXd(const std::vector<Eigen::Vector2d>& arguments)>;

/// The control points (a row per basis function) with which the space reproduces the
/// polynomial: row k = blossom(space.blossomArguments(k)).
Eigen::MatrixXd controlPointsFromBlossom(const DmsSpace& space, const Blossom& blossom);
/// The same for a polynomial in monomial form (its degree at most space.degree()).
Eigen::MatrixXd controlPointsOfPolynomial(const DmsSpace& space,
                                          const BivariatePolynomial& polynomial);

}  // namespace mspline::spline
