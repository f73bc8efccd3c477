#include "mspline/structure/flatten/surface_voronoi.h"

#include <algorithm>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/topology/topology.h"

namespace mspline::structure {

SurfaceVoronoi surfaceVoronoi(const TriMesh& mesh, const SurfaceVoronoiOptions& options,
                              const Progress& progress) {
  const std::string named = options.name.empty() ? "" : options.name + ": ";
  const TopologyReport topology = analyzeTopology(mesh);
  if (topology.components != 1 || !topology.closed || topology.genus != 1)
    throw TopologyError(named + "voronoi needs a closed genus-1 surface; this one has " +
                        std::to_string(topology.components) + " components, genus " +
                        std::to_string(topology.genus) + " and " +
                        std::to_string(topology.boundaryLoops) + " boundary loops");
  if (options.sites.empty() && options.randomSites <= 0)
    throw InputError(named + "voronoi needs at least one site");

  SurfaceVoronoi out;
  out.flattenOptions.cones.emplace();
  out.flattenOptions.name = options.name;
  report(progress, std::to_string(mesh.n_faces()) + " faces loaded; flattening without cones");
  out.flattening = flattenSurface(mesh, out.flattenOptions, progress);
  if (!out.flattening.converged) return out;
  const TriMesh& surface = out.flattening.surface();
  if (options.sites.empty())
    out.sites = randomSurfacePoints(surface, options.randomSites, options.seed);
  else if (out.flattening.overlay)
    out.sites = pointsOnOverlay(mesh, *out.flattening.overlay, options.sites);
  else
    out.sites = options.sites;

  out.voronoi = flatTorusVoronoi(surface, out.flattening.layout, out.sites);
  std::vector<int> facesPerCell(out.sites.size(), 0);
  for (int label : out.voronoi.faceLabel) ++facesPerCell[label];
  const auto [fewest, most] = std::minmax_element(facesPerCell.begin(), facesPerCell.end());
  out.fewestFacesPerCell = *fewest;
  out.mostFacesPerCell = *most;
  return out;
}

}  // namespace mspline::structure
