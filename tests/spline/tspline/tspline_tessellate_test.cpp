#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include <Eigen/Geometry>

#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_tessellate.h"
#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "support/test_tmeshes.h"

using namespace mspline;
using spline::TMesh;
using spline::TSplineSpace;
using test::randomWeights;
using test::unitKnots;

namespace {

struct EdgeUse {
  bool oriented = true;    // no directed edge twice
  long edges = 0;          // undirected
  long boundaryEdges = 0;  // used by one triangle
  long moreThanTwo = 0;    // used by three or more
};

EdgeUse edgeUse(const structure::PolygonSoup& mesh) {
  std::map<std::pair<std::int64_t, std::int64_t>, int> directed;
  for (const auto& f : mesh.faces)
    for (std::size_t k = 0; k < 3; ++k) ++directed[{f[k], f[(k + 1) % 3]}];
  EdgeUse use;
  for (const auto& [edge, count] : directed) {
    if (count != 1) use.oriented = false;
    const auto reverse = directed.find({edge.second, edge.first});
    const int total = count + (reverse == directed.end() ? 0 : reverse->second);
    if (reverse == directed.end() || edge.first < edge.second) ++use.edges;
    if (total == 1) ++use.boundaryEdges;
    if (total > 2) ++use.moreThanTwo;
  }
  return use;
}

long eulerCharacteristic(const spline::TSplineTessellation& t) {
  return long(t.mesh.positions.size()) - edgeUse(t.mesh).edges + long(t.mesh.faces.size());
}

// Largest distance between a mesh vertex (not a hole sample) and TSplineSpace::evaluate at its
// point; infinity if a coordinate is not finite.
double worstAgainstEvaluate(const TSplineSpace& space, const Eigen::MatrixXd& control,
                            const Eigen::VectorXd& weights, const spline::TSplineTessellation& t) {
  double worst = 0.0;
  for (std::size_t v = 0; v < t.mesh.positions.size(); ++v) {
    const Eigen::Vector3d x(t.mesh.positions[v][0], t.mesh.positions[v][1], t.mesh.positions[v][2]);
    if (!x.allFinite()) return INFINITY;
    if (std::binary_search(t.holeVertices.begin(), t.holeVertices.end(), int(v))) continue;
    const auto& p = t.vertexPoints[v];
    worst = std::max(worst,
                     (space.evaluate(control, weights, p.face, p.position, 0).position - x).norm());
  }
  return worst;
}

}  // namespace

TEST_CASE("tspline_tessellate: a periodic grid gives a closed torus", "[spline]") {
  const TSplineSpace space(spline::gridTMesh(unitKnots(6), {0.0, 1.0, 2.5, 3.0, 4.0}, true, true));
  const TMesh& mesh = space.mesh();
  std::srand(3);
  const Eigen::MatrixXd control = Eigen::MatrixXd::Random(space.numBasis(), 3);
  const Eigen::VectorXd weights = randomWeights(space.numBasis(), 3);
  const long edges = 2L * mesh.numFaces();  // four sides per face, each shared by two
  for (int r : {1, 2, 3, 5}) {
    INFO("resolution " << r);
    const auto t = spline::tessellateTSpline(space, control, weights, r);
    CHECK(t.mesh.faces.size() == std::size_t(2 * r * r * mesh.numFaces()));
    CHECK(t.mesh.positions.size() ==
          std::size_t(mesh.numVertices + edges * (r - 1) + mesh.numFaces() * (r - 1) * (r - 1)));
    CHECK(t.vertexPoints.size() == t.mesh.positions.size());
    const EdgeUse use = edgeUse(t.mesh);
    CHECK(use.oriented);
    CHECK(use.boundaryEdges == 0);
    CHECK(use.moreThanTwo == 0);
    CHECK(eulerCharacteristic(t) == 0);
    CHECK(t.holeVertices.empty());
    CHECK(t.minDenominator > 0.0);
    CHECK(worstAgainstEvaluate(space, control, weights, t) <= 1e-12);
  }
}

TEST_CASE("tspline_tessellate: T-junction faces are stitched watertight", "[spline]") {
  // A 2 x 2 block with four T-junctions facing each other, and a line stopping at a T-junction
  // with its neighbours merged two by two (faces with 5 and 6 boundary vertices).
  for (const TMesh& mesh :
       {test::mergedBlock(),
        test::gridWithMerges(8, {{3, 4, 5, 5}, {3, 5, 5, 6}, {3, 6, 5, 7}, {0, 0, 3, 2}})}) {
    const TSplineSpace space(mesh);
    long tmeshEdges = 0, tmeshBoundaryEdges = 0, tJunctionFaces = 0;
    for (const auto& face : mesh.faces) {
      tJunctionFaces += face.vertices.size() > 4;
      for (int g : face.twinFace) {
        tmeshEdges += g < 0 ? 2 : 1;
        tmeshBoundaryEdges += g < 0;
      }
    }
    tmeshEdges /= 2;
    REQUIRE(tJunctionFaces > 0);
    // Control points at the anchors' places in the plane: the surface is a map of the plane close
    // to the identity, so its triangles keep the frames' counter-clockwise orientation.
    const std::vector<Eigen::Vector2d> place = test::planarVertices(mesh);
    Eigen::MatrixXd control(space.numBasis(), 3);
    for (int a = 0; a < space.numBasis(); ++a)
      control.row(a) << place[std::size_t(space.anchors()[a].vertex)].transpose(), 0.0;
    const Eigen::VectorXd weights = randomWeights(space.numBasis(), 4);
    for (int r : {1, 2, 3, 6}) {
      INFO("resolution " << r);
      const auto t = spline::tessellateTSpline(space, control, weights, r);
      const EdgeUse use = edgeUse(t.mesh);
      CHECK(use.oriented);
      CHECK(use.moreThanTwo == 0);
      // Every T-mesh edge sampled r times, the boundary edges used once, the mesh a disk.
      CHECK(use.boundaryEdges == r * tmeshBoundaryEdges);
      CHECK(eulerCharacteristic(t) == 1);
      const long interior = r == 1 ? 1 : (r - 1) * (r - 1);
      CHECK(t.mesh.positions.size() ==
            std::size_t(mesh.numVertices + tmeshEdges * (r - 1) +
                        (mesh.numFaces() - tJunctionFaces) * (r - 1) * (r - 1) +
                        tJunctionFaces * interior));
      CHECK(t.holeVertices.empty());
      CHECK(t.minDenominator > 0.0);
      CHECK(worstAgainstEvaluate(space, control, weights, t) <= 1e-12);
      int inverted = 0;
      for (const auto& f : t.mesh.faces) {
        const auto& a = t.mesh.positions[std::size_t(f[0])];
        const auto& b = t.mesh.positions[std::size_t(f[1])];
        const auto& c = t.mesh.positions[std::size_t(f[2])];
        inverted += (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) <= 0.0;
      }
      CHECK(inverted == 0);
    }
  }
}

TEST_CASE("tspline_tessellate: extraordinary vertices are sampled on the surface itself",
          "[spline]") {
  // The surface of the cube [0, k]^3 in unit cells: 8 extraordinary vertices of valence 3, each
  // with a cap: the sample is the cone point, its normal the cap's one normal there.
  const test::CubeTMesh cube = test::cubeTMesh(5);
  const TSplineSpace space(cube.mesh);
  const TMesh& mesh = space.mesh();
  const Eigen::MatrixXd control = test::anchorControl(space, cube.latticePoints);
  for (int r : {1, 4}) {
    INFO("resolution " << r);
    const auto t = spline::tessellateTSpline(space, control, {}, r);
    const EdgeUse use = edgeUse(t.mesh);
    CHECK(use.oriented);
    CHECK(use.boundaryEdges == 0);
    CHECK(eulerCharacteristic(t) == 2);
    CHECK(t.minDenominator == Approx(1.0).margin(1e-12));
    CHECK(worstAgainstEvaluate(space, control, {}, t) <= 1e-12);
    CHECK(t.holeVertices.empty());
    CHECK(t.collapsedEdgeSamples == 0);
    int cones = 0;
    for (int v = 0; v < mesh.numVertices; ++v) {
      if (!mesh.isExtraordinary(v)) continue;
      ++cones;
      const auto& p = t.vertexPoints[std::size_t(v)];
      const auto point = space.evaluate(control, {}, p.face, p.position);
      const Eigen::Vector3d x(t.mesh.positions[std::size_t(v)].data());
      CHECK((x - point.position).norm() <= 1e-12);
      const Eigen::Vector3d normal(t.normals[std::size_t(v)].data());
      CHECK((normal - point.normal).norm() <= 1e-12);
      // The cube's corner points outwards.
      CHECK(normal.dot(x) > 0.0);
    }
    CHECK(cones == 8);
  }
}

TEST_CASE("tspline_tessellate: no flat or folded triangles at cones of any valence", "[spline]") {
  // At a cone of valence 2 a face corner's right angle opens to a straight angle: a triangle with
  // the corner between its other two vertices would be flat and face anywhere.
  for (const int n : {2, 3, 5}) {
    INFO("valence " << n);
    const test::StarTMesh star = test::starTMesh(n);
    // Cells' frames turned by quarter turns that differ from sector to sector, so that the cone
    // is not always the corner (0, 0).
    constexpr std::size_t cells = test::StarTMesh::kSide * test::StarTMesh::kSide;
    std::vector<spline::TMeshFace> turned;
    for (std::size_t f = 0; f < star.mesh.faces.size(); ++f) {
      const spline::TMeshFace& face = star.mesh.faces[f];
      spline::TMeshFace cell;
      for (std::size_t k = 0; k < 4; ++k) {
        cell.vertices.push_back(face.vertices[(k + f + f / cells) % 4]);
        cell.positions.push_back(face.positions[k]);
      }
      turned.push_back(cell);
    }
    const TSplineSpace space(spline::buildTMesh(star.mesh.numVertices, turned));
    const Eigen::MatrixXd control = test::starControl(star, space, 0.1);
    for (int r : {3, 6}) {
      INFO("resolution " << r);
      const auto t = spline::tessellateTSpline(space, control, {}, r);
      const auto normalOf = [&](const std::array<std::int64_t, 3>& f) {
        const Eigen::Vector3d a(t.mesh.positions[std::size_t(f[0])].data());
        const Eigen::Vector3d b(t.mesh.positions[std::size_t(f[1])].data());
        const Eigen::Vector3d c(t.mesh.positions[std::size_t(f[2])].data());
        return Eigen::Vector3d((b - a).cross(c - a));
      };
      std::map<std::pair<std::int64_t, std::int64_t>, Eigen::Vector3d> sides;
      double smallestUp = 1.0, largestTurn = 0.0;
      for (const auto& face : t.mesh.faces) {
        const std::array<std::int64_t, 3> f{face[0], face[1], face[2]};
        const Eigen::Vector3d normal = normalOf(f).normalized();
        // The surface is a graph over the plane: every triangle faces up.
        smallestUp = std::min(smallestUp, normal.z());
        for (int k = 0; k < 3; ++k) {
          const auto across = sides.find({f[std::size_t((k + 1) % 3)], f[std::size_t(k)]});
          if (across != sides.end())
            largestTurn = std::max(largestTurn, std::acos(std::clamp(
                                                    normal.dot(across->second), -1.0, 1.0)));
          sides[{f[std::size_t(k)], f[std::size_t((k + 1) % 3)]}] = normal;
        }
      }
      CHECK(smallestUp > 0.5);
      CHECK(largestTurn * 180.0 / kPi < 30.0);
    }
  }
}

TEST_CASE("tspline_tessellate: bad resolution and sizes are refused", "[spline]") {
  const TSplineSpace space(spline::gridTMesh(unitKnots(4), unitKnots(4), true, true));
  const Eigen::MatrixXd control = Eigen::MatrixXd::Zero(space.numBasis(), 3);
  CHECK_THROWS_AS(spline::tessellateTSpline(space, control, {}, 0), structure::InputError);
  CHECK_THROWS_AS(spline::tessellateTSpline(space, Eigen::MatrixXd::Zero(3, 3), {}, 2),
                  structure::InputError);
  CHECK_THROWS_AS(spline::tessellateTSpline(space, control, Eigen::VectorXd::Ones(2), 2),
                  structure::InputError);
}
