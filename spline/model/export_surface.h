#pragma once
// A spline model's surface ready to write as a triangle mesh: tessellated at a given resolution
// or at the one a chord tolerance asks for, with normals and chart coordinates, the faces over a
// scan's filled holes trimmed away, and optionally the control net. Writing the files is io's
// (io/export_model.h): this computes only.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mspline/spline/core/spline_model.h"
#include "mspline/spline/model/model_surface.h"

namespace mspline::spline {

struct ExportOptions {
  /// Segments along each domain side or T-mesh edge (>= 1); used when `tolerance` is 0.
  int resolution = 8;
  /// > 0: instead of `resolution`, the smallest resolution whose chord error estimate
  /// h^2 max|x''| / 8 (h the longest grid edge of a piece, x'' the second derivatives at a few
  /// points of it) is at most `tolerance` times the model's bounding-box diagonal.
  double tolerance = 0.0;
  /// The resolution `tolerance` may ask for at most (resolution^2 triangles per face); beyond
  /// it the result says toleranceMet false.
  int maxToleranceResolution = 256;
  /// Drop the faces over the patches that closed a scan's holes (spline/model/filled_faces.h).
  bool trimFills = true;
  /// Also gather the control net (ExportResult::controlNet).
  bool controlNet = false;
};

/// The control net as points and lines, with the figures the kind reports.
struct ExportControlNet {
  /// The net's points (control points; for a T-spline only those of anchored T-mesh vertices).
  std::vector<std::array<double, 3>> points;
  /// Lines as pairs of indices into `points`.
  std::vector<std::array<std::int64_t, 2>> lines;
  /// Triangular B-splines: the domain faces; -1 for the other kinds.
  int domainFaces = -1;
  /// T-splines: the T-mesh vertices left out (no blending function) and the T-mesh edges left
  /// out with them; -1 for the other kinds.
  std::int64_t missingAnchors = -1;
  int edgesSkipped = -1;
};

struct ExportResult {
  /// "tribspline", "tspline" or "subd".
  std::string kindName;
  SplineKind kind = SplineKind::TriangularBSpline;
  /// The resolution used (given, or chosen from the tolerance).
  int resolution = 0;
  /// The surface: trimmed triangles with per-vertex normals and chart coordinates (its uvs), and
  /// the kind's figures (ModelTessellation::report). After trimming, coneVertices, meanVertices
  /// and the sample lists still index the untrimmed tessellation.
  ModelTessellation surface;
  /// Faces trimmed away (over filled holes, and bow-ties that trimming would leave).
  std::size_t trimmedFaces = 0;
  /// With a tolerance: the model's bounding-box diagonal (of its surface vertices, else of its
  /// control points), the chord error estimate at `resolution` relative to it, and whether it is
  /// within the tolerance (false when the resolution cap stopped the search).
  double diagonal = 0.0;
  double chordErrorEstimate = 0.0;
  bool toleranceMet = true;
  /// With ExportOptions::controlNet: the net.
  ExportControlNet controlNet;
};

/// Exports `model` (`name` names it in messages). Throws InputError (naming the model) when its
/// structure is invalid for its kind or the options are out of range.
ExportResult exportSurface(const SplineModel& model, const std::string& name,
                           const ExportOptions& options = {});

}  // namespace mspline::spline
