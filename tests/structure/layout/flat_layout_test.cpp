#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/intrinsic/intrinsic_flattening.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/picture/layout_svg.h"
#include "mspline/structure/ricci/cone_placement.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/ricci/ricci_newton.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "mspline/structure/topology/topology.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using structure::Cone;
using structure::FlatLayout;
using structure::TriMesh;

namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

Eigen::Vector2d uv(const FlatLayout& layout, int face, int k) {
  return layout.cornerUV.row(3 * face + k).transpose();
}

// The metric's residual curvature (up to tolerance * 2 pi per vertex) is what the layout cannot
// close around; a tighter tolerance than the default leaves only round-off.
Eigen::VectorXd flatMetric(const TriMesh& mesh, const std::vector<Cone>& cones = {},
                           double tolerance = 1e-10) {
  structure::RicciNewtonOptions options;
  options.tolerance = tolerance;
  const auto result =
      structure::solveVertexScaling(mesh, structure::flatTarget(mesh, cones), options);
  INFO(result.message);
  REQUIRE(result.converged);
  return result.edgeLengths;
}

// Checks, from the per-corner UVs alone, that the layout realizes the metric: corners name the
// face's vertices, every triangle is positive, every edge has its metric length, the two sides of
// an uncut edge agree and the two sides of a cut edge are congruent.
FlatLayout layoutAndCheck(const std::string& name, const TriMesh& mesh,
                          const Eigen::VectorXd& lengths) {
  const FlatLayout layout = structure::layoutFlatMetric(mesh, lengths);
  WARN(name << ": " << layout.cutEdges.size() << " cut edges, " << layout.cones.size() << " cones, "
            << layout.flippedTriangles << " flipped, edge length error "
            << layout.maxEdgeLengthError << ", seam residual " << layout.maxSeamResidual
            << ", area ratio " << layout.minAreaRatio << " .. " << layout.maxAreaRatio << " (mean "
            << layout.meanAreaRatio << "), mean angle distortion " << layout.meanAngleDistortion);
  REQUIRE(layout.cornerUV.rows() == static_cast<Eigen::Index>(3 * mesh.n_faces()));
  REQUIRE(layout.cornerCopy.size() == 3 * mesh.n_faces());
  CHECK(layout.flippedTriangles == 0);
  CHECK(layout.maxEdgeLengthError <= 1e-9);
  CHECK(layout.maxLayoutAngleError <= 1e-9);
  CHECK(layout.maxSeamResidual <= 1e-9);
  CHECK(layout.minAreaRatio > 0.0);
  CHECK(layout.minAreaRatio <= layout.meanAreaRatio);
  CHECK(layout.meanAreaRatio <= layout.maxAreaRatio);

  std::vector<char> cut(mesh.n_edges(), 0);
  for (int e : layout.cutEdges) cut[e] = 1;
  int flipped = 0;
  double lengthError = 0.0;
  for (auto f : mesh.faces()) {
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      CHECK(layout.chartSourceVertex[layout.cornerCopy[3 * f.idx() + k]] == v.idx());
      CHECK((layout.chartPositions.row(layout.cornerCopy[3 * f.idx() + k]) -
             layout.cornerUV.row(3 * f.idx() + k))
                .norm() == 0.0);
      ++k;
    }
    if (cross(uv(layout, f.idx(), 1) - uv(layout, f.idx(), 0),
              uv(layout, f.idx(), 2) - uv(layout, f.idx(), 0)) <= 0.0)
      ++flipped;
    k = 0;
    for (auto h : mesh.fh_range(f)) {
      const double l = lengths[mesh.edge_handle(h).idx()];
      const double drawn = (uv(layout, f.idx(), k) - uv(layout, f.idx(), (k + 2) % 3)).norm();
      lengthError = std::max(lengthError, std::abs(drawn - l) / l);
      ++k;
    }
  }
  CHECK(flipped == 0);
  CHECK(lengthError <= 1e-9);
  // Uncut interior edges: both faces use the same two copies.
  for (auto e : mesh.edges()) {
    if (mesh.is_boundary(e) || cut[e.idx()]) continue;
    for (int side = 0; side < 2; ++side) {
      const auto h = mesh.halfedge_handle(e, side);
      const auto o = mesh.opposite_halfedge_handle(h);
      // Corner copies by halfedge: the corner at to_vertex(h).
      auto copyAt = [&](TriMesh::HalfedgeHandle g) {
        int k = 0;
        for (auto x = mesh.halfedge_handle(mesh.face_handle(g)); x != g;
             x = mesh.next_halfedge_handle(x))
          ++k;
        return layout.cornerCopy[3 * mesh.face_handle(g).idx() + k];
      };
      CHECK(copyAt(h) == copyAt(mesh.prev_halfedge_handle(o)));
    }
  }
  CHECK(layout.seams.size() == layout.cutEdges.size());
  for (const auto& seam : layout.seams) CHECK(cut[seam.edge]);
  return layout;
}

// The transition of a seam applied to the face0 side's endpoints must land on the face1 side's.
double seamMismatch(const TriMesh& mesh, const FlatLayout& layout,
                    const structure::SeamTransition& seam, const Eigen::Vector2d& translation,
                    double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Eigen::Matrix2d rotation;
  rotation << c, -s, s, c;
  double worst = 0.0;
  for (auto v0 : mesh.fv_range(TriMesh::FaceHandle(seam.face0))) {
    const auto e = TriMesh::EdgeHandle(seam.edge);
    const auto h = mesh.halfedge_handle(e, 0);
    if (v0 != mesh.from_vertex_handle(h) && v0 != mesh.to_vertex_handle(h)) continue;
    auto cornerOf = [&](int face, TriMesh::VertexHandle v) {
      int k = 0;
      for (auto w : mesh.fv_range(TriMesh::FaceHandle(face))) {
        if (w == v) return uv(layout, face, k);
        ++k;
      }
      FAIL("vertex not in face");
      return Eigen::Vector2d(0, 0);
    };
    const Eigen::Vector2d image = rotation * cornerOf(seam.face0, v0) + translation;
    worst = std::max(worst, (image - cornerOf(seam.face1, v0)).norm());
  }
  return worst / layout.diameter;
}

// A flat torus: pure translations, periods spanning the layout's area, every seam a lattice shift.
void checkFlatTorus(const std::string& name, const TriMesh& mesh, double tolerance) {
  const Eigen::VectorXd lengths = flatMetric(mesh, {}, tolerance);
  const FlatLayout layout = layoutAndCheck(name, mesh, lengths);
  CHECK(layout.cones.empty());
  REQUIRE(layout.hasPeriods);
  const Eigen::Vector2d p0 = layout.periods[0], p1 = layout.periods[1];
  WARN(name << ": periods (" << p0.x() << ", " << p0.y() << ") and (" << p1.x() << ", " << p1.y()
            << "), period residual " << layout.maxPeriodResidual << ", diameter "
            << layout.diameter);
  CHECK(layout.maxPeriodResidual <= 1e-9);
  // The fundamental parallelogram has the area of the torus.
  double area = 0.0;
  for (auto f : mesh.faces())
    area += 0.5 * cross(uv(layout, f.idx(), 1) - uv(layout, f.idx(), 0),
                        uv(layout, f.idx(), 2) - uv(layout, f.idx(), 0));
  CHECK(std::abs(std::abs(cross(p0, p1)) - area) <= 1e-9 * area);
  CHECK(
      (layout.fundamentalParallelogram[2] - layout.fundamentalParallelogram[0] - p0 - p1).norm() <=
      1e-12 * layout.diameter);

  Eigen::Matrix2d lattice;
  lattice << p0, p1;
  for (const auto& seam : layout.seams) {
    CHECK(std::abs(seam.angle) <= 1e-9);
    const Eigen::Vector2d mn = lattice.inverse() * seam.translation;
    CHECK(std::abs(mn.x() - std::round(mn.x())) <= 1e-9);
    CHECK(std::abs(mn.y() - std::round(mn.y())) <= 1e-9);
    const Eigen::Vector2d shift = lattice * mn.array().round().matrix();
    CHECK(seamMismatch(mesh, layout, seam, shift, 0.0) <= 1e-9);
  }
}

}  // namespace

TEST_CASE("flat_layout: knot1.off, genus 1 without cones", "[structure]") {
  const TriMesh mesh = test::realMesh("knot1.off");
  REQUIRE(structure::analyzeTopology(mesh).genus == 1);
  checkFlatTorus("knot1.off", mesh, 1e-10);
}

TEST_CASE("flat_layout: generated torus", "[structure]") {
  checkFlatTorus("generated torus", test::torus(32, 16), 1e-13);
}

TEST_CASE("flat_layout: icosphere with eight cones of pi/2", "[structure]") {
  const TriMesh mesh = test::icosphere(3);
  const std::vector<Cone> cones = test::cubeCornerCones(mesh);
  std::vector<int> coneVertices;
  for (const Cone& cone : cones) coneVertices.push_back(cone.vertex);
  const FlatLayout layout = layoutAndCheck("icosphere, 8 cones", mesh, flatMetric(mesh, cones));
  CHECK_FALSE(layout.hasPeriods);
  REQUIRE(layout.cones.size() == 8);
  for (const Cone& c : layout.cones) {
    CHECK(std::find(coneVertices.begin(), coneVertices.end(), c.vertex) != coneVertices.end());
    CHECK(std::abs(c.curvature - kPi / 2) <= 1e-9);
  }
  // Every cone lies on the cut, so that no cone is inside the disk.
  for (int v : coneVertices) {
    bool onCut = false;
    for (auto e : mesh.ve_range(TriMesh::VertexHandle(v)))
      onCut = onCut || std::binary_search(layout.cutEdges.begin(), layout.cutEdges.end(), e.idx());
    CHECK(onCut);
  }
  REQUIRE_FALSE(layout.seams.empty());
  int rotated = 0;
  for (const auto& seam : layout.seams) {
    const double quarters = seam.angle / (kPi / 2);
    CHECK(std::abs(quarters - std::round(quarters)) <= 1e-9);
    if (std::round(quarters) != 0.0) ++rotated;
    CHECK(seamMismatch(mesh, layout, seam, seam.translation, seam.angle) <= 1e-9);
  }
  CHECK(rotated > 0);
}

TEST_CASE("flat_layout: bounded disks lay out in one chart", "[structure]") {
  SECTION("a planar grid is laid out congruently, without distortion") {
    const TriMesh mesh = test::gridDisk(8);
    const FlatLayout layout = layoutAndCheck("planar grid", mesh, flatMetric(mesh));
    CHECK(layout.cutEdges.empty());
    CHECK(layout.chartPositions.rows() == static_cast<Eigen::Index>(mesh.n_vertices()));
    CHECK(std::abs(layout.minAreaRatio - 1.0) <= 1e-12);
    CHECK(std::abs(layout.maxAreaRatio - 1.0) <= 1e-12);
    CHECK(layout.maxAngleDistortion <= 1e-12);
    for (auto v : mesh.vertices())
      for (auto w : mesh.vertices()) {
        const auto d3 = (mesh.point(v) - mesh.point(w)).norm();
        CHECK(std::abs(
                  (layout.chartPositions.row(v.idx()) - layout.chartPositions.row(w.idx())).norm() -
                  d3) <= 1e-12);
      }
  }
  SECTION("a bump with the boundary held fixed") {
    TriMesh mesh = test::gridDisk(16);
    for (const auto v : mesh.vertices()) {
      auto p = mesh.point(v);
      p[2] = 0.4 * std::exp(-10.0 * ((p[0] - 0.5) * (p[0] - 0.5) + (p[1] - 0.4) * (p[1] - 0.4)));
      mesh.set_point(v, p);
    }
    const FlatLayout layout = layoutAndCheck("bumpy disk", mesh, flatMetric(mesh));
    CHECK(layout.cutEdges.empty());
    CHECK(layout.seams.empty());
    CHECK(layout.cones.empty());
    CHECK(layout.chartPositions.rows() == static_cast<Eigen::Index>(mesh.n_vertices()));
    // The bump has to shrink to lie flat inside a fixed boundary.
    CHECK(layout.minAreaRatio < 0.9);
    CHECK(layout.meanAngleDistortion > 1e-3);
  }
}

TEST_CASE("flat_layout: generated surfaces with automatic cones", "[structure]") {
  // Newton on the input triangulation, with flips (and doubling) where it degenerates, as flatten
  // does; the layout must have no flipped triangle.
  const std::pair<std::string, TriMesh> meshes[] = {{"torus(40, 16)", test::torus(40, 16)},
                                                    {"icosphere(3)", test::icosphere(3)},
                                                    {"doubleTorus(4)", test::doubleTorus(4)},
                                                    {"pairOfPants(6)", test::pairOfPants(6)}};
  for (const auto& [name, mesh] : meshes) {
    const auto cones = structure::placeCones(mesh).cones;
    const auto target = structure::flatTarget(mesh, cones);
    structure::RicciNewtonOptions options;
    options.tolerance = 1e-10 / (2 * kPi);
    const auto plain = structure::solveVertexScaling(mesh, target, options);
    FlatLayout layout;
    double error = plain.maxCurvatureError;
    if (plain.converged) {
      layout = structure::layoutFlatMetric(mesh, plain.edgeLengths);
    } else {
      const auto flipped = structure::flattenWithFlips(mesh, target, options);
      INFO(name << ": " << flipped.solve.ricci.message);
      REQUIRE(flipped.solve.ricci.converged);
      error = flipped.solve.ricci.maxCurvatureError;
      layout = structure::layoutFlatMetric(flipped.overlay.mesh, flipped.overlay.edgeLengths);
    }
    WARN(name << ": " << cones.size() << " cones, " << (plain.converged ? "no flips" : "flips")
              << ", error " << error << ", " << layout.flippedTriangles << " flipped");
    CHECK(error <= 1e-10);
    CHECK(layout.flippedTriangles == 0);
    CHECK(layout.maxEdgeLengthError <= 1e-8);
  }
}

TEST_CASE("flat_layout: bad edge lengths are input errors", "[structure]") {
  const TriMesh mesh = test::torus(8, 6);
  CHECK_THROWS_AS(structure::layoutFlatMetric(mesh, Eigen::VectorXd::Ones(3)),
                  structure::InputError);
  Eigen::VectorXd lengths = structure::edgeLengths(mesh);
  lengths[4] = 0.0;
  CHECK_THROWS_WITH(structure::layoutFlatMetric(mesh, lengths), Catch::Contains("edge 4"));
}

TEST_CASE("flat_layout: SVG pictures", "[structure]") {
  const TriMesh torus = test::torus(24, 12);
  const FlatLayout layout = structure::layoutFlatMetric(torus, flatMetric(torus));
  const std::string picture = structure::layoutSvg(torus, layout);
  CHECK(picture.rfind("<svg", 0) == 0);
  CHECK(test::countOf(picture, "<polygon") == torus.n_faces());
  CHECK(test::countOf(picture, "<line") == 2 * layout.cutEdges.size());
  CHECK(test::countOf(picture, "</svg>") == 1);

  structure::LayoutSvgOptions cover;
  cover.coverRadius = 1;
  const std::string tiled = structure::layoutSvg(torus, layout, cover);
  CHECK(tiled.rfind("<svg", 0) == 0);
  CHECK(test::countOf(tiled, "<polygon") == 9 * torus.n_faces());

  const TriMesh sphere = test::icosphere(2);
  const std::vector<Cone> cones = test::cubeCornerCones(sphere);
  const FlatLayout coned = structure::layoutFlatMetric(sphere, flatMetric(sphere, cones));
  const std::string sphereSvg = structure::layoutSvg(sphere, coned);
  CHECK(test::countOf(sphereSvg, "<polygon") == sphere.n_faces());
  // Each cone appears once per copy in the layout.
  std::size_t coneCopies = 0;
  for (int source : coned.chartSourceVertex)
    for (const Cone& c : coned.cones) coneCopies += (c.vertex == source);
  CHECK(test::countOf(sphereSvg, "<circle") == coneCopies);
  CHECK(coneCopies >= 8);
  CHECK_THROWS_AS(structure::layoutSvg(sphere, coned, cover), structure::InputError);
}
