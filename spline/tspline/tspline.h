#pragma once
// Cubic T-splines on a T-mesh (tmesh.h), planar or on a surface (Sederberg, Zheng, Bakenov and
// Nasri 2003; on manifolds He, Wang, Gu and Qin 2006).
//
// Every vertex of the T-mesh anchors one blending function N(s) N(t), a product of two cubic
// B-splines. Their knots are inferred from the T-mesh: rays cast from the anchor along its four
// axis directions, through the faces and across their sides, meet edges perpendicular to them; the
// first two met in each direction are the knots. The anchor's chart is the frame of a face it is a
// corner of, moved so that the anchor is the origin; faces are developed into it through the
// frame changes across their sides, so on a surface the function lives in its home chart and is
// read at a point by moving the point into that chart. Frame changes are quarter turns and
// translations, which map axis-aligned knot lines to axis-aligned knot lines: the value at a
// surface point is the same whichever face's frame the point is given in.
//
// Where a ray leaves an open T-mesh before meeting two edges, the knot spacing it last saw is
// repeated beyond the boundary (a uniform grid then gets the uniform B-splines, as OpenSubdiv's
// limit surface of the same net has on its inner faces). No function is anchored where its open
// support would overlap itself when developed (a T-mesh too small for it): those anchors are
// listed instead.
//
// Extraordinary vertices get polynomial caps (tspline_cap.h): the vertex and its one-ring anchor
// uniform B-splines, developed sector by sector on the faces of the cap region that do not touch
// the vertex, and each face around the vertex is one bicubic Bezier patch whose coefficients are
// affine combinations of control points (capFace). The surface is defined at the vertex, with a
// unique normal there. A T-mesh whose extraordinary vertices lack the uniform grid a cap needs is
// rejected (SolverError).
//
// The surface is the rational sum_i w_i c_i N_i / sum_i w_i N_i. On an analysis-suitable T-mesh
// (in particular a grid), on faces at least one face away from an open boundary, the N_i sum to
// one and with unit weights this is the plain sum; elsewhere (next to an open boundary, where the
// padded knots have no functions beyond it, and where T-junction extensions cross) the
// normalization keeps the partition of unity, and `denominator` reports how far it was needed.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/tspline/tmesh.h"

namespace mspline::spline {

/// One blending function.
struct TSplineAnchor {
  /// The T-mesh vertex it is anchored at.
  int vertex = -1;
  /// Its chart: the frame of this face (the anchor is one of its corners), translated so that the
  /// anchor is the origin.
  int chartFace = -1;
  /// Knots along the chart's axes; entry 2 is 0 (the anchor).
  std::array<double, 5> sKnots{};
  std::array<double, 5> tKnots{};
  /// Rays that left the T-mesh and had knots added beyond its boundary.
  int paddedRays = 0;
};

/// A face's share of a blending function: the motion from the face's frame into the function's
/// chart.
struct TSplinePiece {
  int anchor = -1;
  QuarterMotion toChart;
};

/// A blending function's knot lines in the frame of a face: its chart axes turned onto the face's
/// (x = xKnots, y = yKnots), each sorted ascending. The function there is
/// cubicBSpline(xKnots, x) * cubicBSpline(yKnots, y).
struct FaceKnots2d {
  std::array<double, 5> xKnots{}, yKnots{};
};

/// The knots of `anchor` seen from a face whose frame goes into the anchor's chart by `toChart`.
FaceKnots2d knotsInFace(const TSplineAnchor& anchor, const QuarterMotion& toChart);

/// A face around an extraordinary vertex: one bicubic Bezier patch whose coefficients (row 4 j + i
/// for Bernstein B_i(x / width) B_j(y / height) in the face frame) are affine combinations of the
/// blending functions' coefficients (one column per entry of `anchors`).
struct TSplineCapFace {
  int face = -1;
  /// The extraordinary vertex, a corner of the face.
  int cone = -1;
  std::vector<int> anchors;
  Eigen::Matrix<double, 16, Eigen::Dynamic> bezier;
};

/// A vertex without a blending function, and why.
struct TSplineMissingAnchor {
  int vertex = -1;
  std::string reason;
};

/// The value and derivatives (in the frame of the face the point was given in) of one blending
/// function at a point.
struct TSplineBasisValue {
  int anchor = -1;
  double value = 0.0;
  double ds = 0.0, dt = 0.0, dss = 0.0, dst = 0.0, dtt = 0.0;
};

/// A point of a T-spline surface with derivatives along the face frame's axes.
struct TSplinePoint {
  Eigen::VectorXd position, ds, dt, dss, dst, dtt;
  /// Surfaces in 3-space, with derivatives asked for: the unit normal ds x dt / |ds x dt| (NaN
  /// where the derivatives are parallel); empty otherwise.
  Eigen::VectorXd normal;
  /// sum_i w_i N_i at the point (1 where the blending functions form a partition of unity);
  /// 0 in a hole, where position is NaN.
  double denominator = 0.0;
};

/// The blending functions of a T-mesh. Immutable; evaluation may run on several threads at once.
class TSplineSpace {
 public:
  /// Infers every blending function. Throws InputError for an invalid mesh (buildTMesh's checks
  /// are assumed done) and SolverError for an extraordinary vertex without a cap (tspline_cap.h).
  explicit TSplineSpace(TMesh mesh);

  const TMesh& mesh() const { return mesh_; }
  int numBasis() const { return static_cast<int>(anchors_.size()); }
  const std::vector<TSplineAnchor>& anchors() const { return anchors_; }
  /// Per T-mesh vertex its blending function, or -1.
  const std::vector<int>& anchorOfVertex() const { return anchorOfVertex_; }
  const std::vector<TSplineMissingAnchor>& missingAnchors() const { return missing_; }
  /// The blending functions whose support overlaps face f, with the motions into their charts;
  /// empty on a cap face.
  const std::vector<TSplinePiece>& pieces(int face) const { return pieces_.at(face); }
  /// The cap patch on face f, or nullptr when f is not around an extraordinary vertex.
  const TSplineCapFace* capFace(int face) const {
    const int at = capFaceOf_.at(std::size_t(face));
    return at < 0 ? nullptr : &capFaces_[std::size_t(at)];
  }
  const std::vector<TSplineCapFace>& capFaces() const { return capFaces_; }

  /// Every blending function that is non-zero at point p (in face f's frame, inside its
  /// rectangle), with derivatives when `derivatives` is 1 (first) or 2 (first and second).
  void basisAt(int face, const Eigen::Vector2d& p, std::vector<TSplineBasisValue>& out,
               int derivatives = 0) const;

  /// The surface of `control` (one row per blending function, any number of columns) with
  /// `weights` (one per function; empty means all 1) at p in face f's frame.
  TSplinePoint evaluate(const Eigen::MatrixXd& control, const Eigen::VectorXd& weights, int face,
                        const Eigen::Vector2d& p, int derivatives = 1) const;

  /// The same point computed the other way round: the blending functions' knots are moved into the
  /// face's frame (the inverse motions) instead of the point into their charts. Equal to evaluate
  /// up to rounding; `check` compares the two. A cap face has nothing to move: there it is
  /// evaluate's patch.
  TSplinePoint evaluateMovingKnots(const Eigen::MatrixXd& control, const Eigen::VectorXd& weights,
                                   int face, const Eigen::Vector2d& p) const;

 private:
  TMesh mesh_;
  std::vector<TSplineAnchor> anchors_;
  std::vector<int> anchorOfVertex_;
  std::vector<TSplineMissingAnchor> missing_;
  std::vector<std::vector<TSplinePiece>> pieces_;
  std::vector<TSplineCapFace> capFaces_;
  std::vector<int> capFaceOf_;  // per face: its entry of capFaces_, or -1
};

/// A face developed into some chart: the face and the motion from its frame into the chart.
struct DevelopedFace {
  int face = -1;
  QuarterMotion toChart;
};

/// The faces of `mesh` whose rectangles, developed from `start` (placed by `startToChart`) across
/// their sides, meet the box [lo, hi] of the chart (each distinct placement once), reached only
/// through faces that meet it. Closed box: touching counts (for rays, boxes of zero width). Open
/// box: only faces overlapping its interior, so that the development does not wind around an
/// extraordinary vertex on the box's boundary.
std::vector<DevelopedFace> developFaces(const TMesh& mesh, int start,
                                        const QuarterMotion& startToChart,
                                        const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                                        bool openBox = false);

/// developFaces for many developments of one mesh: the frame changes across all sides are worked
/// out once (developFaces costs a pass over the whole mesh per call). Not for use from several
/// threads at once (it keeps scratch space).
class FaceDeveloper {
 public:
  explicit FaceDeveloper(const TMesh& mesh);
  ~FaceDeveloper();
  std::vector<DevelopedFace> develop(int start, const QuarterMotion& startToChart,
                                     const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                                     bool openBox = false);
  class Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace mspline::spline
