#include "mspline/structure/topology/homotopy_basis.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>
#include <string>
#include <utility>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/topology/topology.h"

namespace mspline::structure {

namespace {

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  bool unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    parent[a] = b;
    return true;
  }
};

}  // namespace

void requireConnectedManifold(const TriMesh& mesh) {
  if (mesh.n_faces() == 0) throw TopologyError("mesh has no faces");
  for (auto v : mesh.vertices()) {
    if (mesh.is_isolated(v))
      throw TopologyError("vertex " + std::to_string(v.idx()) + " belongs to no face");
    if (!mesh.is_manifold(v))
      throw TopologyError("vertex " + std::to_string(v.idx()) + " is not manifold");
  }
  const TopologyReport topology = analyzeTopology(mesh);
  if (topology.components != 1)
    throw TopologyError("mesh has " + std::to_string(topology.components) +
                        " connected components; cut each component separately");
}

std::vector<int> treePath(const HomotopyBasis& basis, int v) {
  std::vector<int> path;
  for (int w = v; w != -1; w = basis.parent[w]) path.push_back(w);
  std::reverse(path.begin(), path.end());
  return path;
}

HomotopyBasis computeHomotopyBasis(const TriMesh& mesh, const HomotopyBasisOptions& options) {
  requireConnectedManifold(mesh);
  HomotopyBasis basis;
  const int nv = static_cast<int>(mesh.n_vertices());

  // Boundary loops; each halfedge on one gets the loop's index (its virtual cap face).
  std::vector<int> capOfHalfedge(mesh.n_halfedges(), -1);
  for (auto h : mesh.halfedges()) {
    if (!mesh.is_boundary(h) || capOfHalfedge[h.idx()] != -1) continue;
    const int cap = static_cast<int>(basis.boundaryLoops.size());
    std::vector<int> loop;
    auto walk = h;
    do {
      capOfHalfedge[walk.idx()] = cap;
      loop.push_back(mesh.from_vertex_handle(walk).idx());
      walk = mesh.next_halfedge_handle(walk);
    } while (walk != h);
    basis.boundaryLoops.push_back(std::move(loop));
  }

  int base = options.baseVertex;
  if (base == -1) {
    base = 0;
    if (!basis.boundaryLoops.empty()) {
      base = nv;
      for (const auto& loop : basis.boundaryLoops)
        base = std::min(base, *std::min_element(loop.begin(), loop.end()));
    }
  }
  if (base < 0 || base >= nv)
    throw InputError("base vertex " + std::to_string(base) + " is out of range (mesh has " +
                     std::to_string(nv) + " vertices)");
  basis.baseVertex = base;

  // Shortest-path tree from the base. Entering a boundary vertex costs a penalty larger than any
  // path, so that tree paths and loops keep off the boundary wherever the mesh allows: a cut
  // graph touching a boundary loop anywhere but at its anchor would close a cycle with it, and
  // the surface would fall apart instead of opening into a disk.
  double penalty = 0;
  if (!basis.boundaryLoops.empty())
    for (auto e : mesh.edges()) penalty += mesh.calc_edge_length(e);
  basis.distance.assign(nv, std::numeric_limits<double>::infinity());
  basis.parent.assign(nv, -1);
  std::vector<int> parentEdge(nv, -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  basis.distance[base] = 0;
  queue.push({0.0, base});
  while (!queue.empty()) {
    auto [d, v] = queue.top();
    queue.pop();
    if (d > basis.distance[v]) continue;
    for (auto h : mesh.voh_range(TriMesh::VertexHandle(v))) {
      const int w = mesh.to_vertex_handle(h).idx();
      const double nd = d + mesh.calc_edge_length(h) +
                        (mesh.is_boundary(TriMesh::VertexHandle(w)) ? penalty : 0.0);
      if (nd < basis.distance[w]) {
        basis.distance[w] = nd;
        basis.parent[w] = v;
        parentEdge[w] = mesh.edge_handle(h).idx();
        queue.push({nd, w});
      }
    }
  }
  std::vector<char> inTree(mesh.n_edges(), 0);
  for (int v = 0; v < nv; ++v)
    if (parentEdge[v] != -1) inTree[parentEdge[v]] = 1;

  for (const auto& loop : basis.boundaryLoops) {
    int anchor = loop.front();
    for (int v : loop)
      if (basis.distance[v] < basis.distance[anchor]) anchor = v;
    basis.boundaryAnchors.push_back(anchor);
  }

  // Maximum spanning tree of the dual graph (faces plus one cap per boundary loop) over the
  // edges not in the tree; the edges it cannot take close the 2g loops.
  std::vector<std::pair<double, int>> candidates;
  auto weight = [&](TriMesh::EdgeHandle e) {
    const auto h = mesh.halfedge_handle(e, 0);
    return basis.distance[mesh.from_vertex_handle(h).idx()] + mesh.calc_edge_length(e) +
           basis.distance[mesh.to_vertex_handle(h).idx()];
  };
  for (auto e : mesh.edges())
    if (!inTree[e.idx()]) candidates.push_back({weight(e), e.idx()});
  std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  });
  const int nf = static_cast<int>(mesh.n_faces());
  UnionFind dual(nf + basis.boundaryLoops.size());
  auto dualNode = [&](TriMesh::HalfedgeHandle h) {
    return mesh.is_boundary(h) ? nf + capOfHalfedge[h.idx()] : mesh.face_handle(h).idx();
  };
  for (const auto& candidate : candidates) {
    const int e = candidate.second;
    const TriMesh::EdgeHandle eh(e);
    if (dual.unite(dualNode(mesh.halfedge_handle(eh, 0)), dualNode(mesh.halfedge_handle(eh, 1))))
      continue;
    basis.leftoverEdges.push_back(e);
    const auto h = mesh.halfedge_handle(eh, 0);
    std::vector<int> loop = treePath(basis, mesh.from_vertex_handle(h).idx());
    std::vector<int> back = treePath(basis, mesh.to_vertex_handle(h).idx());
    loop.insert(loop.end(), back.rbegin(), back.rend());
    basis.loops.push_back(std::move(loop));
    double length = 0;
    for (std::size_t k = 0; k + 1 < basis.loops.back().size(); ++k)
      length += (mesh.point(TriMesh::VertexHandle(basis.loops.back()[k])) -
                 mesh.point(TriMesh::VertexHandle(basis.loops.back()[k + 1])))
                    .norm();
    basis.lengths.push_back(length);
  }
  MSPLINE_ASSERT(basis.loops.size() % 2 == 0, "tree-cotree left an odd number of edges");
  basis.genus = static_cast<int>(basis.loops.size() / 2);
  return basis;
}

}  // namespace mspline::structure
