#pragma once
// The limit surface of a Catmull-Clark control net, evaluated exactly (double precision) by
// OpenSubdiv's Far layer: the net is refined adaptively around extraordinary vertices, every
// regular region is a uniform bicubic B-spline patch, and the faces left irregular at the isolation
// level are approximated by Gregory patches (OpenSubdiv's end caps). This is the reference the
// project's own splines are compared against.
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace mspline::spline {

/// How the limit surface treats the boundary of an open net (OpenSubdiv's vertex boundary
/// interpolation).
enum class BoundaryRule {
  /// Faces touching a boundary vertex have no limit surface: the surface is only where the net
  /// defines it completely (on an nx x ny grid, the (nx-3)(ny-3) inner faces).
  None,
  /// The surface reaches the boundary edges; boundary curves are cubic B-splines of the boundary
  /// points, and corners (boundary vertices in one face) are smooth.
  EdgeOnly,
  /// As EdgeOnly, and the surface interpolates the corner points.
  EdgeAndCorner,
};

struct CatmullClarkOptions {
  /// Default EdgeAndCorner: an open net then has a surface over every face, reaching its corners,
  /// which is what users of modelling tools expect.
  BoundaryRule boundary = BoundaryRule::EdgeAndCorner;
  /// How many times faces at extraordinary vertices are refined (1 to 10) before the rest of
  /// them is approximated by Gregory patches; each level shrinks the approximated region to a
  /// quarter and makes setup slower and bigger (a 226k-quad net with extraordinary vertices in
  /// every face: 5.5, 8.8, 16.6 s and 1.4, 2.3, 4.2 GB peak at levels 1, 2, 3). Default 2,
  /// OpenSubdiv's own default approximation level for smooth features (Bfr::SurfaceFactory).
  int isolationLevel = 2;
};

/// A point on the limit surface of a patch face, with the derivatives in its (u, v).
struct LimitPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d du = Eigen::Vector3d::Zero();
  Eigen::Vector3d dv = Eigen::Vector3d::Zero();
  /// Second derivatives; computed only when asked for (evaluate's `secondDerivatives`), zero
  /// otherwise.
  Eigen::Vector3d duu = Eigen::Vector3d::Zero();
  Eigen::Vector3d duv = Eigen::Vector3d::Zero();
  Eigen::Vector3d dvv = Eigen::Vector3d::Zero();
};

/// A parameter point: patch face and (u, v) in [0,1]^2.
struct FaceParameter {
  int face = 0;
  double u = 0.0;
  double v = 0.0;
};

/// Batched evaluation results, one row per parameter point.
struct LimitPoints {
  /// Position and first derivatives; rows of points without a limit surface are NaN.
  Eigen::MatrixX3d position;
  Eigen::MatrixX3d du;
  Eigen::MatrixX3d dv;
  /// 1 where the point's face has a limit surface, 0 where it has none.
  std::vector<char> onSurface;
};

/// How the base faces of the net turned out.
struct FaceCounts {
  /// Faces whose limit is one uniform bicubic B-spline patch.
  int regular = 0;
  /// Faces with a limit surface made of refined patches and Gregory end caps (faces at an
  /// extraordinary vertex, non-quads).
  int irregular = 0;
  /// Faces without limit surface (at the boundary under BoundaryRule::None).
  int withoutSurface = 0;
};

/// Evaluates the Catmull-Clark limit surface of a fixed net topology; the control points can
/// change (updateControlPoints) without rebuilding the tables. Surface points are addressed by
/// patch face and (u, v) in [0,1]^2 (OpenSubdiv's ptex faces): a quad base face is one patch face
/// with (0,0) at its vertex 0, u running towards vertex 1 and v towards its last vertex; a base
/// face with n != 4 vertices is n patch faces, the k-th the quarter at its vertex k with (0,0)
/// there, (1,1) at the face centre, u towards vertex k+1 and v towards vertex k-1. For a net of
/// quads only, patch face f is base face f. Derivatives are those of the evaluated position: on
/// Gregory end caps the rational weights are differentiated exactly (OpenSubdiv's EvaluateBasis
/// approximates them, about 1% off), and on non-quads' sub-faces OpenSubdiv 3.5's derivative
/// scale (twice too large) is corrected. Const methods may run concurrently.
class CatmullClarkLimit {
 public:
  /// Builds the refined topology and patch tables of the net: `controlPoints` n x 3, `faces` as
  /// polygons of control point indices, consistently oriented. Throws InputError for an empty net,
  /// indices out of range, faces with fewer than 3 or repeated vertices, duplicate faces,
  /// non-manifold edges or vertices, inconsistent orientation, non-finite coordinates, points not
  /// n x 3, or an isolation level outside 1..10. Unreferenced control points are allowed.
  CatmullClarkLimit(const Eigen::MatrixXd& controlPoints,
                    const std::vector<std::vector<int>>& faces,
                    const CatmullClarkOptions& options = {});
  ~CatmullClarkLimit();
  CatmullClarkLimit(CatmullClarkLimit&&) noexcept;
  CatmullClarkLimit& operator=(CatmullClarkLimit&&) noexcept;

  /// Recomputes the refined and local points from new positions of the same control points
  /// (same count); the result equals rebuilding with them. Throws InputError for a wrong size or
  /// non-finite coordinates.
  void updateControlPoints(const Eigen::MatrixXd& controlPoints);

  /// The limit surface at (u, v) of patch face `face`, or nothing when that face has no limit
  /// surface. Throws InputError for a face out of range or (u, v) outside [0,1]^2 (or NaN).
  std::optional<LimitPoint> evaluate(int face, double u, double v,
                                     bool secondDerivatives = false) const;

  /// Position and first derivatives at every parameter point (as evaluate); returns how many lie
  /// on the surface. Checks every point as evaluate does before evaluating any.
  std::size_t evaluate(const std::vector<FaceParameter>& points, LimitPoints& out) const;

  int numControlPoints() const;
  int numBaseFaces() const;
  int numPatchFaces() const;
  /// Patch faces of base face f are firstPatchFace(f) .. firstPatchFace(f + 1) - 1 (f may be
  /// numBaseFaces()).
  int firstPatchFace(int baseFace) const;
  FaceCounts faceCounts() const;
  /// Points the patches are built on: refined vertices of every level and OpenSubdiv's local points
  /// (Gregory end caps).
  int numPatchPoints() const;
  const CatmullClarkOptions& options() const;

 private:
  struct Tables;
  std::unique_ptr<Tables> tables_;
};

}  // namespace mspline::spline
