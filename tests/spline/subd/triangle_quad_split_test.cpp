#include <catch2/catch.hpp>

#include <map>
#include <vector>

#include "mspline/spline/subd/triangle_quad_split.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/polygon_soup.h"
#include "mspline/structure/mesh/validate.h"
#include "support/test_meshes.h"

using namespace mspline;

namespace {

Eigen::Vector3d position(const structure::TriMesh& mesh, int v) {
  const auto& p = mesh.point(structure::TriMesh::VertexHandle(v));
  return {p[0], p[1], p[2]};
}

structure::PolygonSoup soupOf(const spline::TriangleQuadSplit& split) {
  structure::PolygonSoup soup;
  for (Eigen::Index i = 0; i < split.points.rows(); ++i)
    soup.positions.push_back({split.points(i, 0), split.points(i, 1), split.points(i, 2)});
  for (const auto& quad : split.quads) soup.faces.emplace_back(quad.begin(), quad.end());
  return soup;
}

}  // namespace

TEST_CASE("triangle_quad_split: quads through corners, edge midpoints and centroids", "[spline]") {
  for (const structure::TriMesh& mesh : {test::icosphere(1), test::gridDisk(3)}) {
    const auto split = spline::splitTrianglesIntoQuads(mesh);
    const int nv = int(mesh.n_vertices()), ne = int(mesh.n_edges()), nf = int(mesh.n_faces());
    REQUIRE(split.points.rows() == nv + ne + nf);
    REQUIRE(split.quads.size() == std::size_t(3 * nf));
    for (auto f : mesh.faces()) {
      std::vector<int> corner;
      for (auto v : mesh.fv_range(f)) corner.push_back(v.idx());
      const Eigen::Vector3d centroid =
          (position(mesh, corner[0]) + position(mesh, corner[1]) + position(mesh, corner[2])) / 3;
      for (int k = 0; k < 3; ++k) {
        const auto& quad = split.quads[std::size_t(3 * f.idx() + k)];
        REQUIRE(quad.size() == 4);
        const Eigen::Vector3d at = position(mesh, corner[k]),
                              next = position(mesh, corner[(k + 1) % 3]),
                              previous = position(mesh, corner[(k + 2) % 3]);
        CHECK(quad[0] == corner[k]);
        CHECK(quad[2] == nv + ne + f.idx());
        CHECK((split.points.row(quad[1]).transpose() - (at + next) / 2).norm() <= 1e-15);
        CHECK((split.points.row(quad[2]).transpose() - centroid).norm() <= 1e-15);
        CHECK((split.points.row(quad[3]).transpose() - (at + previous) / 2).norm() <= 1e-15);
      }
    }
    // A clean, consistently oriented quad mesh with the triangle mesh's Euler characteristic;
    // centroids have valence 3, midpoints 4 (2 on the boundary), the vertices keep theirs.
    const auto report = structure::validate(soupOf(split));
    INFO(report.summary());
    CHECK(report.ok());
    CHECK(int(report.vertices) - int(report.edges) + int(report.faces) == nv - ne + nf);
    std::map<int, int> valence;
    for (const auto& quad : split.quads)
      for (int k = 0; k < 4; ++k) ++valence[quad[k]];  // faces at the vertex
    for (auto v : mesh.vertices())
      CHECK(valence[v.idx()] == int(mesh.valence(v)) - mesh.is_boundary(v));
    for (auto e : mesh.edges()) CHECK(valence[nv + e.idx()] == (mesh.is_boundary(e) ? 2 : 4));
    for (int f = 0; f < nf; ++f) CHECK(valence[nv + ne + f] == 3);
  }
}

TEST_CASE("triangle_quad_split: quad parameters map to barycentric coordinates bilinearly",
          "[spline]") {
  const structure::TriMesh mesh = test::icosphere(0);
  const auto split = spline::splitTrianglesIntoQuads(mesh);
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d origin = spline::quadPointBarycentric(k, 0, 0);
    CHECK(origin[k] == 1.0);
    CHECK(origin.sum() == 1.0);
    CHECK((spline::quadPointBarycentric(k, 1, 1) - Eigen::Vector3d::Constant(1.0 / 3)).norm() <=
          1e-15);
    CHECK(spline::quadPointBarycentric(k, 1, 0)[(k + 1) % 3] == 0.5);
    CHECK(spline::quadPointBarycentric(k, 0, 1)[(k + 2) % 3] == 0.5);
  }
  // In a triangle, the barycentric point is the bilinear interpolation of the quad's points.
  const int f = 7;
  std::vector<int> corner;
  for (auto v : mesh.fv_range(structure::TriMesh::FaceHandle(f))) corner.push_back(v.idx());
  for (int k = 0; k < 3; ++k)
    for (const auto& [u, v] : std::vector<std::pair<double, double>>{{0.2, 0.9}, {0.6, 0.35}}) {
      const auto& q = split.quads[std::size_t(3 * f + k)];
      const Eigen::Vector3d bilinear = (1 - u) * (1 - v) * split.points.row(q[0]).transpose() +
                                       u * (1 - v) * split.points.row(q[1]).transpose() +
                                       u * v * split.points.row(q[2]).transpose() +
                                       (1 - u) * v * split.points.row(q[3]).transpose();
      const Eigen::Vector3d b = spline::quadPointBarycentric(k, u, v);
      CHECK(b.sum() == Approx(1.0).margin(1e-15));
      CHECK((b.minCoeff() >= 0.0));
      const Eigen::Vector3d inTriangle = b[0] * position(mesh, corner[0]) +
                                         b[1] * position(mesh, corner[1]) +
                                         b[2] * position(mesh, corner[2]);
      CHECK((inTriangle - bilinear).norm() <= 1e-15);
    }
  CHECK_THROWS_AS(spline::quadPointBarycentric(3, 0.5, 0.5), structure::InputError);
}
