#include "mspline/spline/model/scan_errors.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "mspline/spline/model/filled_faces.h"
#include "mspline/spline/model/model_surface.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/bounding_box.h"
#include "mspline/structure/mesh/closest_point.h"

namespace mspline::spline {

namespace {

struct Spread {
  double rms = 0.0, p99 = 0.0, max = 0.0;
};

// RMS, 99th percentile (the smallest distance that at least 99% of them do not exceed) and max.
Spread spread(std::vector<double> distances) {
  Spread result;
  if (distances.empty()) return result;
  double squares = 0.0;
  for (const double d : distances) squares += d * d;
  result.rms = std::sqrt(squares / double(distances.size()));
  const std::size_t rank = std::size_t(std::ceil(0.99 * double(distances.size()))) - 1;
  std::nth_element(distances.begin(), distances.begin() + std::ptrdiff_t(rank), distances.end());
  result.p99 = distances[rank];
  result.max = *std::max_element(distances.begin() + std::ptrdiff_t(rank), distances.end());
  return result;
}

}  // namespace

SurfaceErrors measureAgainstScan(const SplineModel& model, const structure::TriMesh& scan,
                                 const ScanErrorOptions& options) {
  const Eigen::Index scanVertices = Eigen::Index(scan.n_vertices());
  Eigen::MatrixX3d scanPoints(scanVertices, 3);
  for (const auto v : scan.vertices())
    scanPoints.row(v.idx()) << scan.point(v)[0], scan.point(v)[1], scan.point(v)[2];
  SurfaceErrors errors;
  errors.diagonal = structure::boundingBoxDiagonal(scanPoints);
  if (model.surfaceVertices.rows() < scanVertices ||
      !model.surfaceVertices.topRows(scanVertices).isApprox(scanPoints, 1e-12))
    throw structure::InputError(options.name +
                                ": the model's surface does not start with the scan's " +
                                std::to_string(scanVertices) + " vertices (not fitted to it)");
  const ModelSurface surface(model, options.name);

  // Scan to surface: the fit left each surface vertex's parameters at its closest point.
  bool anyFilled = false;
  for (const char filled : model.surfaceFaceFilled) anyFilled = anyFilled || filled;
  const Eigen::Index measuredRows = anyFilled ? scanVertices : model.surfaceVertices.rows();
  const Eigen::MatrixX3d spline = surfaceVertexSpline(model);
  std::vector<double> distances;
  for (Eigen::Index k = 0; k < measuredRows; ++k) {
    const double d = (spline.row(k) - model.surfaceVertices.row(k)).norm();
    if (std::isfinite(d)) distances.push_back(d);
  }
  errors.measured = int(distances.size());
  const Spread scanToSurface = spread(std::move(distances));

  // Surface to scan: the tessellation's vertices over the scan (fills trimmed away).
  const int resolution = options.resolution > 0                        ? options.resolution
                         : model.kind == SplineKind::TriangularBSpline ? 8
                                                                       : 4;
  structure::PolygonSoup tessellation = surface.tessellate(model.controlPoints, resolution).mesh;
  keepFaces(tessellation, facesOverScan(tessellation, model));
  std::vector<std::array<int, 3>> scanFaces;
  for (const auto f : scan.faces()) {
    std::array<int, 3> corners{};
    int k = 0;
    for (const auto v : scan.fv_range(f)) corners[std::size_t(k++)] = v.idx();
    scanFaces.push_back(corners);
  }
  const structure::TriangleMeshDistance scanDistance(scanPoints, scanFaces);
  std::vector<Eigen::Vector3d> points;
  for (const auto& p : tessellation.positions) points.emplace_back(p[0], p[1], p[2]);
  distances.clear();
  for (const auto& hit : scanDistance.queryAll(points)) distances.push_back(hit.distance);
  errors.surfaceSamples = int(points.size());
  const Spread surfaceToScan = spread(std::move(distances));

  const double unit = errors.diagonal > 0.0 ? errors.diagonal : 1.0;
  errors.rms = scanToSurface.rms / unit;
  errors.p99 = scanToSurface.p99 / unit;
  errors.max = scanToSurface.max / unit;
  errors.rmsSurfaceToScan = surfaceToScan.rms / unit;
  errors.p99SurfaceToScan = surfaceToScan.p99 / unit;
  errors.maxSurfaceToScan = surfaceToScan.max / unit;
  return errors;
}

}  // namespace mspline::spline
