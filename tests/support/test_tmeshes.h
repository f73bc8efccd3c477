#pragma once
// T-meshes generated in code and random T-spline data, shared by the T-spline tests.
#include <array>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/tspline/tmesh.h"
#include "mspline/spline/tspline/tspline.h"

namespace mspline::test {

/// The knot lines 0, 1, ..., n.
std::vector<double> unitKnots(int n);

/// The unit cells of an n x n grid, some replaced by the merged rectangles [x0, y0, x1, y1]
/// (the merged rectangles are the first faces, in the order given).
spline::TMesh gridWithMerges(int n, const std::vector<std::array<int, 4>>& merged);

/// The 2 x 2 block [2,4]^2 of a 6 x 6 grid as one face (face 0): four T-junctions facing each
/// other, so the T-mesh is not analysis-suitable.
spline::TMesh mergedBlock();

/// An 8 x 8 grid whose line x = 4 stops at the T-junction (4, 4) (face 0 at (3, 4)):
/// analysis-suitable.
spline::TMesh stoppedLine();

/// The surface of a cube [0, k]^3 made of 6 k x k unit cells: vertices the integer points on it,
/// each cube face walked counter-clockwise around its outward normal. The 8 corners are
/// extraordinary vertices of valence 3.
struct CubeTMesh {
  spline::TMesh mesh;
  Eigen::MatrixXd latticePoints;  // per vertex its lattice point, centred and scaled to [-1, 1]^3
  Eigen::MatrixXd vertexPoints;   // latticePoints plus noise in [-0.02, 0.02]^3 drawn from `seed`
};
CubeTMesh cubeTMesh(int k, unsigned seed = 1);

/// Where the faces' frames start in the plane of a planar T-mesh (frames that are translations
/// of one another; fails the test if one turns), walking from face 0 placed at `first`.
/// planarTMesh starts each face at its lower-left corner.
std::vector<Eigen::Vector2d> faceOrigins(const spline::TMesh& mesh,
                                         const Eigen::Vector2d& first = Eigen::Vector2d::Zero());

/// Per vertex of a planar T-mesh, its position in that plane with face 0 placed at the origin.
std::vector<Eigen::Vector2d> planarVertices(const spline::TMesh& mesh);

/// The vertex at position p of a planar T-mesh whose faces start at `origin` (faceOrigins); -1
/// when there is none.
int vertexAt(const spline::TMesh& mesh, const std::vector<Eigen::Vector2d>& origin,
             const Eigen::Vector2d& p);

/// A point of `face` in its frame: x uniform in [lo, hi] times its width, then y in [lo, hi]
/// times its height.
Eigen::Vector2d randomPointIn(const spline::TMeshFace& face, std::mt19937& rng, double lo = 0.0,
                              double hi = 1.0);

/// `rows` points uniform in [-1, 1]^3, drawn row by row.
Eigen::MatrixXd randomPoints(int rows, std::mt19937& rng);
Eigen::MatrixXd randomPoints(int rows, unsigned seed);

/// `n` weights uniform in [0.5, 2].
Eigen::VectorXd randomWeights(int n, std::mt19937& rng);
Eigen::VectorXd randomWeights(int n, unsigned seed);

/// Control points of the space's anchors from a point per T-mesh vertex.
Eigen::MatrixXd anchorControl(const spline::TSplineSpace& space,
                              const Eigen::MatrixXd& vertexPoints);

/// n sectors of kSide x kSide unit cells glued around vertex 0, an extraordinary vertex of
/// valence n (a cone): sector k's column i = 0 is sector k + 1's row j = 0. Face of cell (a, b) of
/// sector k: face(k, a, b), its frame the sector frame translated to the cell.
struct StarTMesh {
  static constexpr int kSide = 6;
  spline::TMesh mesh;
  int n = 0;
  std::vector<std::array<int, 3>> where;  // per vertex: a sector and (i, j) in it
  int id(int k, int i, int j) const;
  int face(int k, int a, int b) const { return k * kSide * kSide + b * kSide + a; }
};
StarTMesh starTMesh(int n);

/// Control points of a star's anchors on a smooth graph over the plane, at the characteristic
/// positions scaled by h (sector k's quadrant opened to the angle 2 pi / n:
/// z -> |z| exp(i (4/n arg z + 2 pi k / n))).
Eigen::MatrixXd starControl(const StarTMesh& star, const spline::TSplineSpace& space, double h);

}  // namespace mspline::test
