#include <catch2/catch.hpp>

#include <map>
#include <random>

#include "mspline/spline/tribspline/tessellate.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
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

TEST_CASE("tessellate: normals are the spline's, chart coordinates the sampling face's",
          "[spline]") {
  const auto cube = test::cubeSurface(1);
  const spline::SplineDomain domain = spline::domainFromMesh(cube, structure::edgeLengths(cube));
  const spline::TriBSplineSpace space(
      domain, spline::placeKnotClouds(domain, spline::buildHomeCharts(domain), 3));
  // Random control points: the normals are compared with evaluate's, not with a shape.
  Eigen::MatrixXd control(space.numBasis(), 3);
  std::mt19937 random(5);
  std::normal_distribution<double> gauss;
  for (Eigen::Index i = 0; i < control.size(); ++i) control.data()[i] = gauss(random);
  const int r = 4;
  const auto t = spline::tessellate(space, control, r);
  REQUIRE(t.normals.size() == t.mesh.positions.size());
  REQUIRE(t.uvs.size() == t.mesh.positions.size());
  for (const auto& n : t.normals)
    CHECK(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) == Approx(1.0).margin(1e-12));
  // Grid point (2, 1) inside face 0 (made by face 0 alone): found by its position, its chart
  // coordinates and normal are face 0's frame position and evaluate's normal.
  const auto corners = spline::canonicalCorners(domain, 0);
  const Eigen::Vector3d barycentric(2.0 / r, 1.0 / r, double(r - 3) / r);
  const Eigen::Vector2d frame =
      barycentric[0] * corners[0] + barycentric[1] * corners[1] + barycentric[2] * corners[2];
  const spline::SplinePoint expected = space.evaluate(control, {0, barycentric}, 1);
  int found = 0;
  for (std::size_t v = 0; v < t.uvs.size(); ++v) {
    const Eigen::Vector3d p(t.mesh.positions[v][0], t.mesh.positions[v][1], t.mesh.positions[v][2]);
    if ((p - expected.position).norm() > 1e-12) continue;
    ++found;
    CHECK((Eigen::Vector2d(t.uvs[v][0], t.uvs[v][1]) - frame).norm() < 1e-12);
    CHECK((Eigen::Vector3d(t.normals[v][0], t.normals[v][1], t.normals[v][2]) - expected.normal)
              .norm() < 1e-12);
  }
  CHECK(found == 1);
}
