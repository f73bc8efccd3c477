#pragma once
// The affine atlas of a flat metric with cone singularities (paper sections 1.1 and 4.2): charts
// covering the surface minus the cones, with rigid transition maps.
//
// Chart design: one chart per vertex that is not a cone, on its closed star (the faces around it).
// The star is laid out isometrically from the metric, starting from one of its faces where the
// global layout (FlatLayout) put it and turning around the vertex by the metric's angles, so
// charts are oriented like the layout: inside the cut disk the transitions are translations, and
// across a seam they rotate as the seam does (quarter turns for quantized cones, none for a flat
// torus). Two charts overlap exactly when their vertices share an edge; every point of a face with
// a vertex that is no cone lies in that vertex's chart, so with at least one non-cone vertex per
// face the charts cover the surface minus the cones. Stars are small, which keeps every chart an
// embedding; a larger neighbourhood is reached by composing transitions (developing).
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/core/surface_point.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/mesh/tri_mesh.h"
#include "mspline/structure/ricci/curvature_target.h"

namespace mspline::structure {

/// A rigid motion x -> R(angle) x + translation of the plane.
struct RigidMotion {
  double angle = 0.0;
  Eigen::Vector2d translation = Eigen::Vector2d::Zero();

  Eigen::Vector2d operator()(const Eigen::Vector2d& x) const;
  /// this after `first`: x -> this(first(x)).
  RigidMotion after(const RigidMotion& first) const;
  RigidMotion inverse() const;
};

struct Chart {
  /// The vertex whose star this is.
  int vertex = -1;
  /// The star's faces, in turning order around the vertex.
  std::vector<int> faces;
  /// The star's vertices (the centre first) and their planar coordinates, column by column.
  std::vector<int> vertices;
  Eigen::Matrix2Xd positions;
  /// Position of vertex w in this chart; InternalError if w is not in the star.
  Eigen::Vector2d position(int w) const;
  /// Whether w is a vertex of the star.
  bool contains(int w) const;
};

/// The transition from chart `from` to chart `to` (charts of adjacent vertices).
struct Transition {
  int from = -1;
  int to = -1;
  RigidMotion motion;
  /// max |motion(x_from) - x_to| over the vertices of the faces both charts contain (the two
  /// faces of the edge joining their vertices), relative to the atlas diameter.
  double residual = 0.0;
};

enum class TransitionKind {
  /// All rotation angles 0: an affine structure (flat torus without cones).
  Translation,
  /// All rotation angles multiples of pi/2 (quantized cones).
  Rotation90,
  /// Other rotations.
  Rigid,
};
const char* transitionKindName(TransitionKind kind);

struct AffineAtlas {
  /// Charts, and for every vertex the index of its chart (-1 at cones).
  std::vector<Chart> charts;
  std::vector<int> chartOfVertex;
  /// One transition per edge whose two vertices have charts, from the lower chart index.
  std::vector<Transition> transitions;
  /// The cones (vertices without a chart), with their curvature in the metric.
  std::vector<Cone> cones;
  /// Diagonal of the global layout: the scale residuals are measured against.
  double diameter = 0.0;
  /// max Transition::residual.
  double maxTransitionResidual = 0.0;
  /// max over faces with three charts of |T_ca(T_bc(T_ab(x))) - x| over the face's vertices,
  /// relative to the diameter: the cocycle condition.
  double maxCocycleResidual = 0.0;
  /// Sum of |curvature| over the interior vertices that are not cones: the metric is flat there
  /// only to the solver's tolerance, and a transition's angle can be off by at most this much
  /// (the curvature its path encloses), so the kind is judged up to it.
  double flatnessDefect = 0.0;
  /// The coarsest kind all transitions fit (angles within angleTolerance + flatnessDefect of the
  /// kind's).
  TransitionKind kind = TransitionKind::Rigid;
  /// max distance of a transition angle from its kind's angles (radians).
  double maxKindAngleError = 0.0;
  /// Faces whose three vertices are all cones: their interior lies in no chart.
  int uncoveredFaces = 0;

  /// Index into `transitions` of the transition between the charts of vertices a and b
  /// (either order), -1 if they are not adjacent or one is a cone.
  int transitionIndex(int a, int b) const;
  /// The rigid motion from the chart of vertex a to the chart of vertex b (adjacent vertices).
  RigidMotion transition(int a, int b) const;
};

struct AffineAtlasOptions {
  /// Interior vertices with |curvature| above this (radians) are cones and get no chart.
  double coneTolerance = 1e-6;
  /// A transition angle within this plus AffineAtlas::flatnessDefect of 0 (or of a multiple of
  /// pi/2) counts as such.
  double angleTolerance = 1e-9;
};

/// Builds the atlas of the flat metric `flatLengths` (by edge index) on `mesh`, with charts
/// oriented like `layout` (layoutFlatMetric of the same mesh and lengths). InputError on sizes
/// that do not match.
AffineAtlas buildAffineAtlas(const TriMesh& mesh, const Eigen::VectorXd& flatLengths,
                             const FlatLayout& layout, const AffineAtlasOptions& options = {});

/// Recomputes the figures of an atlas from its charts and transitions (residuals, cocycle, kind,
/// coverage), e.g. after reading it back. InputError when it does not fit the mesh.
void measureAtlas(const TriMesh& mesh, AffineAtlas& atlas, const AffineAtlasOptions& options = {});

/// The flat metric the atlas carries: every edge's length in a chart containing it (a chart of an
/// end, or of a vertex opposite it). InputError when an edge lies in no chart.
Eigen::VectorXd atlasEdgeLengths(const TriMesh& mesh, const AffineAtlas& atlas);

/// A point of a face (barycentric coordinates) in one chart.
struct ChartPoint {
  int chart = -1;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
};

/// Every chart containing the point of `face` with `barycentric` coordinates, with its
/// coordinates there (the charts of the face's non-cone vertices).
std::vector<ChartPoint> chartsContaining(const TriMesh& mesh, const AffineAtlas& atlas, int face,
                                         const Eigen::Vector3d& barycentric);

/// Point location in a chart: the face of chart `chart` containing planar point x and its
/// barycentric coordinates (face -1 when x lies outside the star). Points on a shared edge go to
/// the first face found.
SurfacePoint locateInChart(const TriMesh& mesh, const AffineAtlas& atlas, int chart,
                           const Eigen::Vector2d& x, double tolerance = 1e-12);

/// Holonomy of the closed vertex loop v0, v1, ..., v_k-1, back to v0 (consecutive vertices
/// adjacent, none a cone): the composed transitions, a map of chart v0 to itself. A loop turning
/// counter-clockwise (with the faces' orientation) around a single cone rotates by the cone's
/// curvature; around no cone it is the identity; along a non-contractible loop of a flat torus it
/// is a deck translation.
RigidMotion holonomy(const AffineAtlas& atlas, const std::vector<int>& loop);

/// Whether two atlases have the same charts (vertices and positions) and the same transition
/// motions, exactly (e.g. an atlas and the one read back from its file).
bool identicalAtlases(const AffineAtlas& a, const AffineAtlas& b);

}  // namespace mspline::structure
