// `mspline spline --kind tspline`, `check`, `compare-osd` and `export` on T-spline models end to
// end: a real mesh, hand-made T-meshes with T-junctions and extraordinary points, bad input.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "mspline/io/load_mesh.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/structure/topology/topology.h"
#include "support/test_data.h"
#include "support/test_tmeshes.h"

namespace fs = std::filesystem;
using mspline::test::cliPath;
using mspline::test::realMeshPath;
using mspline::test::runCommand;
using mspline::test::runJson;
using namespace mspline;

namespace {

// A T-spline model on `mesh` with the given control points, unit weights and a one-triangle
// surface (the file needs one; the commands here do not look at it).
spline::SplineModel tsplineModel(const spline::TMesh& mesh, const Eigen::MatrixXd& control) {
  spline::SplineModel model;
  model.kind = spline::SplineKind::TSpline;
  model.tmesh = mesh;
  model.surfaceVertices = control.topRows(3);
  model.surfaceFaces = {{0, 1, 2}};
  const auto& face = mesh.faces[0];
  model.surfaceVertexTMeshPoints = {{0, Eigen::Vector2d(0.0, 0.0)},
                                    {0, Eigen::Vector2d(face.width, 0.0)},
                                    {0, Eigen::Vector2d(0.0, face.height)}};
  model.controlPoints = control;
  model.weights = Eigen::VectorXd::Ones(control.rows());
  return model;
}

// The surface of the cube [0, k]^3 in unit cells, control points at the lattice points scaled to
// [-1, 1]^3: 8 extraordinary vertices of valence 3.
spline::SplineModel cubeModel(int k) {
  const test::CubeTMesh cube = test::cubeTMesh(k);
  return tsplineModel(cube.mesh,
                      test::anchorControl(spline::TSplineSpace(cube.mesh), cube.latticePoints));
}

// The exported mesh's topology. `valid`: the mesh must also pass validation (no degenerate
// triangles among others).
structure::TopologyReport exportedTopology(const std::string& path, bool valid = true) {
  io::LoadOptions options;
  options.requireValid = valid;
  const auto loaded = io::loadMesh(path, options);
  REQUIRE(loaded.mesh.has_value());
  return structure::analyzeTopology(*loaded.mesh);
}

}  // namespace

TEST_CASE("tspline_cli: knot1 built, checked, compared with OpenSubdiv and exported",
          "[cli][slow]") {
  const std::string dir = mspline::test::scratchDirectory("cli_tspline_knot");
  const std::string model = dir + "/k.msp";
  const auto built = runJson("spline -q " + realMeshPath("knot1.off") +
                             " --kind tspline --cones none -o " + model);
  CHECK(built["control_points"].get<int>() > 0);
  CHECK(built["fit_max_error"].get<double>() < 0.01);
  const spline::SplineModel loaded = io::readSplineModel(model);
  REQUIRE(loaded.kind == spline::SplineKind::TSpline);
  const int faces = loaded.tmesh.numFaces();

  const auto check = runJson("check " + model);
  CHECK(check["passed"] == true);
  CHECK(check["max_chart_discrepancy"].get<double>() <= 1e-12);
  CHECK(check["partition_of_unity_error"].get<double>() <= 1e-12);

  // A seamless torus grid: every face is a regular Catmull-Clark patch and the same uniform
  // bicubic B-spline on both sides.
  const auto osd = runJson("compare-osd " + model + " --samples 20000 --seed 3");
  WARN("knot1 compare-osd: " << osd.dump());
  CHECK(osd["t_junctions"] == 0);
  CHECK(osd["extraordinary_points"] == 0);
  CHECK(osd["regular_faces"] == faces);
  CHECK(osd["irregular_faces"] == 0);
  CHECK(osd["faces_without_surface"] == 0);
  CHECK(osd["samples"] == 20000);
  CHECK(osd["regular_max_deviation"].get<double>() <= 1e-10);
  CHECK(osd["regular_max_derivative_deviation"].get<double>() <= 1e-10);
  CHECK(osd["irregular_max_deviation"].get<double>() == 0.0);
  CHECK(osd["mspline_points_per_second"].get<double>() > 0.0);
  CHECK(osd["osd_points_per_second"].get<double>() > 0.0);
  CHECK(osd["mspline_setup_seconds"].get<double>() >= 0.0);
  CHECK(osd["osd_setup_seconds"].get<double>() >= 0.0);

  // Export: a closed torus, r^2 vertices and 2 r^2 triangles per face (a grid: as many edges per
  // face as two, vertices as faces), close to the mesh it was fitted to.
  const int r = 3;
  const std::string obj = dir + "/k.obj";
  const auto exported =
      runJson("export " + model + " -o " + obj + " --resolution " + std::to_string(r));
  CHECK(exported["vertices"] == r * r * faces);
  CHECK(exported["faces"] == 2 * r * r * faces);
  CHECK(exported["hole_samples"] == 0);
  CHECK(exported["min_denominator"].get<double>() == Approx(1.0).margin(1e-12));
  const auto topology = exportedTopology(obj);
  CHECK(topology.closed);
  CHECK(topology.components == 1);
  CHECK(topology.genus == 1);
  CHECK(topology.faces == std::size_t(2 * r * r * faces));
  const auto surface = io::loadMesh(obj).soup;
  Eigen::Array3d lo = Eigen::Array3d::Constant(INFINITY), hi = -lo;
  for (const auto& p : surface.positions) {
    lo = lo.min(Eigen::Array3d(p[0], p[1], p[2]));
    hi = hi.max(Eigen::Array3d(p[0], p[1], p[2]));
  }
  const Eigen::Array3d meshLo = loaded.surfaceVertices.colwise().minCoeff().transpose().array();
  const Eigen::Array3d meshHi = loaded.surfaceVertices.colwise().maxCoeff().transpose().array();
  const double diagonal = (meshHi - meshLo).matrix().norm();
  CHECK((lo - meshLo).abs().maxCoeff() <= 0.01 * diagonal);
  CHECK((hi - meshHi).abs().maxCoeff() <= 0.01 * diagonal);
  const auto ply = runJson("export " + model + " -o " + dir + "/k.ply --resolution 1");
  CHECK(ply["faces"] == 2 * faces);
  CHECK(exportedTopology(dir + "/k.ply").genus == 1);
}

TEST_CASE("tspline_cli: T-junctions are refused by compare-osd, extraordinary points reported",
          "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("cli_tspline_tmeshes");
  std::srand(5);
  const spline::TMesh block = test::mergedBlock();
  const int blockBasis = spline::TSplineSpace(block).numBasis();
  io::writeSplineModel(dir + "/block.msp",
                       tsplineModel(block, Eigen::MatrixXd::Random(blockBasis, 3)));
  const auto refused = runCommand(cliPath() + " compare-osd " + dir + "/block.msp");
  CHECK(refused.exitCode == 2);
  CHECK_THAT(refused.err, Catch::Contains("block.msp") && Catch::Contains("T-junctions"));
  const auto refusedJson = runJson("compare-osd " + dir + "/block.msp", 2);
  CHECK(refusedJson["error"]["kind"] == "input");
  // The same model exports: an open disk (the block's face stitched to its 8 boundary edges).
  const auto exported =
      runJson("export " + dir + "/block.msp -o " + dir + "/block.obj --resolution 4");
  CHECK(exported["hole_samples"] == 0);
  const auto blockTopology = exportedTopology(dir + "/block.obj");
  CHECK(blockTopology.components == 1);
  CHECK(blockTopology.boundaryLoops == 1);
  CHECK(blockTopology.genus == 0);

  // A cube: 8 valence-3 vertices with caps; compare-osd compares them with Gregory patches.
  const int k = 8;
  io::writeSplineModel(dir + "/cube.msp", cubeModel(k));
  const auto cube = runJson("compare-osd " + dir + "/cube.msp --samples 4000");
  WARN("cube compare-osd: " << cube.dump());
  CHECK(cube["t_junctions"] == 0);
  CHECK(cube["extraordinary_points"] == 8);
  // The 3 cap faces around each corner; every other face is OpenSubdiv's regular patch.
  CHECK(cube["irregular_faces"] == 8 * 3);
  CHECK(cube["regular_faces"] == 6 * k * k - 8 * 3);
  CHECK(cube["regular_max_deviation"].get<double>() <= 1e-12);
  CHECK(cube["irregular_max_deviation"].get<double>() > 0.0);
  const auto text = runCommand(cliPath() + " compare-osd " + dir + "/cube.msp --samples 1000");
  CHECK(text.exitCode == 0);
  CHECK_THAT(text.out, Catch::Contains("1000 samples on 360 regular and 24 irregular faces"));
  const auto cubeExport =
      runJson("export " + dir + "/cube.msp -o " + dir + "/cube.obj --resolution 2");
  CHECK(cubeExport["hole_samples"] == 0);
  CHECK(cubeExport["collapsed_edge_samples"] == 0);
  CHECK(cubeExport["min_denominator"].get<double>() == Approx(1.0).margin(1e-12));
  // The cone points are sampled themselves: a valid closed mesh, no degenerate triangle.
  const auto cubeTopology = exportedTopology(dir + "/cube.obj");
  CHECK(cubeTopology.closed);
  CHECK(cubeTopology.genus == 0);
  CHECK(cubeTopology.components == 1);
  CHECK(mspline::test::fileText(dir + "/cube.obj").find("nan") == std::string::npos);
}

TEST_CASE("tspline_cli: bad input exits 2 naming the file, writing nothing", "[cli]") {
  const std::string dir = mspline::test::scratchDirectory("cli_tspline_bad");
  // A triangular B-spline model.
  runJson("spline -q " + realMeshPath("knot1.off") + " --cones none --control 500 -o " + dir +
          "/tri.msp");
  const auto triangular = runCommand(cliPath() + " compare-osd " + dir + "/tri.msp");
  CHECK(triangular.exitCode == 2);
  CHECK_THAT(triangular.err,
             Catch::Contains("tri.msp") && Catch::Contains("compare-osd needs a T-spline model"));

  // A truncated T-spline model.
  io::writeSplineModel(dir + "/cube.msp", cubeModel(5));
  const std::string bytes = mspline::test::fileText(dir + "/cube.msp");
  std::ofstream(dir + "/cut.msp", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  for (const std::string& name : {std::string("cut.msp"), std::string("missing.msp")}) {
    INFO(name);
    const auto compared = runCommand(cliPath() + " compare-osd " + dir + "/" + name);
    CHECK(compared.exitCode == 2);
    CHECK_THAT(compared.err, Catch::Contains(name));
    const auto exported =
        runCommand(cliPath() + " export " + dir + "/" + name + " -o " + dir + "/out.obj");
    CHECK(exported.exitCode == 2);
    CHECK_THAT(exported.err, Catch::Contains(name));
    CHECK_FALSE(fs::exists(dir + "/out.obj"));
  }
  const auto badResolution =
      runCommand(cliPath() + " export " + dir + "/cube.msp -o " + dir + "/out.obj --resolution 0");
  CHECK(badResolution.exitCode == 1);
  CHECK_FALSE(fs::exists(dir + "/out.obj"));
}
