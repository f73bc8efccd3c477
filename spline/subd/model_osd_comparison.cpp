#include "mspline/spline/subd/model_osd_comparison.h"

#include "mspline/structure/core/errors.h"

namespace mspline::spline {

ModelOsdComparison compareWithOpenSubdiv(const SplineModel& model, const std::string& name,
                                         const OsdCompareOptions& options) {
  if (model.kind != SplineKind::TSpline)
    throw structure::InputError(
        name + ": compare-osd needs a T-spline model (this is a " +
        (model.kind == SplineKind::Subdivision ? "subdivision" : "triangular B-spline") +
        " model; build one with `mspline spline --kind tspline`)");
  const TSplineSpace space(model.tmesh);
  ModelOsdComparison result;
  result.tmeshFaces = model.tmesh.numFaces();
  result.controlPoints = space.numBasis();
  result.tJunctions = model.tmesh.numTJunctions();
  result.extraordinaryPoints = model.tmesh.numExtraordinary();
  try {
    result.comparison = compareWithOpenSubdiv(space, model.controlPoints, model.weights, options);
  } catch (const structure::InputError& e) {
    throw structure::InputError(name + ": " + e.what());
  }
  return result;
}

}  // namespace mspline::spline
