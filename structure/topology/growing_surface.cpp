#include "mspline/structure/topology/growing_surface.h"

#include <string>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/subdivide.h"

namespace mspline::structure {

namespace {

using VH = TriMesh::VertexHandle;

/// The same path on subdivideMidpoint(coarse): the midpoint of each edge is inserted.
std::vector<int> refinePath(const TriMesh& coarse, const std::vector<int>& path) {
  std::vector<int> fine;
  const int nv = static_cast<int>(coarse.n_vertices());
  for (std::size_t k = 0; k + 1 < path.size(); ++k) {
    fine.push_back(path[k]);
    fine.push_back(nv + edgeBetween(coarse, path[k], path[k + 1]));
  }
  if (!path.empty()) fine.push_back(path.back());
  return fine;
}

}  // namespace

VertexPair edgeKey(int a, int b) {
  return a < b ? VertexPair{a, b} : VertexPair{b, a};
}

int edgeBetween(const TriMesh& mesh, int a, int b) {
  const auto h = mesh.find_halfedge(VH(a), VH(b));
  MSPLINE_ASSERT(h.is_valid(), "vertices " + std::to_string(a) + " and " + std::to_string(b) +
                                   " are not adjacent");
  return mesh.edge_handle(h).idx();
}

std::vector<int> edgesOfPaths(const TriMesh& mesh, const std::vector<std::vector<int>>& paths) {
  std::vector<int> edges;
  for (const auto& path : paths)
    for (std::size_t k = 0; k + 1 < path.size(); ++k)
      edges.push_back(edgeBetween(mesh, path[k], path[k + 1]));
  return edges;
}

int splitEdge(GrowingSurface& work, int a, int b) {
  TriMesh& mesh = *work.surface;
  const auto point = 0.5 * (mesh.point(VH(a)) + mesh.point(VH(b)));
  const auto midpoint = mesh.add_vertex(point);
  mesh.split(TriMesh::EdgeHandle(edgeBetween(mesh, a, b)), midpoint);
  ++work.edgeSplits;
  return midpoint.idx();
}

void checkGrowth(const GrowingSurface& work) {
  if (work.surface->n_vertices() <= work.maxVertices) return;
  throw SolverError("the loops need more than " + std::to_string(work.maxVertices) +
                    " vertices on this mesh (genus too high for its resolution; the budget is "
                    "CutOptions::maxGrowth)");
}

void refineSurface(GrowingSurface& work, std::vector<std::vector<int>>& paths) {
  if (work.refinements >= work.maxRefinements)
    throw SolverError("the mesh is too coarse to cut into a disk as asked even after " +
                      std::to_string(work.refinements) +
                      " midpoint refinements; raise CutOptions::maxRefinements (or, for the "
                      "one-vertex schema, turn oneVertexSchema off)");
  for (auto& path : paths) path = refinePath(*work.surface, path);
  work.surface = std::make_unique<TriMesh>(subdivideMidpoint(*work.surface));
  ++work.refinements;
}

}  // namespace mspline::structure
