#pragma once
// Polynomial caps at the extraordinary vertices of a T-mesh (used by TSplineSpace, tspline.h).
//
// Around an extraordinary vertex v of valence n (n faces with v as a corner, n >= 2), sector k is
// the face F_k around v (counter-clockwise) with its sector frame: v at the origin, F_k in the
// first quadrant, the x-axis along edge k and the y-axis along edge k + 1 (F_{k+1} lies across
// it, F_{k-1} across the x-axis). A cap applies when in every sector the 3 x 3 cells (a, b),
// a, b in 0..2, are quads of one size d x d without T-junctions, distinct, and all their vertices
// but v regular interior vertices: then v and its 2n one-ring vertices anchor uniform B-splines
// (knots -2d .. 2d, reaching the vertices at index 3), every face of the 3 x 3 cells of a sector
// but F_k is an ordinary T-spline face, and every F_k is one bicubic Bezier patch. Nothing beyond
// index 3 is asked for: on F_k = [0, d]^2 a cubic B-spline depends only on its knots in
// [-2d, 3d] (the first piece of N[t0..t4] only on t0..t3, the last only on t1..t4), so the 16
// functions there are the uniform ones whatever lies farther out, and the patch, being the true
// T-spline away from the corner coefficients, meets the faces around it as the T-spline does.
// T-junctions and other cones may sit at index 4 (refineAroundCones splits 2 cells around a cone
// without a cap: 4 half cells, the T-junctions beyond the 3 a cap needs).
//
// The patch on F_k starts from the uniform B-spline's Bezier coefficients b_ij, computed in the
// sector frame from the net P_ij, i, j in -1..2 (rows and columns -1 lie in the sectors k - 1 and
// k + 1; only b_00 would need the missing P_{-1,-1}), and replaces the corner: b_00 is the
// Catmull-Clark limit point L = (n^2 v + 4 sum e_j + sum d_j) / (n (n + 5)), and the edge
// coefficients E_k = b_10 of sector k (= b_01 of sector k - 1) are projected onto the first
// Fourier harmonic around L: E'_k = L + (2/n) sum_j cos(2 pi (j - k) / n) (E_j - L), so that all
// b_10, b_01 lie in one plane through L (a tangent plane and a unique normal at v). For n = 4 this
// is the uniform B-spline itself. Valence 2 (two quadrants make a half-plane; the layout makes
// such cones) has no first harmonic in the tangent plane: there b_10 = b_01 = L and the
// second-order corner coefficients b_20, b_11, b_02 are projected instead (see capPatch). Every
// coefficient is an affine combination of net points, so
// the basis stays a partition of unity. The patches meet each other with a position match, the
// same tangent plane at v and, along the sector edges, a cross-derivative mismatch of O(h^2)
// (E'_k - E_k) against derivatives of O(h): normals jump by O(h) there; across the outer sides of
// F_k the patch is C1 (b_10 sits in the column next to the corner, so C2 does not hold there).
// Valence 2 also moves b_20 and b_02, which sit next to the outer sides: there the normals jump by
// O(h) too, near the sector edges. The constant is large where a valence-2 cone sits on a sharp
// tip: three_peaks' fit folds on a valence-2 cap's sector edges until the fit loop splits the
// region (tspline_adaptive_fit.h).
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/tspline/tmesh.h"
#include "mspline/spline/tspline/tspline.h"

namespace mspline::spline {

/// The cubic Bernstein polynomials at u in [0, 1], with first (d1) and second (d2) derivatives.
void cubicBernstein(double u, double b[4], double* d1 = nullptr, double* d2 = nullptr);

/// Cells per sector side that a cap needs (see above).
constexpr int kCapCells = 3;

/// The cells around an extraordinary vertex that a cap needs, in sector frames.
struct TSplineCapRegion {
  int vertex = -1;
  int valence = 0;
  double cellSize = 0.0;
  /// Per sector: cell (a, b) at index kCapCells b + a, a face with the motion of its frame into
  /// the sector frame.
  std::vector<std::array<DevelopedFace, kCapCells * kCapCells>> cells;
  /// Per sector: the vertex at (i, j) * cellSize, index (kCapCells + 1) j + i, i, j in
  /// 0..kCapCells.
  std::vector<std::array<int, (kCapCells + 1) * (kCapCells + 1)>> vertices;

  /// The vertex at (i, j) * cellSize of sector k's frame, i, j in -kCapCells..kCapCells and not
  /// both negative: a negative row or column lies in the neighbouring sector.
  int vertexAt(int sector, int i, int j) const;
};

/// Why vertex `vertex` of `mesh` (extraordinary) has no cap, or "" and `region` filled.
/// `developer` is a FaceDeveloper of `mesh`, shared by the calls for one mesh (each builds the
/// frame changes of the whole mesh).
std::string findCapRegion(const TMesh& mesh, int vertex, TSplineCapRegion& region,
                          FaceDeveloper& developer);

/// The cap regions of every extraordinary vertex of `mesh`. Throws SolverError naming the vertex
/// and the condition it fails.
std::vector<TSplineCapRegion> capRegions(const TMesh& mesh);

/// The Bezier patch of sector k: the 16 coefficients in the frame of its face F_k (row 4 j + i for
/// Bernstein B_i(x / d) B_j(y / d)) as affine combinations of the net's vertices (`vertices`, one
/// column each).
struct TSplineCapPatch {
  int face = -1;
  std::vector<int> vertices;
  Eigen::Matrix<double, 16, Eigen::Dynamic> coefficients;
};
TSplineCapPatch capPatch(const TSplineCapRegion& region, int sector);

/// Fills the rows of `points` (numVertices x columns) of the vertices not `placed` with the average
/// of their placed neighbours along T-mesh edges; where no neighbour is placed, the average of the
/// neighbours filled in the previous such ring, outwards. Net points for vertices without a
/// control point (tsplineControlNet; cap anchors of models written before caps). Throws
/// InputError, starting with `context`, when a vertex has no placed vertex in its component.
void fillByRingAverages(const TMesh& mesh, Eigen::MatrixXd& points, std::vector<char> placed,
                        const std::string& context);

}  // namespace mspline::spline
