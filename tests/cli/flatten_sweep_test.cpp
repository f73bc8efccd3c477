// Issue 3's robustness sweep: `mspline flatten` with automatic cones on every libcgal-demo mesh
// that `mspline info` accepts without problems and that has at least 1,000 faces. Prints one table
// row per mesh.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/test_data.h"

namespace fs = std::filesystem;
using mspline::test::cliPath;
using mspline::test::realMeshPath;
using mspline::test::runCommand;

TEST_CASE("flatten: every accepted libcgal-demo mesh with >= 1000 faces", "[cli][slow]") {
  const fs::path folder = fs::path(realMeshPath("knot1.off")).parent_path();
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.path().extension() == ".off") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  const std::string out = mspline::test::scratchDirectory("cli_flatten_sweep") + "/out.obj";

  int swept = 0, withFlips = 0;
  std::printf("%-34s %7s %5s %5s %5s %5s %6s %9s %7s %7s\n", "mesh", "faces", "genus", "bdry",
              "cones", "iters", "flips", "max|dK|", "flipped", "seconds");
  for (const auto& path : files) {
    const auto info = runCommand(cliPath() + " info --json '" + path.string() + "'");
    if (info.exitCode != 0) continue;
    const auto mesh = nlohmann::json::parse(info.out);
    if (!mesh["valid"].get<bool>() || !mesh["problems"].empty() || mesh["faces"].get<long>() < 1000)
      continue;
    ++swept;
    const auto run =
        runCommand(cliPath() + " flatten --json -q '" + path.string() + "' -o '" + out + "'");
    INFO(path.filename().string() << ": exit " << run.exitCode << "\n" << run.err);
    REQUIRE(run.exitCode == 0);
    const auto report = nlohmann::json::parse(run.out);
    std::printf("%-34s %7ld %5ld %5ld %5zu %5d %6ld %9.1e %7d %7.2f\n",
                path.filename().string().c_str(), mesh["faces"].get<long>(),
                mesh["genus"].get<long>(), mesh["boundaries"].get<long>(), report["cones"].size(),
                report["iterations"].get<int>(), report["flips"].get<long>(),
                report["max_curvature_error"].get<double>(), report["flipped_triangles"].get<int>(),
                report["seconds"].get<double>());
    withFlips += report["flips"].get<long>() > 0;
    CHECK(report["converged"] == true);
    CHECK(report["max_curvature_error"].get<double>() <= 1e-10);
    CHECK(report["flipped_triangles"] == 0);
  }
  std::printf("flatten sweep: %d meshes, %d of them needed intrinsic flips\n", swept, withFlips);
  std::fflush(stdout);
  // The fetched set has 57 such meshes; fewer means the data or the filter changed.
  CHECK(swept == 57);
}
