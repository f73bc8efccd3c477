#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <queue>
#include <random>

#include <Eigen/Dense>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/layout/flat_torus_voronoi.h"
#include "mspline/structure/picture/torus_voronoi_svg.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/ricci/ricci_newton.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::FlatLayout;
using structure::SurfacePoint;
using structure::TorusVoronoi;
using structure::TriMesh;

namespace {

FlatLayout flatLayout(const TriMesh& mesh, const std::vector<structure::Cone>& cones = {}) {
  structure::RicciNewtonOptions options;
  options.tolerance = 1e-13;
  const auto flow =
      structure::solveVertexScaling(mesh, structure::flatTarget(mesh, cones), options);
  REQUIRE(flow.converged);
  return structure::layoutFlatMetric(mesh, flow.edgeLengths);
}

Eigen::Vector2d layoutPoint(const FlatLayout& layout, const SurfacePoint& p) {
  return layout.cornerUV.middleRows(3 * p.face, 3).transpose() * p.barycentric;
}

// Distances on the torus by brute force over the deck translations with |m|, |n| <= 4, from
// layout positions as they are (not reduced into a fundamental domain).
struct BruteForce {
  const FlatLayout& layout;
  std::vector<Eigen::Vector2d> sites;

  double distance(const Eigen::Vector2d& x, int site) const {
    double best = std::numeric_limits<double>::infinity();
    for (int m = -4; m <= 4; ++m)
      for (int n = -4; n <= 4; ++n)
        best = std::min(best,
                        (x - sites[site] - m * layout.periods[0] - n * layout.periods[1]).norm());
    return best;
  }
  // The nearest site, or -1 when the two nearest are within 1e-9 (either label is right).
  int nearest(const Eigen::Vector2d& x) const {
    std::vector<std::pair<double, int>> order;
    for (std::size_t s = 0; s < sites.size(); ++s) order.push_back({distance(x, int(s)), int(s)});
    std::sort(order.begin(), order.end());
    if (order.size() > 1 && order[1].first - order[0].first <= 1e-9 * order[1].first) return -1;
    return order[0].second;
  }
};

// Components of faces labelled alike and sharing an edge: the component of every face.
// Components of equally labelled faces, joined across shared edges (or, with `throughVertices`,
// shared vertices).
std::vector<int> labelComponents(const TriMesh& mesh, const std::vector<int>& label,
                                 bool throughVertices = false) {
  std::vector<int> component(mesh.n_faces(), -1);
  int count = 0;
  for (auto f : mesh.faces()) {
    if (component[f.idx()] >= 0) continue;
    std::queue<TriMesh::FaceHandle> queue;
    queue.push(f);
    component[f.idx()] = count;
    while (!queue.empty()) {
      const auto g = queue.front();
      queue.pop();
      const auto visit = [&](TriMesh::FaceHandle h) {
        if (component[h.idx()] < 0 && label[h.idx()] == label[g.idx()]) {
          component[h.idx()] = count;
          queue.push(h);
        }
      };
      if (throughVertices) {
        for (auto v : mesh.fv_range(g))
          for (auto h : mesh.vf_range(v)) visit(h);
      } else {
        for (auto h : mesh.ff_range(g)) visit(h);
      }
    }
    ++count;
  }
  return component;
}

double longestLayoutEdge(const FlatLayout& layout, int face) {
  double longest = 0.0;
  for (int k = 0; k < 3; ++k)
    longest = std::max(
        longest,
        (layout.cornerUV.row(3 * face + k) - layout.cornerUV.row(3 * face + (k + 1) % 3)).norm());
  return longest;
}

TorusVoronoi checkVoronoi(const std::string& name, const TriMesh& mesh, const FlatLayout& layout,
                          const std::vector<SurfacePoint>& sites) {
  REQUIRE(layout.hasPeriods);
  // How far the layout reaches in lattice coordinates: a span below 2.5 keeps every nearest
  // translation within |m|, |n| <= 4 for the brute force (see flat_torus_voronoi.cpp).
  Eigen::Matrix2d basis;
  basis << layout.periods[0], layout.periods[1];
  Eigen::Vector2d low = Eigen::Vector2d::Constant(1e300), high = -low;
  for (Eigen::Index k = 0; k < layout.cornerUV.rows(); ++k) {
    const Eigen::Vector2d mn = basis.inverse() * layout.cornerUV.row(k).transpose();
    low = low.cwiseMin(mn);
    high = high.cwiseMax(mn);
  }
  const TorusVoronoi voronoi = structure::flatTorusVoronoi(mesh, layout, sites);
  const int siteCount = static_cast<int>(sites.size());
  WARN(name << ": " << sites.size() << " sites, " << voronoi.cells << " cells, "
            << voronoi.replicatedSites << " replicated sites, " << voronoi.segments.size()
            << " segments, " << voronoi.polylines.size() << " polylines, equidistance error "
            << voronoi.maxEquidistanceError << ", layout span " << (high - low).transpose()
            << " periods");
  REQUIRE((high - low).maxCoeff() < 2.5);
  REQUIRE(voronoi.faceLabel.size() == mesh.n_faces());
  REQUIRE(voronoi.vertexLabel.size() == mesh.n_vertices());
  CHECK(voronoi.replicatedSites == 9 * siteCount);
  CHECK(voronoi.maxEquidistanceError <= 1e-12);

  BruteForce brute{layout, {}};
  for (const SurfacePoint& site : sites) brute.sites.push_back(layoutPoint(layout, site));
  int wrongFaces = 0, ties = 0;
  for (auto f : mesh.faces()) {
    const int nearest =
        brute.nearest(layoutPoint(layout, {f.idx(), Eigen::Vector3d::Constant(1.0 / 3.0)}));
    ties += nearest < 0;
    wrongFaces += nearest >= 0 && nearest != voronoi.faceLabel[f.idx()];
  }
  CHECK(wrongFaces == 0);
  CHECK(ties == 0);
  int wrongVertices = 0;
  for (auto f : mesh.faces()) {
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      Eigen::Vector3d corner = Eigen::Vector3d::Zero();
      corner[k++] = 1.0;
      const int nearest = brute.nearest(layoutPoint(layout, {f.idx(), corner}));
      wrongVertices += nearest >= 0 && nearest != voronoi.vertexLabel[v.idx()];
    }
  }
  CHECK(wrongVertices == 0);

  // Cells are connected, up to faces straddling a cell boundary (a centroid in a thin wedge of
  // a cell near a junction): a face outside the largest component of its label has its centroid
  // within its own size of the bisector with another site (d2 - d1 <= 2 * distance to it).
  // Each site's face is in its cell's largest component unless another site is nearer to the
  // face's centroid, which it then is by less than the face's size.
  const std::vector<int> component = labelComponents(mesh, voronoi.faceLabel);
  std::vector<int> componentSize(mesh.n_faces(), 0), largest(siteCount, -1);
  for (int c : component) ++componentSize[c];
  for (auto f : mesh.faces()) {
    int& l = largest[voronoi.faceLabel[f.idx()]];
    if (l < 0 || componentSize[component[f.idx()]] > componentSize[l]) l = component[f.idx()];
  }
  CHECK(siteCount - std::count(largest.begin(), largest.end(), -1) == voronoi.cells);
  auto straddles = [&](int face) {
    const Eigen::Vector2d x = layoutPoint(layout, {face, Eigen::Vector3d::Constant(1.0 / 3.0)});
    std::vector<double> d;
    for (int s = 0; s < siteCount; ++s) d.push_back(brute.distance(x, s));
    std::sort(d.begin(), d.end());
    return d.size() > 1 && d[1] - d[0] <= 2.0 * longestLayoutEdge(layout, face);
  };
  int stray = 0, strayFar = 0, sitesElsewhere = 0, sitesElsewhereFar = 0;
  for (auto f : mesh.faces())
    if (component[f.idx()] != largest[voronoi.faceLabel[f.idx()]]) {
      ++stray;
      strayFar += !straddles(f.idx());
    }
  for (int s = 0; s < siteCount; ++s)
    if (component[sites[s].face] != largest[s]) {
      ++sitesElsewhere;
      sitesElsewhereFar += !straddles(sites[s].face);
    }
  WARN(name << ": " << stray << " faces outside their cell's largest component, " << sitesElsewhere
            << " sites whose face is not in their cell's largest component");
  CHECK(strayFar == 0);
  CHECK(sitesElsewhereFar == 0);
  CHECK(stray <= siteCount);  // the odd face at a junction, not whole pieces of cells
  // Through shared vertices every cell is one piece.
  const std::vector<int> pieces = labelComponents(mesh, voronoi.faceLabel, true);
  CHECK(*std::max_element(pieces.begin(), pieces.end()) + 1 == voronoi.cells);

  // Boundary points on edges are equidistant to their two sites, and the segments chain up.
  int onEdges = 0, unequal = 0;
  for (const auto& segment : voronoi.segments) {
    CHECK(segment.cells[0] < segment.cells[1]);
    CHECK(segment.ends[0].face == segment.ends[1].face);
    CHECK(segment.ends[0].barycentric.minCoeff() == 0.0);
    for (const SurfacePoint& end : segment.ends) {
      if (end.barycentric.minCoeff() != 0.0) continue;
      ++onEdges;
      const Eigen::Vector2d x = layoutPoint(layout, end);
      const double a = brute.distance(x, segment.cells[0]), b = brute.distance(x, segment.cells[1]);
      unequal += std::abs(a - b) > 1e-9 * std::max(a, b);
    }
  }
  CHECK(onEdges >= int(voronoi.segments.size()));
  CHECK(unequal == 0);
  std::size_t chained = 0;
  for (const auto& polyline : voronoi.polylines) {
    REQUIRE(polyline.points.size() >= 2);
    chained += polyline.points.size() - 1;
    if (polyline.closed) CHECK(polyline.points.front() == polyline.points.back());
  }
  CHECK(chained == voronoi.segments.size());
  return voronoi;
}

}  // namespace

TEST_CASE("flat_torus_voronoi: knot1.off with 20 random sites", "[structure]") {
  const TriMesh mesh = test::realMesh("knot1.off");
  const FlatLayout layout = flatLayout(mesh);
  const auto sites = structure::randomSurfacePoints(mesh, 20, 1);
  const TorusVoronoi voronoi = checkVoronoi("knot1.off", mesh, layout, sites);
  CHECK(voronoi.cells == 20);
  CHECK_FALSE(voronoi.polylines.empty());
  for (int s = 0; s < 20; ++s) CHECK(voronoi.faceLabel[sites[s].face] == s);

  // One copy around the fundamental parallelogram is enough: two give the same diagram.
  structure::TorusVoronoiOptions wide;
  wide.windowRadius = 2;
  const TorusVoronoi wider = structure::flatTorusVoronoi(mesh, layout, sites, wide);
  CHECK(wider.replicatedSites == 25 * 20);
  CHECK(wider.faceLabel == voronoi.faceLabel);
  CHECK(wider.vertexLabel == voronoi.vertexLabel);

  const std::string picture = structure::torusVoronoiSvg(mesh, layout, sites, voronoi);
  CHECK(picture.rfind("<svg", 0) == 0);
  CHECK(test::countOf(picture, "<polygon") == mesh.n_faces());
  CHECK(test::countOf(picture, "<line") == voronoi.segments.size());
  CHECK(test::countOf(picture, "<circle") == sites.size());
  structure::TorusVoronoiSvgOptions cover;
  cover.coverRadius = 1;
  const std::string tiled = structure::torusVoronoiSvg(mesh, layout, sites, voronoi, cover);
  CHECK(test::countOf(tiled, "<polygon") == 9 * mesh.n_faces());
  CHECK(test::countOf(tiled, "<circle") == 9 * sites.size());
  cover.coverRadius = -1;
  CHECK_THROWS_AS(structure::torusVoronoiSvg(mesh, layout, sites, voronoi, cover),
                  structure::InputError);
}

TEST_CASE("flat_torus_voronoi: generated torus", "[structure]") {
  const TriMesh mesh = test::torus(32, 16);
  const FlatLayout layout = flatLayout(mesh);
  for (int count : {1, 2, 7, 30}) {
    const TorusVoronoi voronoi =
        checkVoronoi("torus(32, 16), " + std::to_string(count) + " sites", mesh, layout,
                     structure::randomSurfacePoints(mesh, count, 5));
    if (count == 1) {
      // A single site's copies form a lattice, cocircular everywhere: one cell, no boundary.
      CHECK(voronoi.cells == 1);
      CHECK(voronoi.segments.empty());
    }
  }
}

TEST_CASE("flat_torus_voronoi: input errors", "[structure]") {
  SECTION("surfaces that are no flat torus") {
    const TriMesh sphere = test::icosphere(2);
    const FlatLayout coned = flatLayout(sphere, test::cubeCornerCones(sphere));
    CHECK_THROWS_AS(structure::flatTorusVoronoi(sphere, coned, {{0, {1, 0, 0}}}),
                    structure::InputError);
    const TriMesh disk = test::gridDisk(6);
    CHECK_THROWS_WITH(structure::flatTorusVoronoi(disk, flatLayout(disk), {{0, {1, 0, 0}}}),
                      Catch::Contains("no periods"));
  }
  SECTION("bad sites and options") {
    const TriMesh mesh = test::torus(12, 8);
    const FlatLayout layout = flatLayout(mesh);
    CHECK_THROWS_WITH(structure::flatTorusVoronoi(mesh, layout, {}), Catch::Contains("no sites"));
    CHECK_THROWS_WITH(
        structure::flatTorusVoronoi(mesh, layout, {{0, {1, 0, 0}}, {9999, {1, 0, 0}}}),
        Catch::Contains("site 1: face 9999 is out of range"));
    CHECK_THROWS_WITH(structure::flatTorusVoronoi(mesh, layout, {{3, {0.5, 0.6, 0}}}),
                      Catch::Contains("site 0: barycentric"));
    // The same vertex named from two faces: one point of the torus.
    const auto h = mesh.halfedge_handle(TriMesh::FaceHandle(0));
    const auto g = mesh.opposite_halfedge_handle(h);
    auto cornerAt = [&](TriMesh::FaceHandle f, TriMesh::VertexHandle v) {
      SurfacePoint p{f.idx(), Eigen::Vector3d::Zero()};
      int k = 0;
      for (auto w : mesh.fv_range(f)) p.barycentric[k++] = w == v ? 1.0 : 0.0;
      return p;
    };
    const auto v = mesh.to_vertex_handle(h);
    CHECK_THROWS_WITH(structure::flatTorusVoronoi(mesh, layout,
                                                  {cornerAt(TriMesh::FaceHandle(0), v),
                                                   {5, {0.2, 0.3, 0.5}},
                                                   cornerAt(mesh.face_handle(g), v)}),
                      Catch::Contains("sites 0 and 2 are the same point"));
    structure::TorusVoronoiOptions narrow;
    narrow.windowRadius = 0;
    CHECK_THROWS_AS(structure::flatTorusVoronoi(mesh, layout, {{0, {1, 0, 0}}}, narrow),
                    structure::InputError);
  }
}
