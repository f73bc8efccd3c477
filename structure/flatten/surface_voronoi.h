#pragma once
// The Voronoi diagram of sites on a closed genus-1 surface in its flat metric: the surface
// flattened without cones (a flat torus), the sites carried onto the surface laid out, and the
// cells computed on the universal cover (structure/layout/flat_torus_voronoi.h).
#include <string>
#include <vector>

#include "mspline/structure/core/progress.h"
#include "mspline/structure/core/surface_point.h"
#include "mspline/structure/flatten/flatten_surface.h"
#include "mspline/structure/layout/flat_torus_voronoi.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct SurfaceVoronoiOptions {
  /// Sites on the input mesh; when empty, `randomSites` sites spread uniformly by area over the
  /// surface laid out (randomSurfacePoints with `seed`).
  std::vector<SurfacePoint> sites;
  int randomSites = 0;
  unsigned seed = 1;
  /// Names the surface (its file) in messages.
  std::string name;
};

struct SurfaceVoronoi {
  /// The flat metric without cones, and the options it was computed with; when it did not
  /// converge (flattening.converged false, with its message) nothing below is computed.
  FlattenOptions flattenOptions;
  Flattening flattening;
  /// The sites on flattening.surface() (moved onto the overlay when there is one).
  std::vector<SurfacePoint> sites;
  /// The cells, as faces of flattening.surface(), and their boundaries.
  TorusVoronoi voronoi;
  /// The fewest and the most faces a site's cell has.
  int fewestFacesPerCell = 0;
  int mostFacesPerCell = 0;
};

/// Throws TopologyError unless `mesh` is one closed genus-1 surface, InputError for no sites
/// (neither given nor a positive random count) or invalid ones. `mesh` must outlive the result.
SurfaceVoronoi surfaceVoronoi(const TriMesh& mesh, const SurfaceVoronoiOptions& options,
                              const Progress& progress = {});

}  // namespace mspline::structure
