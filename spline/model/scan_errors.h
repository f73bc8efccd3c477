#pragma once
// How far a fitted spline surface is from the scan it was fitted to, both ways: the scan's vertices
// to the surface (at their fitted parameters, the closest points the fit found) and points all
// over the surface (its tessellation, as export writes it, without the fills) to the scan.
#include "mspline/spline/core/spline_model.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::spline {

struct ScanErrorOptions {
  /// Samples along every side of every face of the tessellation measured against the scan
  /// (0: 8 for triangular B-splines, 4 for the other kinds).
  int resolution = 0;
  /// Names the model in messages.
  std::string name = "model";
};

/// Distances relative to the scan's bounding-box diagonal.
struct SurfaceErrors {
  /// The scan's bounding-box diagonal (the unit of the errors below).
  double diagonal = 0.0;
  /// Scan to surface: RMS, 99th percentile and maximum over the measured vertices.
  double rms = 0.0, p99 = 0.0, max = 0.0;
  /// The model's surface vertices that lie on the scan and where the spline is defined.
  int measured = 0;
  /// Surface to scan: RMS, 99th percentile and maximum over the tessellation's vertices that lie
  /// over the scan (facesOverScan).
  double rmsSurfaceToScan = 0.0, p99SurfaceToScan = 0.0, maxSurfaceToScan = 0.0;
  int surfaceSamples = 0;
};

/// Measures `model` (control points set) against `scan`, the mesh it was fitted to: the model's
/// surface vertex k is scan vertex k for k below the scan's vertex count (a model without filled
/// faces measures every surface vertex: the others are points of the scan's faces where the
/// flattening's intrinsic triangulation crossed them). Throws InputError (naming the model) when
/// the model's surface does not start with the scan's vertices or the model is invalid.
SurfaceErrors measureAgainstScan(const SplineModel& model, const structure::TriMesh& scan,
                                 const ScanErrorOptions& options = {});

}  // namespace mspline::spline
