#pragma once
// `mspline compare-osd` as a library call: a T-spline model against OpenSubdiv's Catmull-Clark
// limit of its control net (tspline_osd.h), with the T-mesh's figures.
#include <string>

#include "mspline/spline/core/spline_model.h"
#include "mspline/spline/subd/tspline_osd.h"

namespace mspline::spline {

struct ModelOsdComparison {
  /// The T-mesh: faces, blending functions (control points), T-junctions and extraordinary
  /// vertices (valence other than 4).
  int tmeshFaces = 0;
  int controlPoints = 0;
  int tJunctions = 0;
  int extraordinaryPoints = 0;
  /// The comparison itself (deviations relative to the control points' bounding-box diagonal).
  OsdComparison comparison;
};

/// Compares the T-spline `model` (`name` names it in messages) with OpenSubdiv's limit of its
/// net. Throws InputError (naming the model) for a model of another kind or a T-mesh with
/// T-junctions (no Catmull-Clark net), and as compareWithOpenSubdiv does.
ModelOsdComparison compareWithOpenSubdiv(const SplineModel& model, const std::string& name,
                                         const OsdCompareOptions& options = {});

}  // namespace mspline::spline
