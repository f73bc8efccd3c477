#pragma once
// A surface's quality (spline/quality/surface_quality.h) as `fit`, `check` and `export` report it:
// the same `quality` object everywhere, and one line of text.
#include <string>

#include "cli/command.h"
#include "mspline/spline/quality/surface_quality.h"

namespace mspline::cli {

/// The `quality` object: distances (with a scan), folds, smoothness, regularity, seconds; places
/// as {position, face, uv}.
Json qualityJson(const spline::SurfaceQuality& quality);

/// A short summary for text output (no trailing newline).
std::string qualitySummary(const spline::SurfaceQuality& quality);

}  // namespace mspline::cli
