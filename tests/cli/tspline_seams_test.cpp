// The T-spline built by `mspline spline --kind tspline` on a real genus-2 mesh is C2 across every
// T-mesh edge, chart seams included (edges where the frames of the two cells turn): values and
// derivatives up to second order from the two sides agree, and finite differences across the
// edge match the second derivatives.
#include <catch2/catch.hpp>

#include <array>

#include <nlohmann/json.hpp>

#include "mspline/io/spline_model_file.h"
#include "mspline/spline/tspline/tspline.h"
#include "support/test_data.h"

using namespace mspline;

namespace {

struct Jet {
  Eigen::Vector3d value, ds, dt, dss, dst, dtt;
};

// Value and derivatives at p of face f, expressed along the axes of the frame mapped by `toFace`
// (the frame p is given in): derivatives pulled back through the quarter turn.
Jet jetAt(const spline::TSplineSpace& space, const spline::SplineModel& model, int f,
          const spline::QuarterMotion& toFace, const Eigen::Vector2d& p) {
  const auto point = space.evaluate(model.controlPoints, model.weights, f, toFace.apply(p), 2);
  const spline::QuarterMotion turn{toFace.quarterTurns, Eigen::Vector2d::Zero()};
  Eigen::Matrix2d r;
  r.col(0) = turn.rotate({1.0, 0.0});
  r.col(1) = turn.rotate({0.0, 1.0});
  Jet jet;
  jet.value = point.position;
  // d/dp = R^T d/dq, second derivatives R^T H R, per coordinate of the surface.
  for (int c = 0; c < 3; ++c) {
    const Eigen::Vector2d g = r.transpose() * Eigen::Vector2d(point.ds[c], point.dt[c]);
    Eigen::Matrix2d h;
    h << point.dss[c], point.dst[c], point.dst[c], point.dtt[c];
    const Eigen::Matrix2d hp = r.transpose() * h * r;
    jet.ds[c] = g.x(), jet.dt[c] = g.y();
    jet.dss[c] = hp(0, 0), jet.dst[c] = hp(0, 1), jet.dtt[c] = hp(1, 1);
  }
  return jet;
}

}  // namespace

TEST_CASE("tspline_seams: C2 across chart seams on eight.off", "[cli]") {
  const std::string dir = test::scratchDirectory("cli_tspline_seams");
  const std::string model = dir + "/eight.msp";
  const auto built =
      test::runCommand(test::cliPath() + " spline -q " + test::realMeshPath("eight.off") +
                       " --kind tspline --control 1500 -o " + model + " --json");
  INFO(built.err);
  REQUIRE(built.exitCode == 0);
  const spline::SplineModel loaded = io::readSplineModel(model);
  // The grid's figures: its cones, and how far from square its cells are.
  const auto grid = nlohmann::json::parse(built.out)["grid"];
  CHECK(grid["layout"] == "motorcycle graph");
  CHECK(grid["extraordinary_points"].get<int>() == loaded.tmesh.numExtraordinary());
  CHECK(grid["extraordinary_points"].get<int>() > 0);
  CHECK(grid["anisotropy_p99"].get<double>() >= 1.0);
  CHECK(grid["anisotropy_p99"].get<double>() <= grid["anisotropy"].get<double>());
  const spline::TSplineSpace space(loaded.tmesh);
  const spline::TMesh& mesh = space.mesh();
  const double scale =
      (loaded.controlPoints.colwise().maxCoeff() - loaded.controlPoints.colwise().minCoeff())
          .norm();
  // Faces of the layout's grid (no T-junction: the cells split around close cones have some) with
  // a function at each corner, off the cones' caps (C1 across their sides at best).
  const auto complete = [&](int f) {
    if (space.capFace(f) || mesh.faces[std::size_t(f)].vertices.size() != 4) return false;
    for (int v : mesh.faces[std::size_t(f)].vertices)
      if (space.anchorOfVertex()[std::size_t(v)] < 0) return false;
    return true;
  };
  int edges = 0, turnedEdges = 0;
  double jump0 = 0.0, jump1 = 0.0, jump2 = 0.0;
  // Steps of 1e-3 and 1e-4 cells: the third derivative jumps at knot lines, so the quotient's
  // error shrinks like the step, and would stay at half the jump if the second derivative jumped.
  const std::array<double, 2> steps{1e-3, 1e-4};
  std::array<double, 2> finiteDifference{0.0, 0.0};
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const auto& face = mesh.faces[std::size_t(f)];
    for (int k = 0; k < 4; ++k) {
      const int g = face.twinFace[std::size_t(k)];
      if (g < f || !complete(f) || !complete(g)) continue;
      const spline::QuarterMotion across = mesh.acrossEdge(f, k);
      const Eigen::Vector2d a = face.positions[std::size_t(k)],
                            b = face.positions[std::size_t((k + 1) % 4)];
      // Into f: the edge direction turned a quarter counter-clockwise.
      const Eigen::Vector2d inward =
          spline::QuarterMotion{1, Eigen::Vector2d::Zero()}.rotate(b - a);
      for (double t : {0.3, 0.7}) {
        const Eigen::Vector2d q = a + t * (b - a);
        const Jet here = jetAt(space, loaded, f, {}, q), there = jetAt(space, loaded, g, across, q);
        jump0 = std::max(jump0, (here.value - there.value).norm() / scale);
        jump1 = std::max(
            {jump1, (here.ds - there.ds).norm() / scale, (here.dt - there.dt).norm() / scale});
        jump2 = std::max({jump2, (here.dss - there.dss).norm() / scale,
                          (here.dst - there.dst).norm() / scale,
                          (here.dtt - there.dtt).norm() / scale});
        // Across the edge along `inward`: the first derivative's difference quotient against the
        // second derivative at the edge.
        const auto directional = [&](const Jet& jet) {
          return Eigen::Vector3d(inward.x() * jet.ds + inward.y() * jet.dt);
        };
        const Eigen::Vector3d second = inward.x() * inward.x() * here.dss +
                                       2.0 * inward.x() * inward.y() * here.dst +
                                       inward.y() * inward.y() * here.dtt;
        for (std::size_t i = 0; i < steps.size(); ++i) {
          const double h = steps[i];
          const Jet inside = jetAt(space, loaded, f, {}, q + h * inward);
          const Jet outside = jetAt(space, loaded, g, across, q - h * inward);
          finiteDifference[i] = std::max(
              finiteDifference[i],
              ((directional(inside) - directional(outside)) / (2.0 * h) - second).norm() / scale);
        }
      }
      ++edges;
      turnedEdges += across.quarterTurns != 0;
    }
  }
  WARN("edges " << edges << " (turned " << turnedEdges << "): jumps " << jump0 << " " << jump1
                << " " << jump2 << ", finite differences " << finiteDifference[0] << " "
                << finiteDifference[1]);
  CHECK(edges > 2000);
  CHECK(turnedEdges > 50);
  CHECK(jump0 <= 1e-13);
  CHECK(jump1 <= 1e-12);
  CHECK(jump2 <= 1e-11);
  CHECK(finiteDifference[1] <= 1e-4);
  CHECK(finiteDifference[1] <= finiteDifference[0] / 5.0);
}
