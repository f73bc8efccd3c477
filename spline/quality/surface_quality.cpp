#include "mspline/spline/quality/surface_quality.h"

#include <stdexcept>

namespace mspline::spline {

SurfaceQuality measureQuality(const SplineModel&, const ModelSurface&, const Eigen::MatrixXd&,
                              const structure::TriMesh*, const QualityOptions&,
                              const structure::Progress&) {
  throw std::logic_error("measureQuality: not implemented yet");
}

SurfaceQuality measureQuality(const SplineModel& model, const structure::TriMesh* scan,
                              const QualityOptions& options, const structure::Progress& progress) {
  const ModelSurface surface(model, options.name);
  return measureQuality(model, surface, model.controlPoints, scan, options, progress);
}

}  // namespace mspline::spline
