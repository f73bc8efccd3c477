#include <catch2/catch.hpp>

#include <map>
#include <random>

#include "spline/tessellate.h"
#include "structure/errors.h"
#include "structure/vertex_scaling_energy.h"
#include "support/test_meshes.h"

using namespace mspline;

namespace {

// Every edge is used once in each direction: the mesh is closed and consistently oriented.
bool closedAndOriented(const structure::PolygonSoup& mesh, long& euler) {
  std::map<std::pair<std::int64_t, std::int64_t>, int> directed;
  for (const auto& f : mesh.faces)
    for (std::size_t k = 0; k < 3; ++k) ++directed[{f[k], f[(k + 1) % 3]}];
  for (const auto& [edge, count] : directed)
    if (count != 1 || directed.count({edge.second, edge.first}) == 0) return false;
  euler = long(mesh.positions.size()) - long(directed.size() / 2) + long(mesh.faces.size());
  return true;
}

}  // namespace

TEST_CASE("tessellate: watertight surfaces of a torus and of a cube with cones", "[spline]") {
  const auto cube = test::cubeSurface(1);
  const std::vector<std::pair<spline::SplineDomain, long>> cases = {
      {test::flatTorusDomain(4, 0.1), 0},
      {spline::domainFromMesh(cube, structure::edgeLengths(cube)), 2}};
  std::mt19937 random(2);
  std::normal_distribution<double> gauss;
  for (const auto& [domain, euler] : cases) {
    const spline::TriBSplineSpace space(
        domain, spline::placeKnotClouds(domain, spline::buildHomeCharts(domain), 3));
    Eigen::MatrixXd control(space.numBasis(), 3);
    for (Eigen::Index i = 0; i < control.size(); ++i) control.data()[i] = gauss(random);
    for (int resolution : {1, 2, 5}) {
      const auto tessellation = spline::tessellate(space, control, resolution);
      INFO("resolution " << resolution << ", euler " << euler);
      CHECK(tessellation.mesh.faces.size() ==
            std::size_t(domain.faceCount() * resolution * resolution));
      long measured = 0;
      CHECK(closedAndOriented(tessellation.mesh, measured));
      CHECK(measured == euler);
      CHECK(tessellation.minDenominator > 0.0);
      CHECK(tessellation.coneVertices == (euler == 2 ? 8 : 0));
    }
    // An interior grid point is the spline there.
    const auto tessellation = spline::tessellate(space, control, 3);
    const Eigen::Vector3d expected =
        space.evaluate(control, {0, Eigen::Vector3d(1.0, 1.0, 1.0) / 3.0}, 0).position;
    double nearest = 1e300;
    for (const auto& p : tessellation.mesh.positions)
      nearest = std::min(nearest, (Eigen::Vector3d(p[0], p[1], p[2]) - expected).norm());
    CHECK(nearest <= 1e-12);
  }
  CHECK_THROWS_AS(spline::tessellate(spline::TriBSplineSpace(
                                         test::flatTorusDomain(3),
                                         spline::placeKnotClouds(
                                             test::flatTorusDomain(3),
                                             spline::buildHomeCharts(test::flatTorusDomain(3)), 2)),
                                     Eigen::MatrixXd::Zero(54, 3), 0),
                  structure::InputError);
}
