#pragma once
// Meshes generated in code, shared by all tests. Every generator returns a clean manifold mesh
// whose topology is stated in its comment; `resolution` scales the number of faces.
#include <vector>

#include "mspline/spline/tribspline/spline_domain.h"
#include "mspline/structure/mesh/polygon_soup.h"
#include "mspline/structure/mesh/tri_mesh.h"
#include "mspline/structure/ricci/curvature_target.h"

namespace mspline::test {

using structure::TriMesh;

/// Unit square [0,1]^2 in the z = 0 plane, n x n quads split into triangles. Disk: genus 0, 1
/// boundary.
TriMesh gridDisk(int n);
/// Annulus (radii 0.5 and 1) bent into a cylinder of height 1: genus 0, 2 boundaries.
TriMesh cylinder(int around, int along);
/// Torus with radii R = 1, r = 0.4: genus 1, closed.
TriMesh torus(int major, int minor);
/// Unit icosphere after `subdivisions` 1-to-4 splits (20 * 4^s faces): genus 0, closed.
TriMesh icosphere(int subdivisions);
/// Smooth closed genus-2 surface (a plate with two holes, rounded): genus 2, closed.
TriMesh doubleTorus(int resolution);
/// Closed surface of genus g >= 1 (a plate with g holes in a row, rounded).
TriMesh genusSurface(int genus, int resolution);
/// Disk with two holes: genus 0, 3 boundaries.
TriMesh pairOfPants(int resolution);
/// The convex polygon with these corners (counter-clockwise), as a fan of triangles from corner
/// 0: a disk.
TriMesh polygonFan(const std::vector<OpenMesh::Vec3d>& corners);

/// Surface of the cube [-1, 1]^3, each square face a 2m x 2m grid of cells split into triangles:
/// genus 0, closed; its edge lengths are a flat metric with 8 cones of curvature pi/2 (the
/// corners, vertices 0 .. 7).
TriMesh cubeSurface(int m);

/// Flat torus as a spline domain: the plane modulo n x n cells spanned by (1, 0) and (shear, 1),
/// each cell split into two triangles along its diagonal from (0, 0) to (1 + shear, 1); no cones.
/// Face 2 (i + n j) is the lower triangle of cell (i, j), face 2 (i + n j) + 1 the upper one.
spline::SplineDomain flatTorusDomain(int n, double shear = 0.0);

}  // namespace mspline::test

namespace mspline::test {

using structure::PolygonSoup;

/// Outward-oriented unit tetrahedron as a soup (source name "tet.off").
PolygonSoup tetrahedronSoup();
/// A tetrahedron whose apex is a hundred times farther from its base than the base is wide
/// ("needle.off"): the apex's cone angle is below pi/4 and no other vertex can take its
/// curvature, so automatic cone placement cannot flatten it.
PolygonSoup needleSoup();
/// Outward-oriented octahedron with vertices on the axes, shifted by `offset` along x ("oct.off").
PolygonSoup octahedronSoup(double offset = 0.0);
/// n x n grid on the unit square; quads split into two triangles or kept as quads ("grid").
PolygonSoup gridSoup(int n, bool quads = false);
/// A Moebius strip of 2n triangles, width 0.6 around the unit circle ("moebius"): no flips
/// orient it.
PolygonSoup moebiusSoup(int n = 6);
/// Appends `other`'s vertices and faces to `soup` (a second component).
void appendSoup(PolygonSoup& soup, const PolygonSoup& other);

}  // namespace mspline::test

namespace mspline::test {

/// Index of the vertex nearest to p.
int nearestVertex(const TriMesh& mesh, const OpenMesh::Vec3d& p);
/// Eight cones of curvature pi/2 at the vertices nearest the corners of the cube inscribed in the
/// unit sphere (a flat metric on a sphere whose cut pieces fold into a cube; sum 4 pi).
std::vector<structure::Cone> cubeCornerCones(const TriMesh& mesh);

}  // namespace mspline::test
