#pragma once
// `mspline export` as a library call: a spline model's surface (spline/model/export_surface.h)
// written as a triangle mesh, and optionally its control net, the error map of a scan against it
// and a shaded picture of it. The files are written all or none (io/atomic_file.h).
#include <cstddef>
#include <string>

#include "mspline/spline/model/export_surface.h"

namespace mspline::io {

struct ExportFileOptions {
  /// The mesh to write (.obj, .ply or .stl): a unit normal per vertex, in OBJ also the chart
  /// coordinates.
  std::string output;
  /// Resolution or tolerance, and trimming (ExportOptions::controlNet is set when `controlNet`
  /// names a file).
  spline::ExportOptions surface;
  /// Optional: the control net as OBJ points and `l` lines (.obj).
  std::string controlNet;
  /// Optional, both or neither: a scan, and the PLY to write it to with its vertices colored by
  /// their distance to the exported surface (io/error_map.h).
  std::string scan;
  std::string errorMap;
  /// Optional: a shaded picture of the surface (PNG, io/shaded_picture.h), with the triangles
  /// at a crease or fold marked in red when `markDefects` (spline::creasedFaces: a neighbour's
  /// normal differs by more than creaseDegrees, at the export resolution).
  std::string png;
  bool markDefects = false;
  double creaseDegrees = 30.0;
};

/// The scan's distances to the exported surface.
struct ScanErrors {
  std::size_t vertices = 0;
  /// Root mean square and largest distance relative to the scan's bounding-box diagonal (0 when
  /// the diagonal is), and the largest distance itself.
  double rms = 0.0;
  double max = 0.0;
  double maxAbsolute = 0.0;
  /// The distance colored red (the 99th percentile, ErrorMap::scale).
  double colorScale = 0.0;
};

struct ExportFileResult {
  /// The surface as written (trimmed, with its figures) and the control net when asked for.
  spline::ExportResult surface;
  /// With a scan: its distances to the surface.
  ScanErrors scanErrors;
  /// With a picture and markDefects: the triangles marked.
  std::size_t markedFaces = 0;
};

/// Throws InputError when a file name of `options` does not fit: an unknown mesh format, a control
/// net that is not .obj, an error map that is not .ply, a scan without an error map file or the
/// reverse. exportModel checks first; a caller that reads the model from a file can check before.
void checkExportFiles(const ExportFileOptions& options);

/// Exports `model` (`name` names it in messages) into the files of `options`: checkExportFiles
/// before the work, then throws as spline::exportSurface and the readers and writers do.
ExportFileResult exportModel(const spline::SplineModel& model, const std::string& name,
                             const ExportFileOptions& options);

}  // namespace mspline::io
