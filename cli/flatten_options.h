#pragma once
// The flattening as the commands that need one (flatten, atlas, picture, voronoi, spline, fit)
// offer it: the flags, their conversion to structure::FlattenOptions, and the JSON report.
#include <string>

#include "cli/command.h"
#include "mspline/structure/flatten/flatten_surface.h"

namespace mspline::cli {

/// The command-line choices of the flattening; defaults as documented in addFlattenOptions.
struct FlattenSettings {
  std::string scheme = "yamabe";
  std::string cones = "auto";
  bool quantize = false;
  bool singleCone = false;
  std::string boundary = "free";
  double tolerance = 1e-10;
  int maxIterations = 100;
  bool quiet = false;
};

/// Whether `text` is a whole number written in decimal digits (e.g. a count given where a file
/// name is also accepted).
bool isCount(const std::string& text);

/// Parses a count (isCount) into `count`; false when it is not one or does not fit.
bool parseCount(const std::string& text, int& count);

/// Adds --scheme, --cones, --quantize, --single-cone, --boundary, --tolerance (named
/// `toleranceFlag`, for commands with a tolerance of their own), --max-iterations and -q/--quiet
/// to a subcommand.
void addFlattenOptions(CLI::App& sub, FlattenSettings& settings,
                       const std::string& toleranceFlag = "--tolerance");

/// Adds --min-corner-valence (2 or 3, default 3) to a subcommand that builds a quad layout: the
/// smallest valence of a cone's corner (see spline::FitOptions::minCornerValence).
void addCornerValenceOption(CLI::App& sub, int& minCornerValence);

/// The cone file --cones names, or "" when it names none (auto, none, a count, or unread because
/// of --single-cone).
std::string coneFile(const FlattenSettings& settings);

/// The library's options for flattening the surface read from `file`: --cones auto, none, a count
/// or a cone file (read here; IoError/InputError as readConeFile).
structure::FlattenOptions toFlattenOptions(const FlattenSettings& settings,
                                           const std::string& file);

/// The flattening's JSON report (file, scheme, cones, flips, the fallback's figures, convergence,
/// holonomy, distortions, seams, periods), its stage seconds appended to `stages`. When it did not
/// converge, throws SolverError with the report so far and `stages` in command.partialResult.
Json flatteningJson(const structure::Flattening& flattening,
                    const structure::FlattenOptions& options, Json& stages, Command& command);

}  // namespace mspline::cli
