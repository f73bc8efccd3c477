#pragma once
// How good a spline surface is, measured the way a user judges it: how far it is from the scan
// both ways (exact closest points), whether it folds over (against the scan's normals, or between
// neighbouring triangles), how smooth it is (dihedral angles of its tessellation at two
// resolutions: halving the sample spacing halves them where the surface is C1, not at a crease)
// and how regular its parametrization is (the smallest area element met).
//
// Everything is measured where export keeps the surface: faces over the scan's fill patches
// (SplineModel::surfaceFaceFilled, filled_faces.h) are left out.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/core/spline_model.h"
#include "mspline/spline/model/model_surface.h"
#include "mspline/structure/core/progress.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::spline {

struct QualityOptions {
  /// Samples along every side of every face of the coarser of the two tessellations measured
  /// (ModelSurface::tessellate); the finer one has twice as many. The coarser one gives the folds;
  /// the finer one is the surface sampled against the scan. Default 3: the acceptance of issue 18
  /// compares resolutions 3 and 6.
  int resolution = 3;
  /// A pair of adjacent triangles whose normals differ by more than this many degrees (at
  /// `resolution`) counts as a crease (SurfaceSmoothness::creases).
  double creaseDegrees = 30.0;
  /// Newton steps at most per closest point on the spline surface (each from the closest point of
  /// the finer tessellation; spline/fitting/surface_fit.h's projectOntoSurface).
  int newtonSteps = 12;
  /// Keep the per-sample figures (SurfaceQuality::details) for callers that act on them, such as
  /// a refinement loop.
  bool details = false;
  /// Name the model and the scan in messages.
  std::string name = "model";
  std::string scanName = "scan";
};

/// A point of the surface: where it is in space and on the model's parameter domain.
struct SurfaceLocation {
  /// Position in space (NaN when there is none: nothing measured).
  Eigen::Vector3d position = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  /// Face of the model's parameter domain (T-mesh face, or domain face of a triangular B-spline
  /// in FitSpace terms) and position in that face's frame; face -1 when there is none. For a
  /// triangle or an edge of a tessellation, the parameter of its first vertex.
  FacePoint parameter;
};

/// The spread of a set of distances, relative to the scan's bounding-box diagonal.
struct DistanceSpread {
  /// How many distances were measured.
  int count = 0;
  /// Root mean square, 99th percentile (the smallest distance that at least 99% do not exceed)
  /// and maximum.
  double rms = 0.0, p99 = 0.0, max = 0.0;
  /// Where the maximum is: on the surface (its closest point to the scan vertex for scan to
  /// surface; the surface sample for surface to scan).
  SurfaceLocation maxAt;
};

/// Distances both ways by exact closest points, relative to the scan's bounding-box diagonal.
struct SurfaceDistances {
  /// The scan's bounding-box diagonal (the unit of the spreads).
  double diagonal = 0.0;
  /// Every scan vertex to its closest point on the spline surface (closestSurfacePoints from the
  /// finer tessellation and, for the T-mesh kinds, from the vertex's parameters in the model,
  /// SplineModel::surfaceVertexTMeshPoints: what the fit found). The surface includes the parts
  /// over fill patches, where the surface also is. Vertices of the model's fill patches are not the
  /// scan's and not measured.
  DistanceSpread scanToSurface;
  /// Every vertex of the finer tessellation over the scan to its closest point on the scan's
  /// triangles.
  DistanceSpread surfaceToScan;
  /// Scan vertices whose closest point is not converged (ClosestSurfacePoint::converged): their
  /// distance is the best one met, an upper bound.
  int unconvergedProjections = 0;
};

/// Folds: where the surface turns over.
struct SurfaceFolds {
  /// Triangles of the coarser tessellation (over the scan) whose normal makes more than 90 degrees
  /// with the scan's normal at the closest scan point to their centroid (the normal of the scan
  /// triangle there; on a scan edge or vertex, the closest of the normals of the triangles holding
  /// it), out of `triangles`; 0 without a scan. Where the scan itself folds, a scan triangle has
  /// no one normal: one flipped, folded by more than 90 degrees against most of its neighbours,
  /// takes the closest of its own and its neighbours'; one folded against some neighbours (a
  /// crumpled fin) the closest of its own and those of its neighbours but the flipped ones' whose
  /// shared edge is within the tessellation triangle's longest edge of the closest point (a smooth
  /// surface rounds a fold off; farther along the scan than its triangle reaches, it turns with
  /// the scan or folds).
  int againstScan = 0;
  /// Triangles facing more than 90 degrees away from the normal of every scan triangle holding
  /// their closest scan point that the rule above accepts because the scan folds there (not in
  /// total()): elk.off's fitted surface runs smoothly past a crumpled fin of its scan, and all 18
  /// of its folds were there.
  int atScanFolds = 0;
  int triangles = 0;
  /// againstScan / triangles.
  double fraction = 0.0;
  /// The triangle whose normal makes the largest angle with the scan's, when againstScan > 0, and
  /// that angle in degrees.
  SurfaceLocation worstAgainstScan;
  double worstAgainstScanDegrees = 0.0;
  /// Adjacent triangle pairs of the coarser tessellation whose normals differ by more than 90
  /// degrees, and where the sharpest one is (the midpoint of the shared edge).
  int adjacentPairs = 0;
  SurfaceLocation worstPair;
  /// againstScan + adjacentPairs: no folds when 0.
  int total() const { return againstScan + adjacentPairs; }
};

/// Dihedral angles (angle between the normals of two triangles sharing an edge, in degrees) over
/// every interior edge of one tessellation.
struct DihedralPercentiles {
  /// Samples per face side, and adjacent pairs measured.
  int resolution = 0;
  int pairs = 0;
  double p50 = 0.0, p99 = 0.0, p999 = 0.0, max = 0.0;
  /// The shared edge's midpoint of the largest angle.
  SurfaceLocation maxAt;
};

struct SurfaceSmoothness {
  /// At QualityOptions::resolution r and at 2r.
  DihedralPercentiles coarse, fine;
  /// coarse.p99 / fine.p99: about 2 where the surface is C1 (the angles halve with the spacing),
  /// about 1 at a crease or fold (they do not). Empty when fine.p99 is below kFlatDegrees: 99%
  /// of the pairs are flat to round-off, and a quotient of round-offs says nothing.
  std::optional<double> p99Ratio;
  /// Dihedral angles below this (degrees) are round-off of a plane's normals.
  static constexpr double kFlatDegrees = 1e-6;
  /// Adjacent pairs of the coarser tessellation whose dihedral angle exceeds creaseDegrees
  /// (QualityOptions::creaseDegrees).
  int creases = 0;
  double creaseDegrees = 0.0;
};

/// How regular the parametrization is: J = |S_s x S_t|, the area element of the surface over the
/// frame of the sample's face (T-mesh faces are in knot units, so refinement does not change it),
/// at every vertex of the coarser tessellation where the surface has first derivatives (not at the
/// samples that stand for a cone's hole).
struct SurfaceRegularity {
  /// Samples measured.
  int samples = 0;
  /// The median of J over the samples (area in space per unit area of the frames).
  double medianJacobian = 0.0;
  /// The smallest J met relative to medianJacobian: the area in space of the smallest cell
  /// relative to a typical cell of the same size in the frames (1 for a uniform parametrization,
  /// 0 where the surface is singular).
  double minRelativeJacobian = 0.0;
  /// Where the smallest J is.
  SurfaceLocation minAt;
};

/// Per-sample figures, when QualityOptions::details is set.
struct QualityDetails {
  /// Per scan vertex: its distance to the surface (absolute, NaN when not measured) and its
  /// closest point's parameter.
  Eigen::VectorXd scanDistances;
  std::vector<FacePoint> scanClosest;
  /// The finer tessellation's samples measured against the scan: their parameters and their
  /// distances to the scan (absolute).
  std::vector<FacePoint> surfaceSamples;
  Eigen::VectorXd surfaceDistances;
  /// Parameters of the centroids of the folded triangles (againstScan) and of the shared edges'
  /// midpoints of the folded pairs (adjacentPairs).
  std::vector<FacePoint> folds;
};

struct SurfaceQuality {
  /// Measured against a scan: `distances` and SurfaceFolds::againstScan are set.
  bool withScan = false;
  SurfaceDistances distances;
  SurfaceFolds folds;
  SurfaceSmoothness smoothness;
  SurfaceRegularity regularity;
  /// Per-sample figures (QualityOptions::details), else empty.
  QualityDetails details;
  /// Wall-clock seconds the measurement took.
  double seconds = 0.0;
};

/// The quality of the surface of `model` with control points `control` (numControlPoints x 3),
/// whose space `surface` was built from `model` (the fit loop keeps it and changes only the
/// control points), optionally against `scan` (null: no distances, no folds against the scan).
/// `model` supplies the fills to leave out (surfaceFaceFilled with its surface mesh and vertex
/// parameters); its own controlPoints are not used. The scan must be the one the model was fitted
/// to: the model's surface starts with the scan's vertices. Throws InputError naming
/// options.scanName when it does not, naming options.name when the control points do not fit the
/// space.
SurfaceQuality measureQuality(const SplineModel& model, const ModelSurface& surface,
                              const Eigen::MatrixXd& control, const structure::TriMesh* scan,
                              const QualityOptions& options = {},
                              const structure::Progress& progress = {});

/// measureQuality of a loaded model with its own control points (builds its space).
SurfaceQuality measureQuality(const SplineModel& model, const structure::TriMesh* scan,
                              const QualityOptions& options = {},
                              const structure::Progress& progress = {});

/// A point's closest point on a spline surface.
struct ClosestSurfacePoint {
  /// Found by Newton's method on the spline; false where the spline is undefined at every start
  /// (around a cone's hole): then the closest point of the tessellation, with the parameter of a
  /// corner of its triangle.
  bool onSpline = false;
  /// The distance, the closest point's parameter and position.
  double distance = std::numeric_limits<double>::quiet_NaN();
  FacePoint parameter;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  /// A critical point of the distance: the offset along the surface normal to 1e-3 rad (the
  /// distance then within 5e-7 of it of the local minimum's), or the point on the surface to 1e-9
  /// of the tessellation's bounding-box diagonal; true where the surface is singular (no normal).
  bool converged = true;
};

/// The closest points of `points` (rows) on the surface of `surface` with control points
/// `control`, on all cores: Newton's method (spline/fitting/surface_fit.h's projectOntoSurface,
/// `newtonSteps` at most) from the closest point of `tessellation` (a tessellation of that surface:
/// its triangle's nearest corner that is a surface point, the closest point's parameter
/// interpolated from the corners when they lie in one face, the other corners) and from starts[k]
/// when k < starts.size(), in that order until one converges; the nearest point found.
std::vector<ClosestSurfacePoint> closestSurfacePoints(const ModelSurface& surface,
                                                      const Eigen::MatrixXd& control,
                                                      const ModelTessellation& tessellation,
                                                      const Eigen::MatrixX3d& points,
                                                      const std::vector<FacePoint>& starts = {},
                                                      int newtonSteps = 12);

/// Per triangle of `tessellation`, 1 when a neighbour across an edge has a normal that differs
/// from its own by more than `creaseDegrees`: the creases, and the folds between neighbours (above
/// 90 degrees), that export marks in its pictures.
std::vector<char> creasedFaces(const structure::PolygonSoup& tessellation, double creaseDegrees);

}  // namespace mspline::spline
