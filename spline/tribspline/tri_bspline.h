#pragma once
// Manifold triangular B-splines (Gu, He and Qin; He, Gu and Qin): DMS splines (dms_spline.h) over
// a domain triangulation of a flat surface with cones (spline_domain.h), evaluated chart by chart.
//
// Every face carries the (n+1)(n+2)/2 basis functions N_beta^I of its three knot clouds, in its
// home chart. Simplex splines are invariant under affine maps, so a basis function has the same
// value at a surface point in every chart that holds both: mapping the point (or the knots) by
// the transitions changes nothing.
//
// Knot clouds. A vertex that is no cone has one cloud, drawn once in a flat neighbourhood and
// carried into every incident face's chart by the transitions, so neighbouring faces see the same
// knots and the DMS identities hold: the basis is a partition of unity to rounding. At a cone no
// flat neighbourhood exists (going around it turns the plane by the cone's curvature), so no cloud
// can look the same from all its faces; each incident face gets a small cloud of its own inside
// its corner there.
//
// Near cones. With different clouds on the two sides of a side at a cone, the DMS edge terms no
// longer cancel, and the faces' functions sum to less than one along those sides, going to zero
// like t^n at the cone (t: distance from it along the side, relative to the side). So the spline
// is normalized rationally, sum_k c_k N_k / sum_k N_k, as Gu, He and Qin's manifold splines are:
// it is defined, closed and as smooth as the basis (C^(n-1) for knots in general position)
// everywhere except at the cone points themselves, where the denominator vanishes. Where no
// cone's faces contribute the denominator is 1 to rounding and nothing changes. Close to a cone
// the small denominator amplifies rounding; `denominator` reports it, and the commands report
// the smallest one met and where it falls below their threshold (the hole around the cone).
#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mspline/spline/core/spline_model.h"
#include "mspline/spline/tribspline/dms_spline.h"
#include "mspline/spline/tribspline/spline_domain.h"

namespace mspline::spline {

/// Knot clouds for every face of `domain` (see the top of this file). Shared clouds: in the ring
/// from 0.3 to 1 times options.radiusFraction * (smallest inradius of the faces at the vertex),
/// drawn in the home chart of the vertex's first face; cone clouds: in the middle 60% of the
/// corner's angle, 0.02 to 0.04 times that radius from the cone. Knots kept off the vertex keep the
/// knot triangles from degenerating, which would amplify rounding. Deterministic for a given seed.
std::vector<FaceKnots> placeKnotClouds(const SplineDomain& domain,
                                       const std::vector<HomeChart>& charts, int degree,
                                       const KnotCloudOptions& options = {});

/// The basis of a manifold triangular B-spline and evaluation of splines in it. Immutable after
/// construction; evaluation from several threads at once is safe.
class TriBSplineSpace {
 public:
  /// Throws InputError when the domain is invalid (validateDomain, buildHomeCharts), the knots do
  /// not match it (one FaceKnots per face, n + 1 knots per corner, knot 0 the corner in the face's
  /// frame to 1e-9) or violate the DMS conditions (dms_spline.h).
  TriBSplineSpace(SplineDomain domain, std::vector<FaceKnots> knots);

  int degree() const { return degree_; }
  /// (n + 1)(n + 2) / 2.
  int basisPerFace() const { return perFace_; }
  int numBasis() const { return perFace_ * domain_.faceCount(); }
  const SplineDomain& domain() const { return domain_; }
  const std::vector<HomeChart>& charts() const { return charts_; }
  const std::vector<FaceKnots>& knots() const { return knots_; }

  /// The point's position in its face's frame.
  Eigen::Vector2d framePosition(const SurfacePoint& point) const;

  /// The normalized basis functions that may be non-zero at `point`, with derivatives (0, 1 or 2)
  /// with respect to the frame of point.face; `denominator` receives sum_k N_k at the point. At a
  /// cone point, where every function vanishes, `out` is left empty.
  void basisAt(const SurfacePoint& point, BasisValues& out, int derivatives = 0,
               double* denominator = nullptr) const;

  /// The spline with control points `control` (numBasis() rows, any dimension) at a point, with
  /// derivatives in the frame of point.face. InputError at a cone point.
  SplinePoint evaluate(const Eigen::MatrixXd& control, const SurfacePoint& point,
                       int derivatives = 1) const;
  /// The same at many points (rows in the order of `points`); agrees with evaluate up to
  /// rounding. The points are taken face by face; where only a face's own functions reach (inside
  /// it, away from its sides' knot clouds) the sums come from its polynomial pieces
  /// (DmsSpace::trianglePolynomials), elsewhere function by function, normalized once per point.
  SplineSamples evaluateBatch(const Eigen::MatrixXd& control,
                              const std::vector<SurfacePoint>& points, int derivatives = 1) const;
  /// The same into `out`, reusing its matrices' storage when they have the size already.
  void evaluateBatch(const Eigen::MatrixXd& control, const std::vector<SurfacePoint>& points,
                     int derivatives, SplineSamples& out) const;

  /// The faces whose home charts hold `face` (their basis functions may be non-zero on it), one
  /// entry per copy of `face` in the chart: evaluateInChart's `holder` indexes this list.
  std::vector<int> chartsHolding(int face) const;
  /// How evaluateInChart brings a basis function and the point together in a chart.
  enum class ChartRoute {
    /// The point goes into the chart and from there, by the chart's own development, into the
    /// function's home chart: checks that the transitions compose (the cocycle condition).
    MovePoint,
    /// The function's knots are moved into the chart and the simplex splines evaluated there from
    /// scratch (simplex_spline.h): checks affine invariance as well. Slow.
    MoveKnots,
  };
  /// The spline's value at `point` computed in the home chart chartsHolding(point.face)[holder]:
  /// every basis function whose face that chart also holds, at the place where the function's
  /// own chart sees the point (within 1e-6 of the face's size: a chart may hold several copies),
  /// is evaluated through it as `route` says, the others in their own charts.
  Eigen::VectorXd evaluateInChart(const Eigen::MatrixXd& control, const SurfacePoint& point,
                                  int holder, ChartRoute route) const;

 private:
  struct Contributor {
    int face;
    /// From the frame of the face holding the point into `face`'s frame: y = rotation x +
    /// motion.translation (the rotation's matrix kept, as evaluation needs it at every point).
    structure::RigidMotion motion;
    Eigen::Matrix2d rotation;
    /// Where `face`'s functions may be non-zero: its triangle and the convex hulls of the knot
    /// clouds of its three sides (beyond its triangle only the sides' edge sets reach), each as
    /// upper bounds of the barycentric coordinates with respect to the face holding the point,
    /// widened by 1e-9. Three comparisons per region.
    std::array<std::array<double, 3>, 4> reach;
    /// Their largest coordinates (the bounds of their union), tested first.
    std::array<double, 3> anyReach;
    /// Whether a point with barycentric coordinates lambda may lie in one of the regions.
    bool mayReach(const double* lambda) const;
  };
  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  /// evaluateBatch's work on the points in `order` (grouped by face), with rows = [1, control
  /// point] per basis function; Parts: 1, 3 or 6 for derivatives 0, 1, 2; Width: rows' columns
  /// when fixed at compile time, else 0.
  template <int Parts, int Width>
  void evaluateOrdered(const std::vector<SurfacePoint>& points, const std::vector<int>& order,
                       const RowMatrix& rows, SplineSamples& samples) const;
  /// The barycentric coordinates of the frame position x in `face`.
  std::array<double, 3> barycentricAt(int face, const Eigen::Vector2d& x) const;
  /// Calls visit(contributor, basis) for every contributor with a function that may be non-zero
  /// at the point `x` (frame position; lambda: barycentricAt) of `face`, with its basis there in
  /// its own frame.
  template <class Visitor>
  void visitContributors(int face, const Eigen::Vector2d& x, const std::array<double, 3>& lambda,
                         int derivatives, TriangleBasis& basis, Visitor&& visit) const;

  SplineDomain domain_;
  std::vector<FaceKnots> knots_;
  std::vector<HomeChart> charts_;
  int degree_ = 0;
  int perFace_ = 0;
  /// Per face: the one-triangle DMS space of its knots in its frame.
  std::vector<DmsSpace> faceSpaces_;
  /// Per face: canonicalCorners.
  std::vector<std::array<Eigen::Vector2d, 3>> corners_;
  /// Per face: its barycentric coordinates in its frame, lambda_j(x) = c_j + gx_j x.x + gy_j x.y
  /// stored as (c_j, gx_j, gy_j) for j = 0, 1, 2.
  std::vector<std::array<double, 9>> barycentric_;
  /// Per face G: the faces whose charts hold G, with the motion from G's frame into theirs.
  std::vector<std::vector<Contributor>> contributors_;
  /// Per face G: lower bounds t of its barycentric coordinates such that where lambda_j > t_j
  /// (j = 0, 1, 2) only G's own functions reach (no other contributor's regions, none of the
  /// hulls of the clouds of G's sides) and they are polynomials (DmsSpace::trianglePolynomials).
  /// An inner triangle, chosen so that each such region lies in some lambda_j <= t_j.
  std::vector<std::array<double, 3>> polynomialFrom_;
};

}  // namespace mspline::spline
