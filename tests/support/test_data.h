#pragma once
// Real meshes fetched by scripts/fetch-data into data/ (git-ignored).
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "mspline/spline/core/spline_model.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::test {

/// Absolute path of a fetched real mesh, e.g. realMeshPath("knot1.off"). Fails the current test
/// with a message saying to run scripts/fetch-data when the file is missing.
std::string realMeshPath(const std::string& name);

/// The fetched real mesh, loaded and validated (fails the test if it is missing or invalid).
structure::TriMesh realMesh(const std::string& name);

/// The whole content of a file ("" when it cannot be read).
std::string fileText(const std::string& path);

/// The text up to its first line break.
std::string firstLine(const std::string& text);

/// How many times `word` occurs in `text` (overlapping occurrences too).
std::size_t countOf(const std::string& text, const std::string& word);

/// The mspline command built with the tests.
std::string cliPath();

/// A fresh empty directory for one test's files (removed at the start of the next run).
std::string scratchDirectory(const std::string& testName);

/// Runs a shell command, capturing stdout and stderr; exit code -1 means it died by a signal.
struct CommandResult {
  int exitCode = 0;
  std::string out;
  std::string err;
};
CommandResult runCommand(const std::string& commandLine);

/// Runs `mspline <arguments> --json` and returns its parsed standard output; the test stops,
/// showing the command's stderr, unless it exits with `expectedExit`.
nlohmann::json runJson(const std::string& arguments, int expectedExit = 0);

/// Fits a model of `kind` (tspline, tribspline, subd) to the real mesh `meshName` with
/// `mspline fit` and small budgets (`arguments` adds or overrides options), writes it to `path`
/// and returns `path`; fails the test when the fit fails.
std::string fitModel(const std::string& meshName, const std::string& kind, const std::string& path,
                     const std::string& arguments =
                         "--control 300 --max-control 500 --rounds 1 "
                         "--max-refinements 0");

/// The arguments of the small models tests share: one refinement round (T-junctions) and no more;
/// the rounds after it only add samples and took a minute of a sanitized test's time.
inline const std::string kSmallFit = "--control 300 --max-control 500 --max-refinements 1";

/// The model fitModel fits with these arguments, read back: fitted once per build of the command
/// and kept in the temporary directory, so that the test cases (processes) that use the same small
/// model share one fit.
const spline::SplineModel& fittedModel(const std::string& meshName, const std::string& kind,
                                       const std::string& arguments);

/// A small model of `kind` (tspline, tribspline, subd) fitted to head.off (kSmallFit), once per
/// kind and build: 3 holes filled for the fit, 4 cones.
const spline::SplineModel& headModel(const std::string& kind);

}  // namespace mspline::test
