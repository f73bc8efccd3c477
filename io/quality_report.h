#pragma once
// A surface's quality (spline/quality/surface_quality.h) as the user sees it: the `quality` object
// of `mspline fit|check|export --json` and of Python's fit_report and Model.quality, and one line
// of text. The object is returned as JSON text so that this header names no JSON library.
#include <string>

#include "mspline/spline/quality/surface_quality.h"

namespace mspline::io {

/// The `quality` object as compact JSON text: with_scan, distances (with a scan), folds,
/// smoothness, regularity, seconds; places as {position, face, uv} or null; NaN as null.
std::string qualityJson(const spline::SurfaceQuality& quality);

/// A short summary for text output (no trailing newline).
std::string qualitySummary(const spline::SurfaceQuality& quality);

}  // namespace mspline::io
