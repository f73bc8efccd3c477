#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "mspline/io/atlas_file.h"
#include "mspline/structure/atlas/affine_atlas.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/ricci/ricci_newton.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;

TEST_CASE("atlas_file: round trip of a flat torus atlas", "[io]") {
  const auto mesh = test::torus(24, 10);
  const auto flow = structure::solveVertexScaling(mesh, structure::flatTarget(mesh, {}));
  REQUIRE(flow.converged);
  const auto layout = structure::layoutFlatMetric(mesh, flow.edgeLengths);
  const auto atlas = structure::buildAffineAtlas(mesh, flow.edgeLengths, layout);
  const std::string dir = test::scratchDirectory("io_atlas_file");
  io::writeAtlas(dir + "/torus.json", mesh, atlas);
  const auto back = io::readAtlas(dir + "/torus.json");
  CHECK(back.mesh.n_faces() == mesh.n_faces());
  REQUIRE(back.atlas.charts.size() == atlas.charts.size());
  REQUIRE(back.atlas.transitions.size() == atlas.transitions.size());
  for (std::size_t c = 0; c < atlas.charts.size(); ++c) {
    CHECK(back.atlas.charts[c].vertices == atlas.charts[c].vertices);
    CHECK(back.atlas.charts[c].faces == atlas.charts[c].faces);
    CHECK(back.atlas.charts[c].positions == atlas.charts[c].positions);  // bit for bit
  }
  for (std::size_t t = 0; t < atlas.transitions.size(); ++t) {
    CHECK(back.atlas.transitions[t].motion.angle == atlas.transitions[t].motion.angle);
    CHECK(back.atlas.transitions[t].motion.translation == atlas.transitions[t].motion.translation);
  }
  CHECK(back.atlas.kind == structure::TransitionKind::Translation);
  CHECK(back.atlas.maxTransitionResidual == atlas.maxTransitionResidual);
  CHECK(back.atlas.maxCocycleResidual == atlas.maxCocycleResidual);
}

TEST_CASE("atlas_file: broken files are input errors naming the file", "[io]") {
  const auto mesh = test::torus(12, 6);
  const auto flow = structure::solveVertexScaling(mesh, structure::flatTarget(mesh, {}));
  const auto layout = structure::layoutFlatMetric(mesh, flow.edgeLengths);
  const auto atlas = structure::buildAffineAtlas(mesh, flow.edgeLengths, layout);
  const std::string dir = test::scratchDirectory("io_atlas_file_bad");
  const std::string good = dir + "/good.json";
  io::writeAtlas(good, mesh, atlas);
  const std::string text = mspline::test::fileText(good);

  const auto expectInputError = [&](const std::string& name, const std::string& content,
                                    const std::string& words) {
    const std::string path = dir + "/" + name;
    std::ofstream(path) << content;
    INFO(name);
    try {
      io::readAtlas(path);
      FAIL("no error");
    } catch (const structure::InputError& error) {
      const std::string message = error.what();
      CHECK(message.find(path) != std::string::npos);
      INFO(message);
      CHECK(message.find(words) != std::string::npos);
    }
  };
  expectInputError("truncated.json", text.substr(0, text.size() / 2), "not a JSON atlas");
  std::string wrongFormat = text;
  wrongFormat.replace(wrongFormat.find("mspline-atlas"), 13, "something-else");
  expectInputError("format.json", wrongFormat, "format");
  std::string badVertex = text;
  badVertex.replace(badVertex.find("\"vertex\":0"), 10, "\"vertex\":99999");
  expectInputError("vertex.json", badVertex, "vertex 99999");
  const std::size_t from = text.find("\"transitions\":[") + 15, to = text.find("],\"version\"");
  REQUIRE(to != std::string::npos);
  const std::string noTransitions = text.substr(0, from) + text.substr(to);
  expectInputError("transitions.json", noTransitions, "no transition");
  // Numbers where an index belongs, strings where a number does, numbers that overflow (JSON
  // refuses them), faces that repeat a vertex (issue 17).
  const auto replaced = [&](const std::string& original, const std::string& replacement) {
    std::string changed = text;
    const std::size_t at = changed.find(original);
    REQUIRE(at != std::string::npos);
    return changed.replace(at, original.size(), replacement);
  };
  expectInputError("fraction.json", replaced("\"vertex\":0", "\"vertex\":0.5"), "no index");
  expectInputError("unsigned.json", replaced("\"vertex\":0", "\"vertex\":18446744073709551615"),
                   "vertex 18446744073709551615");
  expectInputError("negative.json", replaced("\"vertex\":0", "\"vertex\":-1"), "vertex -1");
  expectInputError("coordinate.json", replaced("\"vertices\":[[", "\"vertices\":[[\"1\",0,0],["),
                   "a coordinate of vertex 0 is not a number");
  expectInputError("infinite.json", replaced("\"diameter\":", "\"diameter\":1e999,\"x\":"),
                   "not a JSON atlas");
  expectInputError("string.json", replaced("\"diameter\":", "\"diameter\":\"1\",\"x\":"),
                   "the diameter is not a number");
  expectInputError("repeated.json", replaced("\"faces\":[[", "\"faces\":[[0,0,1],["),
                   "a face repeats a vertex");
  std::filesystem::create_directories(dir + "/folder.json");
  CHECK_THROWS_AS(io::readAtlas(dir + "/folder.json"), structure::IoError);
  CHECK_THROWS_AS(io::readAtlas(dir + "/missing.json"), structure::IoError);
}
