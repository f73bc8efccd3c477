#include <catch2/catch.hpp>

#include <numeric>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/flatten/surface_voronoi.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::SurfaceVoronoiOptions;
using structure::TriMesh;

TEST_CASE("surface_voronoi: cells of random sites on a torus") {
  const TriMesh mesh = test::torus(32, 16);
  SurfaceVoronoiOptions options;
  options.randomSites = 6;
  const auto cells = structure::surfaceVoronoi(mesh, options);
  REQUIRE(cells.flattening.converged);
  CHECK(cells.flattening.cones.empty());
  REQUIRE(cells.sites.size() == 6);
  CHECK(cells.voronoi.cells == 6);
  CHECK(cells.fewestFacesPerCell > 0);
  // Every face is in one cell: the cells share the faces out.
  CHECK(cells.voronoi.faceLabel.size() == mesh.n_faces());
  CHECK(cells.mostFacesPerCell <= int(mesh.n_faces()) - 5 * cells.fewestFacesPerCell);
  CHECK(cells.voronoi.maxEquidistanceError <= 1e-9);
}

TEST_CASE("surface_voronoi: given sites stay where they are") {
  const TriMesh mesh = test::torus(24, 12);
  SurfaceVoronoiOptions options;
  options.sites = {{3, Eigen::Vector3d(0.2, 0.3, 0.5)}, {200, Eigen::Vector3d(1, 0, 0)}};
  const auto cells = structure::surfaceVoronoi(mesh, options);
  REQUIRE(cells.flattening.converged);
  CHECK(!cells.flattening.overlay);
  REQUIRE(cells.sites.size() == 2);
  CHECK(cells.sites[0].face == 3);
  CHECK(cells.voronoi.faceLabel[3] == 0);
  CHECK(cells.voronoi.cells == 2);
}

TEST_CASE("surface_voronoi: a sphere is refused, and so are no sites") {
  SurfaceVoronoiOptions options;
  options.randomSites = 3;
  options.name = "sphere";
  CHECK_THROWS_AS(structure::surfaceVoronoi(test::icosphere(2), options), structure::TopologyError);
  CHECK_THROWS_AS(structure::surfaceVoronoi(test::torus(24, 12), {}), structure::InputError);
}
