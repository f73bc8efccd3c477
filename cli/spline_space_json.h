#pragma once
// The figures of a spline space (spline/model/build_spline.h) as `spline` and `fit` report them.
#include "cli/command.h"
#include "mspline/spline/model/build_spline.h"

namespace mspline::cli {

/// layout ("torus lattice" or "motorcycle graph"), its cells or traces, rectangles, cell size and
/// rounding, and anisotropy.
Json gridJson(const spline::GridFigures& grid);

/// domain_vertices, domain_faces, cones, unremoved_vertices, cone_separating_vertices,
/// cone_sides, tracking_error, domain_flatness {before, after}.
Json domainJson(const spline::DomainFigures& domain);

}  // namespace mspline::cli
