#include "mspline/structure/topology/one_vertex_loops.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <queue>
#include <set>
#include <utility>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/topology/open_surface.h"

namespace mspline::structure {

namespace {

using VH = TriMesh::VertexHandle;

/// Shortest path from `target` through unblocked vertices to a neighbour of `center`, returned as
/// center..target (empty when there is none). Passing next to a blocked vertex costs four times
/// the length, next to a sink still to be routed fifty times: a path that touches the cut graph
/// or a sink walls off the pocket beside it, which later paths could not enter.
std::vector<int> routeToCenter(const TriMesh& mesh, int center, int target,
                               const std::vector<char>& blocked, const std::vector<int>& pending) {
  const std::size_t nv = mesh.n_vertices();
  std::vector<double> factor(nv, 1.0);
  for (auto v : mesh.vertices())
    if (blocked[v.idx()])
      for (auto w : mesh.vv_range(v)) factor[w.idx()] = 4.0;
  for (int s : pending)
    for (auto w : mesh.vv_range(VH(s))) factor[w.idx()] = 50.0;
  std::vector<char> nearCenter(nv, 0);
  for (auto w : mesh.vv_range(VH(center))) nearCenter[w.idx()] = 1;

  std::vector<double> dist(nv, std::numeric_limits<double>::infinity());
  std::vector<int> previous(nv, -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  dist[target] = 0;
  queue.push({0.0, target});
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v]) continue;
    if (nearCenter[v]) {
      std::vector<int> path{center};
      for (int w = v; w != -1; w = previous[w]) path.push_back(w);
      return path;
    }
    for (auto h : mesh.voh_range(VH(v))) {
      const int w = mesh.to_vertex_handle(h).idx();
      if (blocked[w] || w == center) continue;
      const double nd = d + mesh.calc_edge_length(h) * factor[w];
      if (nd < dist[w]) {
        dist[w] = nd;
        previous[w] = v;
        queue.push({nd, w});
      }
    }
  }
  return {};
}

/// Hop distance of every vertex from the marked ones.
std::vector<int> hopDistance(const TriMesh& mesh, const std::vector<char>& marked) {
  std::vector<int> dist(mesh.n_vertices(), std::numeric_limits<int>::max());
  std::deque<int> queue;
  for (auto v : mesh.vertices())
    if (marked[v.idx()]) {
      dist[v.idx()] = 0;
      queue.push_back(v.idx());
    }
  while (!queue.empty()) {
    const int v = queue.front();
    queue.pop_front();
    for (auto w : mesh.vv_range(VH(v)))
      if (dist[w.idx()] == std::numeric_limits<int>::max()) {
        dist[w.idx()] = dist[v] + 1;
        queue.push_back(w.idx());
      }
  }
  return dist;
}

/// Where the loops cross the cut graph: crossing edge i is on basis loop i.
struct Crossings {
  std::vector<VertexPair> edges;
  /// The two vertices opposite crossing edge i are sinks 2i and 2i + 1: where delta_i reaches the
  /// cut from either side.
  std::vector<int> sinks;
};

/// Edge positions 0..count-1 of a loop, those nearest its middle first.
std::vector<std::size_t> middleFirst(std::size_t count) {
  std::vector<std::size_t> order(count);
  for (std::size_t k = 0; k < count; ++k) order[k] = k;
  const double middle = 0.5 * static_cast<double>(count);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::abs(double(a) + 0.5 - middle) < std::abs(double(b) + 0.5 - middle);
  });
  return order;
}

/// One crossing edge per loop, used once by all loops together, whose two opposite vertices (the
/// sinks) are off the cut graph and not shared; prefer edges in the middle of the loop, away from
/// the branch vertices near the base. A loop without such an edge gets none.
Crossings chooseCrossings(const TriMesh& mesh, const std::vector<std::vector<int>>& basisLoops) {
  std::map<VertexPair, int> uses;
  std::vector<char> onCut(mesh.n_vertices(), 0);
  for (const auto& loop : basisLoops)
    for (std::size_t k = 0; k + 1 < loop.size(); ++k) {
      ++uses[edgeKey(loop[k], loop[k + 1])];
      onCut[loop[k]] = 1;
    }
  Crossings crossings;
  std::vector<char> taken(mesh.n_vertices(), 0);
  for (const auto& loop : basisLoops)
    for (std::size_t k : middleFirst(loop.size() - 1)) {
      const int a = loop[k], b = loop[k + 1];
      if (uses[edgeKey(a, b)] != 1) continue;
      const auto h = mesh.find_halfedge(VH(a), VH(b));
      const auto o = mesh.opposite_halfedge_handle(h);
      const int p = mesh.to_vertex_handle(mesh.next_halfedge_handle(h)).idx();
      const int q = mesh.to_vertex_handle(mesh.next_halfedge_handle(o)).idx();
      if (onCut[p] || onCut[q] || taken[p] || taken[q] || p == q) continue;
      taken[p] = taken[q] = 1;
      crossings.sinks.push_back(p);
      crossings.sinks.push_back(q);
      crossings.edges.push_back({a, b});
      break;
    }
  return crossings;
}

/// The cut graph, split at the crossings, and what the 4g paths are routed between.
struct Routing {
  /// The basis loops (the cut graph), carried through splits and refinements as paths.
  std::vector<std::vector<int>> basisLoops;
  /// See Crossings::sinks.
  std::vector<int> sinks;
  /// m_i: the vertex splitting crossing edge i, where delta_i crosses the cut graph.
  std::vector<int> midpoints;
  /// Sink indices in the order their paths are routed.
  std::vector<std::size_t> order;
  /// The common vertex of the loops.
  int center = -1;
};

/// Splits the crossing edges so that delta_i crosses the cut graph at a vertex m_i, inserted into
/// basis loop i; returns the m_i.
std::vector<int> splitCrossings(GrowingSurface& work, const std::vector<VertexPair>& crossings,
                                std::vector<std::vector<int>>& basisLoops) {
  std::vector<int> midpoints;
  for (std::size_t i = 0; i < crossings.size(); ++i) {
    const auto [a, b] = crossings[i];
    const int m = splitEdge(work, a, b);
    midpoints.push_back(m);
    auto& loop = basisLoops[i];
    for (std::size_t k = 0; k + 1 < loop.size(); ++k)
      if (edgeKey(loop[k], loop[k + 1]) == edgeKey(a, b)) {
        loop.insert(loop.begin() + static_cast<long>(k) + 1, m);
        break;
      }
  }
  return midpoints;
}

/// Route in the order the sinks appear around the disk the cut graph leaves: each new path then
/// runs beside the previous one instead of threading between two earlier paths, which would
/// make it (and the splits opening its contacts) as long as both together.
std::vector<std::size_t> routingOrder(const TriMesh& mesh, const Routing& routing) {
  const OpenedSurface opened = openSurface(mesh, edgesOfPaths(mesh, routing.basisLoops));
  std::map<int, std::size_t> sinkIndex;
  for (std::size_t k = 0; k < routing.sinks.size(); ++k) sinkIndex[routing.sinks[k]] = k;
  std::vector<char> placed(routing.sinks.size(), 0);
  std::vector<std::size_t> order;
  const TriMesh& disk = opened.cut.mesh;
  for (int corner : opened.boundaryLoop) {
    const int m = opened.cut.sourceVertex[corner];
    for (auto w : disk.vv_range(VH(corner))) {
      const auto found = sinkIndex.find(opened.cut.sourceVertex[w.idx()]);
      if (found == sinkIndex.end() || placed[found->second] ||
          routing.midpoints[found->second / 2] != m)
        continue;
      placed[found->second] = 1;
      order.push_back(found->second);
    }
  }
  MSPLINE_ASSERT(order.size() == routing.sinks.size(), "a sink is not beside its crossing");
  return order;
}

/// The common vertex: as far from the cut graph as possible.
int chooseCenter(const TriMesh& mesh, const Routing& routing) {
  std::vector<char> onCut(mesh.n_vertices(), 0);
  for (const auto& loop : routing.basisLoops)
    for (int v : loop) onCut[v] = 1;
  const std::vector<int> dist = hopDistance(mesh, onCut);
  std::vector<char> isSink(mesh.n_vertices(), 0);
  for (int s : routing.sinks) isSink[s] = 1;
  int center = -1;
  for (auto v : mesh.vertices())
    if (!onCut[v.idx()] && !isSink[v.idx()] && (center == -1 || dist[v.idx()] > dist[center]))
      center = v.idx();
  MSPLINE_ASSERT(center != -1, "no vertex off the cut graph");
  return center;
}

/// What the next path may not pass: the cut graph, the sinks and the paths routed so far (not the
/// center), and the edges they run along, where walls may meet.
struct Walls {
  std::vector<char> vertices;
  std::set<VertexPair> edges;
};

Walls collectWalls(const TriMesh& mesh, const Routing& routing,
                   const std::vector<std::vector<int>>& paths) {
  Walls walls{std::vector<char>(mesh.n_vertices(), 0), {}};
  auto addWall = [&](const std::vector<int>& path) {
    for (std::size_t k = 0; k < path.size(); ++k) {
      walls.vertices[path[k]] = 1;
      if (k + 1 < path.size()) walls.edges.insert(edgeKey(path[k], path[k + 1]));
    }
  };
  for (const auto& loop : routing.basisLoops) addWall(loop);
  for (const auto& path : paths) addWall(path);
  for (std::size_t k = 0; k < routing.sinks.size(); ++k) {
    walls.vertices[routing.sinks[k]] = 1;
    walls.edges.insert(edgeKey(routing.sinks[k], routing.midpoints[k / 2]));
  }
  walls.vertices[routing.center] = 0;
  return walls;
}

/// Splits the contacts at the vertices `around`: edges joining two walls that no wall runs along.
void splitContacts(GrowingSurface& work, const Walls& walls, const std::vector<int>& around) {
  const TriMesh& mesh = *work.surface;
  std::vector<VertexPair> contacts;
  for (int v : around)
    for (auto w : mesh.vv_range(VH(v)))
      if (walls.vertices[w.idx()] && !walls.edges.count(edgeKey(v, w.idx())))
        contacts.push_back(edgeKey(v, w.idx()));
  std::sort(contacts.begin(), contacts.end());
  contacts.erase(std::unique(contacts.begin(), contacts.end()), contacts.end());
  for (const auto& [x, y] : contacts) splitEdge(work, x, y);
}

std::vector<int> wallVertices(const Walls& walls) {
  std::vector<int> vertices;
  for (std::size_t v = 0; v < walls.vertices.size(); ++v)
    if (walls.vertices[v]) vertices.push_back(static_cast<int>(v));
  return vertices;
}

/// Refines the surface, carrying the cut graph and the paths routed so far. A sink stops being
/// adjacent to its m_i, so the midpoint between them takes over (appended to the path already
/// routed to it).
void refineRouting(GrowingSurface& work, Routing& routing, std::vector<std::vector<int>>& paths) {
  std::vector<int> nextSinks;
  const int nv = static_cast<int>(work.surface->n_vertices());
  for (std::size_t k = 0; k < routing.sinks.size(); ++k)
    nextSinks.push_back(nv +
                        edgeBetween(*work.surface, routing.sinks[k], routing.midpoints[k / 2]));
  const long loopCount = static_cast<long>(routing.basisLoops.size());
  std::vector<std::vector<int>> carried = routing.basisLoops;
  carried.insert(carried.end(), paths.begin(), paths.end());
  refineSurface(work, carried);
  routing.basisLoops.assign(carried.begin(), carried.begin() + loopCount);
  paths.assign(carried.begin() + loopCount, carried.end());
  for (std::size_t k = 0; k < paths.size(); ++k) paths[k].push_back(nextSinks[routing.order[k]]);
  routing.sinks = nextSinks;
}

/// Routes the 4g paths one by one, sink by sink, each from the center to its sink. The walls are
/// the cut graph, the sinks and the paths routed so far. Each region they leave is a disk with a
/// copy of the center on its boundary, so a path exists, provided walls meet only where they are
/// meant to (along their own edges, at the center and at the crossings): an edge joining two walls
/// closes a pocket that the vertex graph cannot enter, so such contacts are split open (new points
/// on old edges: the geometry does not change). Refinement remains as a fallback should a route
/// still fail.
std::vector<std::vector<int>> routePaths(GrowingSurface& work, Routing& routing) {
  std::vector<std::vector<int>> paths;
  bool everywhere = true;
  for (;;) {
    Walls walls = collectWalls(*work.surface, routing, paths);
    // Split contacts at the newest path's vertices (everywhere at the start and after a
    // refinement).
    splitContacts(work, walls,
                  everywhere ? wallVertices(walls)
                             : std::vector<int>(paths.back().begin() + 1, paths.back().end()));
    everywhere = false;
    if (paths.size() == routing.sinks.size()) return paths;
    checkGrowth(work);

    walls.vertices.resize(work.surface->n_vertices(), 0);
    const int target = routing.sinks[routing.order[paths.size()]];
    walls.vertices[target] = 0;
    std::vector<int> pending;
    for (std::size_t k = paths.size() + 1; k < routing.order.size(); ++k)
      pending.push_back(routing.sinks[routing.order[k]]);
    std::vector<int> path =
        routeToCenter(*work.surface, routing.center, target, walls.vertices, pending);
    if (!path.empty()) {
      paths.push_back(std::move(path));
      continue;
    }
    refineRouting(work, routing, paths);
    everywhere = true;
  }
}

/// delta_i: the path to sink 2i, on through m_i, and back along the path to sink 2i + 1.
LoopSystem joinPaths(const Routing& routing, const std::vector<std::vector<int>>& paths) {
  std::vector<std::size_t> pathOfSink(routing.sinks.size());
  for (std::size_t k = 0; k < routing.order.size(); ++k) pathOfSink[routing.order[k]] = k;
  LoopSystem system;
  system.center = routing.center;
  for (std::size_t i = 0; i < routing.midpoints.size(); ++i) {
    std::vector<int> loop = paths[pathOfSink[2 * i]];
    const auto& back = paths[pathOfSink[2 * i + 1]];
    loop.push_back(routing.midpoints[i]);
    loop.insert(loop.end(), back.rbegin(), back.rend());
    system.loops.push_back(std::move(loop));
  }
  return system;
}

}  // namespace

LoopSystem buildOneVertexLoops(GrowingSurface& work, const HomotopyBasis& basis) {
  Routing routing;
  routing.basisLoops = basis.loops;
  Crossings crossings;
  for (;;) {
    crossings = chooseCrossings(*work.surface, routing.basisLoops);
    if (crossings.edges.size() == basis.loops.size()) break;
    refineSurface(work, routing.basisLoops);
  }
  routing.sinks = crossings.sinks;
  routing.midpoints = splitCrossings(work, crossings.edges, routing.basisLoops);
  routing.order = routingOrder(*work.surface, routing);
  routing.center = chooseCenter(*work.surface, routing);
  return joinPaths(routing, routePaths(work, routing));
}

}  // namespace mspline::structure
