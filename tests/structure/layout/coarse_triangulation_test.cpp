#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Dense>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/surface_point.h"
#include "mspline/structure/layout/coarse_triangulation.h"
#include "mspline/structure/ricci/cone_placement.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "mspline/structure/topology/topology.h"
#include "support/flat_metric.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::CoarseningOptions;
using structure::CoarseTriangulation;
using structure::TriMesh;

namespace {

test::FlatMetric flattenWithQuantizedCones(const TriMesh& mesh) {
  structure::ConePlacementOptions placement;
  placement.quantize = true;
  return test::flatMetric(mesh, structure::placeCones(mesh, placement).cones);
}

double heronArea(const std::array<double, 3>& l) {
  return structure::fourTimesArea(l[0], l[1], l[2]) / 4.0;
}

// Fine face f laid out in the plane (corners in fv_range order) and its vertices.
struct FineTriangle {
  std::array<int, 3> vertex;
  std::array<Eigen::Vector2d, 3> corner;
};

FineTriangle layOutFineFace(const test::FlatMetric& flat, int f) {
  FineTriangle t;
  std::array<double, 3> side;  // side k joins corners k and k + 1
  auto h = flat.surface.halfedge_handle(TriMesh::FaceHandle(f));
  for (int k = 0; k < 3; ++k, h = flat.surface.next_halfedge_handle(h)) {
    t.vertex[k] = flat.surface.to_vertex_handle(h).idx();
    side[k] = flat.lengths[flat.surface.edge_handle(flat.surface.next_halfedge_handle(h)).idx()];
  }
  const double x = (side[2] * side[2] - side[1] * side[1] + side[0] * side[0]) / (2 * side[0]);
  t.corner = {Eigen::Vector2d::Zero(), Eigen::Vector2d(side[0], 0.0),
              Eigen::Vector2d(x, std::sqrt(std::max(0.0, side[2] * side[2] - x * x)))};
  return t;
}

// The fine vertex's distance from `origin` along the straight segment closest in length to
// `expected` (infinite when none is found within twice that).
double distanceOnCoarse(const CoarseTriangulation& coarse, const structure::SurfacePoint& origin,
                        int fineVertex, double expected) {
  const auto development = structure::developFromPoint(coarse, origin, 2.0 * expected);
  double best = std::numeric_limits<double>::infinity();
  for (const auto& x : structure::sightingsOfFineVertex(coarse, development, fineVertex))
    if (std::abs(x.norm() - expected) < std::abs(best - expected)) best = x.norm();
  return best;
}

// Locates the point of fine face `face` and checks that its distances to the fine face's
// vertices, measured on the coarse triangulation, are the flat ones; returns the largest error
// relative to the face's longest side.
double locateAndMeasure(const test::FlatMetric& flat, const CoarseTriangulation& coarse, int face,
                        const Eigen::Vector3d& barycentric) {
  const FineTriangle t = layOutFineFace(flat, face);
  const auto at = structure::locateOnCoarse(flat.surface, coarse, face, barycentric);
  REQUIRE(at.face >= 0);
  REQUIRE(at.face < int(coarse.faces.size()));
  CHECK(at.barycentric.minCoeff() >= -1e-9);
  CHECK(std::abs(at.barycentric.sum() - 1.0) <= 1e-12);
  const Eigen::Vector2d q =
      barycentric[0] * t.corner[0] + barycentric[1] * t.corner[1] + barycentric[2] * t.corner[2];
  const double scale =
      std::max({(t.corner[1] - t.corner[0]).norm(), (t.corner[2] - t.corner[1]).norm(),
                (t.corner[0] - t.corner[2]).norm()});
  double worst = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double expected = (q - t.corner[k]).norm();
    if (expected <= 1e-3 * scale) continue;
    worst = std::max(
        worst, std::abs(distanceOnCoarse(coarse, at, t.vertex[k], expected) - expected) / scale);
  }
  return worst;
}

// Checks every property the spline layer relies on; fine edges measured on the coarse
// triangulation keep their lengths within `trackingTolerance` (relative).
void checkCoarse(const std::string& name, const test::FlatMetric& flat,
                 const CoarseTriangulation& coarse, const CoarseningOptions& options,
                 double seconds, double trackingTolerance) {
  const TriMesh& surface = flat.surface;
  const auto fineCurvature = structure::vertexCurvatures(surface, flat.lengths);
  int fineCones = 0;
  for (int v = 0; v < int(surface.n_vertices()); ++v)
    fineCones += std::abs(fineCurvature[v]) > options.coneTolerance;
  int coarseCones = 0;
  for (char c : coarse.isCone) coarseCones += c;
  WARN(name << ": " << surface.n_vertices() << " -> " << coarse.vertices.size() << " vertices, "
            << coarse.faces.size() << " faces, " << coarseCones << " cones, "
            << coarse.removedVertices << " removed, " << coarse.unremovedVertices.size()
            << " not removable, " << coarse.removalFlips << " removal flips, "
            << coarse.delaunayFlips << " Delaunay flips, tracking error " << coarse.maxTrackingError
            << ", curvature error " << coarse.maxCurvatureError << ", " << seconds << " s");

  // Vertex counts: the cones and the samples, plus what could not be removed (few).
  const int sampled =
      std::min(int(surface.n_vertices()), std::max(options.targetVertices, std::max(fineCones, 1)));
  CHECK(coarseCones == fineCones);
  CHECK(int(coarse.vertices.size()) == sampled + int(coarse.unremovedVertices.size()));
  CHECK(coarse.removedVertices + int(coarse.vertices.size()) == int(surface.n_vertices()));
  CHECK(coarse.unremovedVertices.size() <= std::max<std::size_t>(3, coarse.vertices.size() / 50));
  CHECK(coarse.complete == coarse.unremovedVertices.empty());
  for (int v : coarse.unremovedVertices) CHECK(coarse.coarseVertex[v] >= 0);

  // A closed Delta-complex with the fine surface's Euler characteristic.
  const int faces = int(coarse.faces.size());
  REQUIRE(faces % 2 == 0);
  for (int f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k) {
      const int g = coarse.neighbour[f][k], m = coarse.neighbourSide[f][k];
      REQUIRE(g >= 0);
      CHECK(coarse.neighbour[g][m] == f);
      CHECK(coarse.neighbourSide[g][m] == k);
      CHECK(coarse.sideLengths[g][m] == coarse.sideLengths[f][k]);
      CHECK(coarse.faces[g][m] == coarse.faces[f][(k + 1) % 3]);
      CHECK(coarse.faces[g][(m + 1) % 3] == coarse.faces[f][k]);
    }
  const long euler = long(coarse.vertices.size()) - 3L * faces / 2 + faces;
  CHECK(euler == structure::analyzeTopology(surface).euler);

  // Curvature: Gauss-Bonnet, and every kept vertex keeps its angle (cones theirs).
  double total = 0.0;
  for (double k : coarse.curvature) total += k;
  CHECK(std::abs(total - 2 * kPi * euler) <= 1e-8);
  double curvatureError = 0.0;
  for (std::size_t k = 0; k < coarse.vertices.size(); ++k)
    curvatureError =
        std::max(curvatureError, std::abs(coarse.curvature[k] - fineCurvature[coarse.vertices[k]]));
  CHECK(curvatureError <= 1e-9);
  CHECK(coarse.maxCurvatureError == Approx(curvatureError).margin(1e-15));

  // Area preserved; every face a proper triangle; Delaunay when asked.
  double fineArea = 0.0, coarseArea = 0.0, smallest = std::numeric_limits<double>::infinity();
  for (const auto f : surface.faces()) {
    std::array<double, 3> l;
    int k = 0;
    for (const auto e : surface.fe_range(f)) l[k++] = flat.lengths[e.idx()];
    fineArea += heronArea(l);
  }
  for (const auto& l : coarse.sideLengths) {
    coarseArea += heronArea(l);
    smallest = std::min(smallest, heronArea(l));
  }
  CHECK(std::abs(coarseArea - fineArea) <= 1e-9 * fineArea);
  CHECK(smallest > 0.0);
  double worstDelaunay = 0.0;
  const auto cosine = [&](int f, int k) {
    const auto& l = coarse.sideLengths[f];
    const double a = l[k], b = l[(k + 1) % 3], c = l[(k + 2) % 3];
    return (b * b + c * c - a * a) / (2 * b * c);
  };
  for (int f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k)
      worstDelaunay = std::min(
          worstDelaunay, cosine(f, k) + cosine(coarse.neighbour[f][k], coarse.neighbourSide[f][k]));
  if (options.delaunay) CHECK(worstDelaunay >= -1e-10);

  // Every fine vertex located; kept vertices at a corner that is theirs.
  double worstBarycentric = 0.0;
  for (int v = 0; v < int(surface.n_vertices()); ++v) {
    const auto& at = coarse.fineVertices[v];
    REQUIRE(at.face >= 0);
    REQUIRE(at.face < faces);
    CHECK(std::abs(at.barycentric.sum() - 1.0) <= 1e-12);
    worstBarycentric = std::min(worstBarycentric, at.barycentric.minCoeff());
    const int c = coarse.coarseVertex[v];
    if (c < 0) continue;
    int k = 0;
    at.barycentric.maxCoeff(&k);
    CHECK(at.barycentric[k] == 1.0);
    CHECK(coarse.faces[at.face][k] == c);
  }
  CHECK(worstBarycentric >= -1e-9);

  // Tracking: fine edges measured on the coarse triangulation keep their lengths. Where both ends
  // lie in one face and the fine edge is shorter than their distances to the face's sides
  // together, it cannot leave the face: it is the segment inside, which needs nothing but the
  // face laid out.
  CHECK(coarse.maxTrackingError <= trackingTolerance);
  double sameFace = 0.0;
  int sameFaceEdges = 0;
  for (const auto e : surface.edges()) {
    const auto h = surface.halfedge_handle(e, 0);
    const auto& a = coarse.fineVertices[surface.from_vertex_handle(h).idx()];
    const auto& b = coarse.fineVertices[surface.to_vertex_handle(h).idx()];
    const double length = flat.lengths[e.idx()];
    if (a.face != b.face) continue;
    const auto& l = coarse.sideLengths[a.face];
    const auto toSides = [&](const Eigen::Vector3d& p) {
      // The height onto the side opposite corner m (side m + 1) times p's weight of corner m.
      double nearest = std::numeric_limits<double>::infinity();
      for (int m = 0; m < 3; ++m)
        nearest = std::min(nearest, p[m] * 2 * heronArea(l) / l[(m + 1) % 3]);
      return nearest;
    };
    if (length >= toSides(a.barycentric) + toSides(b.barycentric)) continue;
    const double x = (l[2] * l[2] - l[1] * l[1] + l[0] * l[0]) / (2 * l[0]);
    Eigen::Matrix<double, 2, 3> corners;
    corners << 0.0, l[0], x, 0.0, 0.0, std::sqrt(l[2] * l[2] - x * x);
    const double d = (corners * (a.barycentric - b.barycentric)).norm();
    sameFace = std::max(sameFace, std::abs(d - length) / length);
    ++sameFaceEdges;
  }
  if (coarse.removedVertices > 0) CHECK(sameFaceEdges > 0);
  CHECK(sameFace <= trackingTolerance);

  // Random points of fine faces, and points of the fine faces around every cone (close to it and
  // at the centroid): located on the coarse triangulation at the flat distances of the fine
  // face's vertices.
  const auto start = std::chrono::steady_clock::now();
  double worstLocated = 0.0;
  int located = 0;
  for (const auto& point : structure::randomSurfacePoints(surface, 200, 7)) {
    worstLocated =
        std::max(worstLocated, locateAndMeasure(flat, coarse, point.face, point.barycentric));
    ++located;
  }
  for (std::size_t c = 0; c < coarse.vertices.size(); ++c) {
    if (!coarse.isCone[c]) continue;
    const TriMesh::VertexHandle cone(coarse.vertices[c]);
    for (const auto f : surface.vf_range(cone)) {
      int k = 0;
      for (const auto v : surface.fv_range(f)) {
        if (v == cone) break;
        ++k;
      }
      Eigen::Vector3d nearCone = Eigen::Vector3d::Constant(0.01);
      nearCone[k] = 0.98;
      for (const Eigen::Vector3d& b : {nearCone, Eigen::Vector3d::Constant(1.0 / 3.0).eval()}) {
        worstLocated = std::max(worstLocated, locateAndMeasure(flat, coarse, f.idx(), b));
        ++located;
      }
    }
  }
  const double locateSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  WARN(name << ": " << located << " points located (with their checks) in " << locateSeconds
            << " s, distance error " << worstLocated);
  CHECK(worstLocated <= 1e-9);
}

CoarseTriangulation coarsenAndCheck(const std::string& name, const test::FlatMetric& flat,
                                    const CoarseningOptions& options,
                                    double trackingTolerance = 1e-9) {
  const auto start = std::chrono::steady_clock::now();
  CoarseTriangulation coarse = structure::coarsenFlatMetric(flat.surface, flat.lengths, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  checkCoarse(name, flat, coarse, options, seconds, trackingTolerance);
  return coarse;
}

}  // namespace

TEST_CASE("coarse_triangulation: knot1.off, a flat torus without cones", "[structure]") {
  const test::FlatMetric flat = test::flatMetric(test::realMesh("knot1.off"), {});
  CoarseningOptions options;
  options.targetVertices = 300;
  const auto coarse = coarsenAndCheck("knot1.off", flat, options);
  CHECK(coarse.complete);
  for (double k : coarse.curvature) CHECK(std::abs(k) <= 1e-9);

  // The intrinsic Delaunay triangulation of the kept vertices does not depend on the order in
  // which the others are removed (knot1's metric has no four cocircular kept vertices).
  options.seed = 2;
  const auto reordered = structure::coarsenFlatMetric(flat.surface, flat.lengths, options);
  REQUIRE(reordered.vertices == coarse.vertices);
  const auto sortedLengths = [](const CoarseTriangulation& c) {
    std::vector<double> all;
    for (const auto& l : c.sideLengths) all.insert(all.end(), l.begin(), l.end());
    std::sort(all.begin(), all.end());
    return all;
  };
  const auto a = sortedLengths(coarse), b = sortedLengths(reordered);
  REQUIRE(a.size() == b.size());
  double difference = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
    difference = std::max(difference, std::abs(a[k] - b[k]));
  CHECK(difference <= 1e-9 * a.back());

  // Down to one vertex: the torus as two triangles glued along three loops.
  options.targetVertices = 1;
  const auto single = coarsenAndCheck("knot1.off, one vertex", flat, options);
  CHECK(single.vertices.size() == 1);
  CHECK(single.faces.size() == 2);

  // Without Delaunay flips only the removals' flips are made: the same invariants, but thinner
  // triangles amplify the rounding of the tracking.
  options.targetVertices = 300;
  options.delaunay = false;
  const auto plain = coarsenAndCheck("knot1.off without Delaunay flips", flat, options, 1e-8);
  CHECK(plain.delaunayFlips == 0);
}

TEST_CASE("coarse_triangulation: generated torus and double torus", "[structure]") {
  // The torus of revolution is flat as a grid: many vertices lie on straight lines between two of
  // their neighbours, where no flip lowers the degree.
  CoarseningOptions options;
  options.targetVertices = 150;
  const auto torus =
      coarsenAndCheck("torus(40, 20)", test::flatMetric(test::torus(40, 20), {}), options);
  CHECK(torus.complete);
  coarsenAndCheck("doubleTorus(2) quantized", flattenWithQuantizedCones(test::doubleTorus(2)),
                  options);
}

TEST_CASE("coarse_triangulation: eight.off with quantized cones", "[structure]") {
  const test::FlatMetric flat = flattenWithQuantizedCones(test::realMesh("eight.off"));
  CoarseningOptions options;
  options.targetVertices = 400;
  coarsenAndCheck("eight.off quantized", flat, options);
  // Fewer wanted than there are cones: the cones alone.
  options.targetVertices = 1;
  const auto cones = coarsenAndCheck("eight.off quantized, cones only", flat, options);
  for (char c : cones.isCone) CHECK(c);
}

TEST_CASE("coarse_triangulation: bunny00.off with quantized cones", "[structure][slow]") {
  const test::FlatMetric flat = flattenWithQuantizedCones(test::realMesh("bunny00.off"));
  for (const int target : {300, 2000}) {
    CoarseningOptions options;
    options.targetVertices = target;
    coarsenAndCheck("bunny00.off quantized, target " + std::to_string(target), flat, options);
  }
}

TEST_CASE("coarse_triangulation: a density puts more vertices where it is higher", "[structure]") {
  const test::FlatMetric flat = test::flatMetric(test::torus(40, 20), {});
  const int n = int(flat.surface.n_vertices());
  // The halves x > 0 and x < 0 are congruent in the flat metric.
  std::vector<char> dense(static_cast<std::size_t>(n), 0);
  for (const auto v : flat.surface.vertices())
    dense[std::size_t(v.idx())] = flat.surface.point(v)[0] > 0.0;
  CoarseningOptions options;
  options.targetVertices = 150;
  const CoarseTriangulation uniform = coarsenAndCheck("torus(40, 20)", flat, options);
  // A constant density scales every distance alike (by 2, exactly): the same vertices.
  options.density = Eigen::VectorXd::Constant(n, 4.0);
  CHECK(structure::coarsenFlatMetric(flat.surface, flat.lengths, options).vertices ==
        uniform.vertices);
  // 16 times the density on one half: about 16 times the vertices per area there (fewer, as the
  // sparse half's samples near the border count for it too).
  options.density = Eigen::VectorXd::Ones(n);
  for (int v = 0; v < n; ++v)
    if (dense[std::size_t(v)]) options.density[v] = 16.0;
  const CoarseTriangulation adapted = coarsenAndCheck("torus(40, 20), denser half", flat, options);
  CHECK(int(adapted.vertices.size()) == options.targetVertices);
  const auto countDense = [&](const CoarseTriangulation& coarse) {
    int count = 0;
    for (int v : coarse.vertices) count += dense[std::size_t(v)];
    return count;
  };
  const int denseCount = countDense(adapted);
  const int sparseCount = int(adapted.vertices.size()) - denseCount;
  INFO("uniform " << countDense(uniform) << " of " << uniform.vertices.size() << ", adapted "
                  << denseCount << " to " << sparseCount);
  CHECK(std::abs(2 * countDense(uniform) - int(uniform.vertices.size())) <= 20);
  CHECK(denseCount >= 8 * sparseCount);
  // Bad densities.
  options.density = Eigen::VectorXd::Ones(n - 1);
  CHECK_THROWS_AS(structure::coarsenFlatMetric(flat.surface, flat.lengths, options),
                  structure::InputError);
  options.density = Eigen::VectorXd::Ones(n);
  options.density[3] = 0.0;
  CHECK_THROWS_AS(structure::coarsenFlatMetric(flat.surface, flat.lengths, options),
                  structure::InputError);
}

TEST_CASE("coarse_triangulation: keeping every vertex leaves the fine surface", "[structure]") {
  // Every located point then starts from a coarse vertex, cones included.
  for (const bool cones : {false, true}) {
    const test::FlatMetric flat = cones ? flattenWithQuantizedCones(test::doubleTorus(2))
                                        : test::flatMetric(test::torus(12, 8), {});
    CoarseningOptions options;
    options.targetVertices = int(flat.surface.n_vertices()) + 5;
    options.delaunay = false;
    const auto coarse = coarsenAndCheck(
        cones ? "doubleTorus(2), every vertex kept" : "torus(12, 8), every vertex kept", flat,
        options);
    CHECK(coarse.removedVertices == 0);
    CHECK(coarse.removalFlips == 0);
    CHECK(coarse.faces.size() == flat.surface.n_faces());
  }
}

TEST_CASE("coarse_triangulation: bad input", "[structure]") {
  const TriMesh disk = test::gridDisk(4);
  CHECK_THROWS_AS(structure::coarsenFlatMetric(disk, structure::edgeLengths(disk)),
                  structure::TopologyError);
  CHECK_THROWS_WITH(structure::coarsenFlatMetric(disk, structure::edgeLengths(disk)),
                    Catch::Contains("only closed surfaces"));
  const TriMesh torus = test::torus(12, 8);
  const Eigen::VectorXd lengths = structure::edgeLengths(torus);
  CHECK_THROWS_AS(structure::coarsenFlatMetric(torus, lengths.head(3)), structure::InputError);
  CoarseningOptions options;
  options.targetVertices = 0;
  CHECK_THROWS_AS(structure::coarsenFlatMetric(torus, lengths, options), structure::InputError);
  Eigen::VectorXd broken = lengths;
  broken[0] = 100.0;
  CHECK_THROWS_AS(structure::coarsenFlatMetric(torus, broken), structure::InputError);
}
