#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "mspline/spline/subd/catmull_clark_limit.h"
#include "mspline/spline/subd/subd_fit_space.h"
#include "mspline/spline/subd/subd_tessellate.h"
#include "mspline/spline/subd/tspline_osd.h"
#include "mspline/spline/tspline/tmesh.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_tessellate.h"
#include "mspline/structure/core/errors.h"
#include "support/test_tmeshes.h"

using namespace mspline;
using spline::FitBasisTerm;
using spline::SubdSpace;
using spline::TMesh;

namespace {

// Sum over the functions of value, ds, dt, dss, dst, dtt.
std::array<double, 6> sums(const std::vector<FitBasisTerm>& terms) {
  std::array<double, 6> s{};
  for (const FitBasisTerm& b : terms) {
    s[0] += b.value;
    s[1] += b.ds;
    s[2] += b.dt;
    s[3] += b.dss;
    s[4] += b.dst;
    s[5] += b.dtt;
  }
  return s;
}

// The surface of `control` and its derivatives from the basis (rows: value, ds, dt, dss, dst,
// dtt).
Eigen::Matrix<double, 6, 3> combine(const std::vector<FitBasisTerm>& terms,
                                    const Eigen::MatrixXd& control) {
  Eigen::Matrix<double, 6, 3> out = Eigen::Matrix<double, 6, 3>::Zero();
  for (const FitBasisTerm& b : terms) {
    const double w[6] = {b.value, b.ds, b.dt, b.dss, b.dst, b.dtt};
    for (int k = 0; k < 6; ++k) out.row(k) += w[k] * control.row(b.index);
  }
  return out;
}

}  // namespace

TEST_CASE("subd_fit_space: on a periodic grid the functions are the uniform B-splines",
          "[spline]") {
  // Equal knot intervals of 2 along x and 0.5 along y: the chain rule to the face frame counts.
  std::vector<double> x, y;
  for (int i = 0; i <= 6; ++i) x.push_back(2.0 * i), y.push_back(0.5 * i);
  const TMesh mesh = spline::gridTMesh(x, y, true, true);
  const SubdSpace subd(mesh);
  const spline::TSplineSpace tspline(mesh);
  REQUIRE(subd.numBasis() == mesh.numVertices);
  REQUIRE(tspline.numBasis() == mesh.numVertices);
  std::mt19937 rng(7);
  std::vector<FitBasisTerm> terms;
  std::vector<spline::TSplineBasisValue> reference;
  double worst = 0.0;
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d p = test::randomPointIn(mesh.faces[std::size_t(f)], rng);
      subd.basisAt(f, p, terms, 2);
      tspline.basisAt(f, p, reference, 2);
      std::map<int, FitBasisTerm> byVertex;
      for (const FitBasisTerm& b : terms) {
        REQUIRE(byVertex.count(b.index) == 0);  // each index once
        byVertex[b.index] = b;
      }
      for (const auto& r : reference) {
        const FitBasisTerm b = byVertex[tspline.anchors()[std::size_t(r.anchor)].vertex];
        worst = std::max({worst, std::abs(b.value - r.value), std::abs(b.ds - r.ds),
                          std::abs(b.dt - r.dt), std::abs(b.dss - r.dss), std::abs(b.dst - r.dst),
                          std::abs(b.dtt - r.dtt)});
      }
      // Functions the T-spline does not have at p vanish there.
      double extra = 0.0;
      for (const FitBasisTerm& b : terms) {
        bool found = false;
        for (const auto& r : reference)
          found = found || tspline.anchors()[std::size_t(r.anchor)].vertex == b.index;
        if (!found) extra = std::max(extra, std::abs(b.value));
      }
      CHECK(extra < 1e-12);
    }
  CHECK(worst < 1e-12);
}

TEST_CASE("subd_fit_space: a partition of unity around extraordinary vertices", "[spline]") {
  const test::CubeTMesh cube = test::cubeTMesh(2);
  REQUIRE(cube.mesh.numExtraordinary() == 8);
  const SubdSpace subd(cube.mesh);
  std::mt19937 rng(11);
  std::vector<FitBasisTerm> terms;
  double worst = 0.0;
  for (int f = 0; f < cube.mesh.numFaces(); ++f)
    for (int k = 0; k < 10; ++k) {
      // Corners included: the extraordinary vertices themselves.
      const Eigen::Vector2d p = k == 0 ? Eigen::Vector2d::Zero()
                                       : test::randomPointIn(cube.mesh.faces[std::size_t(f)], rng);
      subd.basisAt(f, p, terms, 2);
      REQUIRE(!terms.empty());
      const auto s = sums(terms);
      worst = std::max(worst, std::abs(s[0] - 1.0));
      for (int m = 1; m < 6; ++m) worst = std::max(worst, std::abs(s[m]));
    }
  CHECK(worst < 1e-12);
}

TEST_CASE("subd_fit_space: the surface is CatmullClarkLimit's, derivatives included", "[spline]") {
  const test::CubeTMesh cube = test::cubeTMesh(3, 4);
  const SubdSpace subd(cube.mesh);
  const spline::CatmullClarkLimit limit(cube.vertexPoints,
                                        spline::catmullClarkNetFaces(cube.mesh, "test"));
  std::mt19937 rng(13);
  std::vector<FitBasisTerm> terms;
  double worst = 0.0;
  for (int f = 0; f < cube.mesh.numFaces(); ++f)
    for (int k = 0; k < 5; ++k) {
      const spline::TMeshFace& face = cube.mesh.faces[std::size_t(f)];
      const Eigen::Vector2d p = test::randomPointIn(face, rng);
      subd.basisAt(f, p, terms, 2);
      const Eigen::Matrix<double, 6, 3> s = combine(terms, cube.vertexPoints);
      const auto l = limit.evaluate(f, p.x() / face.width, p.y() / face.height, true);
      REQUIRE(l);
      const double w = face.width, h = face.height;
      worst = std::max({worst, (s.row(0).transpose() - l->position).norm(),
                        (w * s.row(1).transpose() - l->du).norm(),
                        (h * s.row(2).transpose() - l->dv).norm(),
                        (w * w * s.row(3).transpose() - l->duu).norm(),
                        (w * h * s.row(4).transpose() - l->duv).norm(),
                        (h * h * s.row(5).transpose() - l->dvv).norm()});
    }
  CHECK(worst < 1e-11);
}

TEST_CASE("subd_fit_space: derivatives are those of the values", "[spline]") {
  // Faces of width 2 and height 1 next to valence-3 vertices (Gregory end caps).
  const test::CubeTMesh cube = test::cubeTMesh(2, 5);
  const SubdSpace subd(cube.mesh);
  std::mt19937 rng(17);
  std::vector<FitBasisTerm> at, plus, minus;
  const double h = 1e-5;
  double worstFirst = 0.0, worstSecond = 0.0;
  for (int f = 0; f < cube.mesh.numFaces(); ++f)
    for (int k = 0; k < 6; ++k) {
      const spline::TMeshFace& face = cube.mesh.faces[std::size_t(f)];
      std::uniform_real_distribution<double> unit(0.1, 0.9);
      const Eigen::Vector2d p(unit(rng) * face.width, unit(rng) * face.height);
      subd.basisAt(f, p, at, 2);
      const Eigen::Matrix<double, 6, 3> s = combine(at, cube.vertexPoints);
      for (int axis = 0; axis < 2; ++axis) {
        const Eigen::Vector2d e = h * Eigen::Vector2d::Unit(axis);
        subd.basisAt(f, p + e, plus, 2);
        subd.basisAt(f, p - e, minus, 2);
        const Eigen::Matrix<double, 6, 3> difference =
            (combine(plus, cube.vertexPoints) - combine(minus, cube.vertexPoints)) / (2 * h);
        // d/ds of (value, ds, dt) is (ds, dss, dst); d/dt is (dt, dst, dtt).
        worstFirst = std::max(worstFirst, (difference.row(0) - s.row(axis == 0 ? 1 : 2)).norm());
        worstSecond = std::max({worstSecond, (difference.row(1) - s.row(axis == 0 ? 3 : 4)).norm(),
                                (difference.row(2) - s.row(axis == 0 ? 4 : 5)).norm()});
      }
    }
  CHECK(worstFirst < 1e-7);
  CHECK(worstSecond < 1e-5);
}

TEST_CASE("subd_fit_space: the fit space's quadrature integrates the faces' areas", "[spline]") {
  const TMesh mesh = spline::gridTMesh({0, 1, 3, 4}, {0, 2, 2.5});
  const SubdSpace subd(mesh);
  const spline::SubdFitSpace space(subd);
  std::vector<spline::FacePoint> nodes;
  std::vector<double> weights;
  space.quadrature(nodes, weights);
  REQUIRE(nodes.size() == 16 * std::size_t(mesh.numFaces()));
  double area = 0.0, moment = 0.0;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    area += weights[k];
    // x^3 y^3 over a face [0, w] x [0, h] is w^4 h^4 / 16: exact for the 4-point rule.
    moment += weights[k] * std::pow(nodes[k].position.x(), 3) * std::pow(nodes[k].position.y(), 3);
  }
  double expectedMoment = 0.0;
  for (const auto& face : mesh.faces)
    expectedMoment += std::pow(face.width, 4) * std::pow(face.height, 4) / 16.0;
  CHECK(std::abs(area - 4.0 * 2.5) < 1e-12);
  CHECK(std::abs(moment - expectedMoment) < 1e-12 * expectedMoment);
  // An open grid: the surface reaches the boundary (BoundaryRule::EdgeAndCorner) and its walks
  // stop there.
  std::vector<FitBasisTerm> terms;
  space.basisAt({0, {0.0, 0.0}}, terms, 1);
  CHECK(std::abs(sums(terms)[0] - 1.0) < 1e-12);
  const spline::FacePoint end = space.walk({0, {0.5, 0.5}}, {-3.0, 0.0});
  CHECK(end.face == 0);
  CHECK((end.position - Eigen::Vector2d(0.0, 0.5)).norm() < 1e-12);
}

TEST_CASE("subd_fit_space: T-junctions and bad points are refused", "[spline]") {
  CHECK_THROWS_AS(SubdSpace(test::stoppedLine()), structure::InputError);
  const SubdSpace subd(spline::gridTMesh(test::unitKnots(3), test::unitKnots(3)));
  std::vector<FitBasisTerm> terms;
  CHECK_THROWS_AS(subd.basisAt(9, {0.5, 0.5}, terms), structure::InputError);
  CHECK_THROWS_AS(subd.basisAt(0, {NAN, 0.5}, terms), structure::InputError);
  Eigen::Vector3d x;
  CHECK_THROWS_AS(subd.evaluate(Eigen::MatrixXd::Zero(3, 3), 0, {0.5, 0.5}, x),
                  structure::InputError);
}

TEST_CASE("subd_fit_space: the tessellation samples the limit surface watertight", "[spline]") {
  const test::CubeTMesh cube = test::cubeTMesh(2, 3);
  const SubdSpace subd(cube.mesh);
  const int r = 3;
  const spline::TMeshTessellation t = spline::tessellateSubd(subd, cube.vertexPoints, r);
  // Vertices, edges and faces of the closed net: V - E + F = 2 with 4 F = 2 E.
  const std::size_t faces = std::size_t(cube.mesh.numFaces()), edges = 2 * faces;
  CHECK(t.mesh.positions.size() ==
        std::size_t(cube.mesh.numVertices) + edges * (r - 1) + faces * (r - 1) * (r - 1));
  CHECK(t.mesh.faces.size() == 2 * faces * r * r);
  CHECK(t.holeVertices.empty());
  REQUIRE(t.normals.size() == t.mesh.positions.size());
  double worst = 0.0, worstNormal = 0.0;
  for (std::size_t v = 0; v < t.mesh.positions.size(); ++v) {
    Eigen::Vector3d x;
    REQUIRE(
        subd.evaluate(cube.vertexPoints, t.vertexPoints[v].face, t.vertexPoints[v].position, x));
    worst = std::max(worst, (x - Eigen::Vector3d(t.mesh.positions[v].data())).norm());
    worstNormal =
        std::max(worstNormal, std::abs(Eigen::Vector3d(t.normals[v].data()).norm() - 1.0));
  }
  CHECK(worst == 0.0);
  CHECK(worstNormal < 1e-12);
}
