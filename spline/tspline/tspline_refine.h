#pragma once
// Local refinement of cubic T-splines (in the spirit of Sederberg, Cardon, Finnigan, North, Zheng
// and Lyche 2004): faces of the T-mesh are cut by new edges, and the control points and weights
// are recomputed so that the rational surface does not change.
//
// The new coefficients are found as a linear problem rather than by Sederberg's blending-function
// bookkeeping: the old numerator sum_i w_i c_i N_i and denominator sum_i w_i N_i, restricted to the
// blending functions whose knots changed, are sampled on the Bezier elements of the faces they
// cover (16 points per bicubic piece determine it) and expressed in the new blending functions
// whose knots are new or changed, by least squares with column-pivoting QR. Functions whose knots
// did not change keep their coefficients. Where the new space does not contain the old surface
// (the residual stays above the tolerance), the inserted edges are extended across one more face
// at each open end (their T-junctions) and the problem is solved again; this is how Sederberg's
// algorithm resolves violations, by adding the knots that the refined blending functions need.
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/tspline/tmesh.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_cap.h"

namespace mspline::spline {

/// Cuts face `face` of `mesh` by the line x = coordinate (axis 0) or y = coordinate (axis 1) of its
/// frame, strictly inside it. The cut's endpoints become vertices on the face's sides: an existing
/// boundary vertex within 1e-9 of the face size is reused (and the cut moved onto it), otherwise a
/// new vertex is appended (ids numVertices, numVertices + 1) and inserted into the side of the
/// neighbouring face too, as a new T-junction. The part of the face at its frame's origin keeps the
/// id `face` and the frame; the other part is appended as face numFaces(), its frame translated by
/// `coordinate` along the axis. Throws InputError for a face out of range, an axis other than 0 or
/// 1, or a coordinate not strictly inside the face.
TMesh splitFace(const TMesh& mesh, int face, int axis, double coordinate);

/// The faces to split into four (each cut through its middle both ways) so that every cone keeps
/// a cap (tspline_cap.h): `faces`, then for each cone whose region (its 3 x 3 cells a sector)
/// holds one of them or shares a side with one, its cells within 2 of it, until no further region
/// is touched. Split, those cells hold the cap at half the cell size. `regions` are `mesh`'s
/// (capRegions, which throws SolverError when a cone has no cap), computed once by callers that
/// try several sets of faces.
std::vector<int> withTouchedCapsSplit(const TMesh& mesh,
                                      const std::vector<TSplineCapRegion>& regions,
                                      std::vector<int> faces);

/// Splits each of `faces` (distinct) into four through its middle, giving the mesh that splitting
/// them one after the other would (splitFace along x, then both halves along y), with one rebuild:
/// face f keeps its lower left quarter, the i-th face listed appends its lower right, upper left
/// and upper right quarters as faces numFaces() + 3i, + 3i + 1, + 3i + 2, and the new vertices are
/// numbered in the order of those splits. `points` on a face follow its quarters (positions in the
/// quarter's frame). Throws InputError for a face out of range or listed twice.
void splitIntoFour(TMesh& mesh, const std::vector<int>& faces, std::vector<FacePoint>& points);

/// Refines around the extraordinary vertices that have no cap (tspline_cap.h: another cone, a
/// boundary or a T-junction within kCapCells = 3 cells, cells of other sizes): the faces within 2
/// cells of each are split into four, halving the distances in cells, until every cone has a cap or
/// `maxRounds` rounds are done (then TSplineSpace will say which cone has none). `points` follow
/// their faces. Returns the faces split.
int refineAroundCones(TMesh& mesh, std::vector<FacePoint>& points, int maxRounds = 4);

/// One cut, as taken by splitFace.
struct FaceSplit {
  int face = -1;
  int axis = 0;
  double coordinate = 0.0;
};

struct RefineOptions {
  /// The refined surface is accepted when the residual (TSplineRefinement::residual) is at most
  /// this.
  double tolerance = 1e-12;
  /// At most this many rounds of extending the cuts' open ends by one face each (0: never extend).
  int maxExtensionRounds = 16;
};

/// Where a face of the refined T-mesh lies in the input T-mesh: the point p of its frame is the
/// point p + offset of input face `face`'s frame (cuts only translate frames).
struct RefinedFaceOrigin {
  int face = -1;
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();
};

struct TSplineRefinement {
  /// The blending functions of the refined T-mesh (its mesh(): input faces keep their ids, as in
  /// splitFace; vertices of the input keep their ids, new ones follow).
  TSplineSpace space;
  /// One row per blending function of `space` (as many columns as the input control points) and
  /// its weight. Where a weight came out 0 the control row is 0 (see minWeight).
  Eigen::MatrixXd control;
  Eigen::VectorXd weights;
  /// Per face of the refined T-mesh: where it lies in the input T-mesh.
  std::vector<RefinedFaceOrigin> faceOrigin;
  /// Faces cut beyond the requested splits, extending their open ends, and in how many rounds.
  int extraSplits = 0;
  int extensionRounds = 0;
  /// Blending functions of the input whose knots changed (re-expressed), and new blending functions
  /// solved for (unknowns of the least-squares problem) in the final round.
  int changedFunctions = 0;
  int unknowns = 0;
  /// Samples (Bezier element points) of the final least-squares problem.
  int samples = 0;
  /// max over the samples of |new - old| of the homogeneous surface (numerator coordinates and
  /// denominator), divided by the largest |w_i c_i| or |w_i| of the input: 0 up to rounding when
  /// the refined space contains the input surface.
  double residual = 0.0;
  /// residual <= RefineOptions::tolerance. When false, control and weights are the least-squares
  /// best fit of the last round, and the surface has changed by about `residual`.
  bool converged = false;
  /// The smallest new weight (positive input weights give positive weights on analysis-suitable
  /// T-meshes; a weight <= 0 means the refined rational surface has a pole or a hole there).
  double minWeight = 0.0;
};

/// Applies `splits` in order (each to the T-mesh left by the previous ones, so face ids follow
/// splitFace's numbering) and re-expresses the surface of `control` (one row per blending function
/// of `space`) and `weights` (one per function, or empty for all 1) in the refined space, extending
/// the cuts as described above until the surface is reproduced, the rounds run out or no cut has an
/// open end left (every cut runs from boundary to boundary or closes on itself). Throws
/// InputError for sizes that do not match `space` or a split splitFace rejects (naming it).
TSplineRefinement refine(const TSplineSpace& space, const Eigen::MatrixXd& control,
                         const Eigen::VectorXd& weights, const std::vector<FaceSplit>& splits,
                         const RefineOptions& options = {});

}  // namespace mspline::spline
