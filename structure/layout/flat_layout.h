#pragma once
// Lays a flat metric with cone singularities out in the plane: cuts the surface into a disk through
// every cone and the homotopy loops, then places the disk triangle by triangle (trilateration).
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/mesh/polygon_soup.h"
#include "mspline/structure/mesh/tri_mesh.h"
#include "mspline/structure/ricci/curvature_target.h"

namespace mspline::structure {

struct FlatLayoutOptions {
  /// Interior vertices whose curvature in the metric exceeds this in absolute value (radians) are
  /// cones, and the cut is extended to reach them.
  double coneTolerance = 1e-6;
  /// Base vertex of the homotopy basis the cut is built from; -1 chooses one (see
  /// HomotopyBasisOptions).
  int baseVertex = -1;
};

/// How the layout across one cut edge continues the layout on the other side: the rigid motion
/// x -> R(angle) x + translation that maps the edge as laid out in `face0` onto the same edge as
/// laid out in `face1`.
struct SeamTransition {
  /// The cut edge (mesh edge index).
  int edge = -1;
  /// Faces of halfedge 0 and halfedge 1 of the edge.
  int face0 = -1;
  int face1 = -1;
  /// Rotation angle in (-pi, pi].
  double angle = 0.0;
  Eigen::Vector2d translation = Eigen::Vector2d::Zero();
  /// Distance between the motion's image of the edge's second endpoint and its twin (the first
  /// endpoint matches by construction), relative to the layout diameter.
  double residual = 0.0;
};

struct FlatLayout {
  /// Vertices of the disk: surface vertices are copied once per side of the cut they touch.
  /// `chartPositions` row k is the plane position of copy k, `chartSourceVertex[k]` the surface
  /// vertex it copies.
  Eigen::MatrixXd chartPositions;
  std::vector<int> chartSourceVertex;
  /// Corner k (0, 1, 2) of face f is row 3f + k: the to-vertex of the k-th halfedge counted from
  /// halfedge_handle(f), i.e. the k-th vertex of the face's vertex circulator.
  std::vector<int> cornerCopy;
  /// Per-corner positions (3 rows per face, as cornerCopy): chartPositions of the corner's copy.
  Eigen::MatrixXd cornerUV;
  /// For every halfedge inside a face (by idx()): the direction angle of its edge, from its
  /// from-vertex to its to-vertex, as laid out in its face. Summed from the metric's angles, so
  /// exact up to rounding even where the edge is too short for positions to tell its direction.
  Eigen::VectorXd halfedgeDirection;
  /// Sorted interior mesh edges the surface was cut along (empty for a disk without cones).
  std::vector<int> cutEdges;
  /// Interior vertices with non-zero curvature in the metric (cone angle 2 pi - curvature).
  std::vector<Cone> cones;
  /// Face the trilateration started from (central in the disk's dual graph).
  int rootFace = -1;
  /// Faces whose signed layout area is <= 0.
  int flippedTriangles = 0;
  /// max |layout edge length - metric length| / metric length over all face edges.
  double maxEdgeLengthError = 0.0;
  /// max |layout corner angle - metric corner angle|: how faithfully the layout realizes the
  /// metric (round-off only, for a valid flat metric).
  double maxLayoutAngleError = 0.0;
  /// Mean and max of |metric corner angle - input corner angle| over all corners: the angle
  /// distortion of the flattening (zero for a conformal map in the smooth limit).
  double meanAngleDistortion = 0.0;
  double maxAngleDistortion = 0.0;
  /// Layout area / input area per face (for vertex scaling about exp(2u)): min, max, mean.
  double minAreaRatio = 0.0;
  double maxAreaRatio = 0.0;
  double meanAreaRatio = 0.0;
  /// Diagonal of the layout's bounding box.
  double diameter = 0.0;
  /// One transition per cut edge, in the order of cutEdges.
  std::vector<SeamTransition> seams;
  /// max residual over the seams.
  double maxSeamResidual = 0.0;
  /// Closed genus 1 without cones: the deck translations of the universal cover, from the two
  /// homotopy loops (the seam transition at each loop's closing edge).
  bool hasPeriods = false;
  std::array<Eigen::Vector2d, 2> periods = {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  /// The parallelogram spanned by the periods at the first copy of the base vertex, in order
  /// o, o + p0, o + p0 + p1, o + p1.
  std::array<Eigen::Vector2d, 4> fundamentalParallelogram = {
      Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(),
      Eigen::Vector2d::Zero()};
  /// With periods: every seam translation rounded to an integer combination m p0 + n p1; the max
  /// over seam edge endpoints of |position + m p0 + n p1 - twin position| / diameter.
  double maxPeriodResidual = 0.0;
};

/// Lays out the metric given by `edgeLengths` (by edge index, e.g. RicciResult::edgeLengths).
/// Throws InputError for lengths of the wrong size or not positive, TopologyError for a mesh that
/// is not a connected manifold. A metric that is not flat away from its cones, or that violates
/// the triangle inequality, is laid out anyway and shows in the error and flip statistics.
FlatLayout layoutFlatMetric(const TriMesh& mesh, const Eigen::VectorXd& edgeLengths,
                            const FlatLayoutOptions& options = {});

/// `mesh` as a polygon soup (named `sourceName`) carrying the layout's per-corner UVs.
PolygonSoup soupWithCornerUVs(const TriMesh& mesh, const FlatLayout& layout,
                              const std::string& sourceName);

}  // namespace mspline::structure
