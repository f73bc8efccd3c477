#pragma once
// A coarse triangulation of a flat metric with cone singularities, by intrinsic coarsening.
//
// The fine surface with its flat edge lengths is an intrinsic triangulation. Every vertex that is
// not kept (all cones are; the rest are chosen by farthest-point sampling in the flat metric) is
// removed: Euclidean edge flips at it (the new diagonal's length from laying the two triangles out
// in the plane; only strictly convex quadrilaterals) bring it to degree 3, and its three triangles
// then merge into one flat triangle, since a flat vertex lies inside the triangle of its three
// neighbours. The flips that bring a vertex to degree 3 are chosen as in Devillers' Delaunay
// deletion (the ear whose circumcircle has the smallest power with respect to the vertex). A vertex
// stuck at degree 4 on the straight segment between two neighbours (common on grids, where every
// flip would leave a degenerate triangle) has its four triangles merged into two instead. With
// `delaunay` the triangulation is kept intrinsically Delaunay throughout (Lawson flips of the fine
// surface first, then around every removal), so the result is the intrinsic Delaunay
// triangulation of the kept vertices and no intermediate triangle is thinner than it must be.
//
// Every removed vertex is tracked as a face and barycentric coordinates of the current
// triangulation: placed by the areas of its three triangles when it is removed, re-expressed at
// every flip (by laying out the quadrilateral) and every merge. Each face keeps the list of the
// points inside it, so the work is local.
//
// The result may be a Delta-complex rather than a simplicial complex (two faces sharing two
// sides, an edge from a vertex to itself), so it is stored as faces with side adjacency.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/core/surface_point.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct CoarseningOptions {
  /// Coarse vertices wanted: every cone, then farthest-point samples until there are this many
  /// (more when there are more cones; at most every vertex). At least 1.
  int targetVertices = 1000;
  /// Vertices whose curvature 2 pi - angle sum exceeds this in absolute value (radians) are cones
  /// and always kept.
  double coneTolerance = 1e-6;
  /// Keep the triangulation intrinsically Delaunay (Euclidean criterion on the lengths): the
  /// result is the intrinsic Delaunay triangulation of the kept vertices. Without it only the
  /// flips that vertex removal needs are made; coarse triangles may then be thin, which costs
  /// tracking accuracy (maxTrackingError on knot1.off with 300 vertices: 2e-9 instead of 3e-11,
  /// up to 6e-8 with 10), and with very few kept vertices some others may not be removable.
  bool delaunay = true;
  /// Per fine vertex: the wanted relative density of coarse vertices (finite, positive), or empty
  /// for uniform. Farthest-point sampling then measures distances in units of the local spacing
  /// h(v) = 1 / sqrt(density(v)): it keeps the vertex with the largest distance * sqrt(density),
  /// so a region of higher density gets proportionally more coarse vertices per unit area.
  Eigen::VectorXd density;
  /// Seed of the random order in which vertices are removed (a random order keeps the faces of
  /// every intermediate triangulation of similar size).
  unsigned seed = 1;
  /// Keep no side between two cones: where the result has one, the fine vertex nearest its
  /// midpoint is kept too and the coarsening made again (a few rounds at most). Splines need it:
  /// a side between two cones has knot clouds of neither cone across it.
  bool separateCones = false;
};

struct CoarseTriangulation {
  /// Coarse vertex k is fine vertex vertices[k] (ascending fine indices).
  std::vector<int> vertices;
  /// Per fine vertex: its coarse vertex index, -1 when it was removed.
  std::vector<int> coarseVertex;
  /// Per coarse face: its corners (coarse vertex indices), counter-clockwise in the surface's
  /// orientation. A vertex may appear twice in a face.
  std::vector<std::array<int, 3>> faces;
  /// Side k of face f joins corners k and k + 1 (mod 3); its length in the flat metric.
  std::vector<std::array<double, 3>> sideLengths;
  /// Across side k of face f lie face neighbour[f][k] and its side neighbourSide[f][k] (the same
  /// edge, traversed the other way). A face may be its own neighbour.
  std::vector<std::array<int, 3>> neighbour;
  std::vector<std::array<int, 3>> neighbourSide;
  /// Per coarse vertex: 2 pi - angle sum in the coarse triangulation.
  std::vector<double> curvature;
  /// Per fine vertex: where it lies in the coarse triangulation. A kept vertex is a corner of a
  /// face (barycentric coordinates a unit vector).
  std::vector<SurfacePoint> fineVertices;
  /// The fine surface's flat edge lengths (by edge idx()), which locateOnCoarse measures with.
  Eigen::VectorXd fineLengths;

  /// Per coarse vertex: 1 when it is a cone (|fine curvature| > coneTolerance).
  std::vector<char> isCone;
  /// Fine vertices removed.
  int removedVertices = 0;
  /// Fine vertices that were to be removed but could not be (no strictly convex flip lowering
  /// the degree and not the straight degree-4 case, even after the others went); they are coarse
  /// vertices too.
  std::vector<int> unremovedVertices;
  /// Flips made to bring vertices to degree 3, and Delaunay flips (fine surface and restoring).
  long removalFlips = 0;
  long delaunayFlips = 0;
  /// max over fine edges of |distance between its endpoints measured on the coarse triangulation
  /// from their locations - flat length| / flat length: the coarse faces are developed from one
  /// endpoint (developFromPoint, radius 1.5 flat lengths) and, of the straight segments reaching
  /// the other, the one closest in length counts (infinite when none does).
  double maxTrackingError = 0.0;
  /// max over coarse vertices of |coarse curvature - fine curvature| (radians).
  double maxCurvatureError = 0.0;
  /// Every vertex that was not kept has been removed (unremovedVertices is empty).
  bool complete = false;
  /// With separateCones: vertices kept to separate cones, and sides still joining two cones.
  int separatingVertices = 0;
  int coneSides = 0;
};

/// Coarsens the closed surface `surface` with the flat metric `flatLengths` (by edge idx(); flat
/// away from its cones, e.g. RicciResult::edgeLengths or the overlay's). Throws InputError for
/// lengths of the wrong size, not positive or violating a triangle inequality and for bad options,
/// TopologyError for a surface with boundary or several components.
CoarseTriangulation coarsenFlatMetric(const TriMesh& surface, const Eigen::VectorXd& flatLengths,
                                      const CoarseningOptions& options = {});

/// One coarse face laid out in the plane by developFromPoint.
struct DevelopedFace {
  /// Coarse face.
  int face = -1;
  /// Positions of its corners 0, 1, 2 in the plane (counter-clockwise).
  std::array<Eigen::Vector2d, 3> corners;
  /// The directions (angles, radians) of the rays from the origin through which this copy is
  /// seen: [fromAngle, toAngle], at most 2 pi wide, possibly outside (-pi, pi].
  double fromAngle = 0.0;
  double toAngle = 0.0;
};

/// The coarse faces seen from `origin` along straight rays of length at most `radius`, laid out in
/// one plane with the origin at (0, 0): the geodesic disk developed across sides, one copy per
/// chain of faces a ray crosses (so a face appears several times around a cone, around a vertex
/// near the origin, or when the disk wraps around a handle). When the origin is a coarse vertex
/// (a barycentric coordinate within 1e-12 of 1) the faces around it are laid out around (0, 0)
/// first. A point of the surface at position x in a copy whose directions contain x's is reached
/// from the origin by a straight segment of length |x| (sightingsOfFineVertex finds fine vertices
/// so). Throws InputError for a face out of range, InternalError when the development does not end
/// (inconsistent adjacency).
std::vector<DevelopedFace> developFromPoint(const CoarseTriangulation& coarse,
                                            const SurfacePoint& origin, double radius);

/// The positions of fine vertex `fineVertex` in `development` (from developFromPoint) that a
/// straight segment from the origin reaches: the distances to them are lengths of straight
/// segments on the surface. Several when different segments reach it (around a cone or a handle).
std::vector<Eigen::Vector2d> sightingsOfFineVertex(const CoarseTriangulation& coarse,
                                                   const std::vector<DevelopedFace>& development,
                                                   int fineVertex);

/// Locates the point of fine face `fineFace` with barycentric coordinates `barycentric` (fv_range
/// order, as SurfacePoint) on the coarse triangulation: the coarse faces are developed from a
/// vertex of the fine face that is not a cone (preferably a removed one, inside a coarse face),
/// the other two vertices are found where their distances match the fine face's flat lengths,
/// and the point is located in the fine triangle so laid out. Throws InputError for a face out
/// of range, coordinates not >= 0 with sum 1, or a coarse triangulation of another surface,
/// InternalError when the construction is inconsistent (a vertex not found or the laid-out fine
/// triangle not matching its lengths).
SurfacePoint locateOnCoarse(const TriMesh& surface, const CoarseTriangulation& coarse, int fineFace,
                            const Eigen::Vector3d& barycentric);

}  // namespace mspline::structure
