#include "structure/cut_to_disk.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <queue>
#include <set>
#include <utility>

#include "structure/cut_along_edges.h"
#include "structure/cut_graph.h"
#include "structure/errors.h"
#include "structure/homotopy_basis.h"
#include "structure/subdivide.h"
#include "structure/topology.h"

namespace mspline::structure {

namespace {

using VH = TriMesh::VertexHandle;
using VertexPair = std::pair<int, int>;

VertexPair key(int a, int b) {
  return a < b ? VertexPair{a, b} : VertexPair{b, a};
}

int edgeBetween(const TriMesh& mesh, int a, int b) {
  const auto h = mesh.find_halfedge(VH(a), VH(b));
  MSPLINE_ASSERT(h.is_valid(), "vertices " + std::to_string(a) + " and " + std::to_string(b) +
                                   " are not adjacent");
  return mesh.edge_handle(h).idx();
}

/// Splits edge (a, b) at its midpoint (both incident triangles split in two); returns the new
/// vertex.
int splitEdge(TriMesh& mesh, int a, int b) {
  const auto point = 0.5 * (mesh.point(VH(a)) + mesh.point(VH(b)));
  const auto midpoint = mesh.add_vertex(point);
  mesh.split(TriMesh::EdgeHandle(edgeBetween(mesh, a, b)), midpoint);
  return midpoint.idx();
}

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

/// The surface cut along a set of edges, with its boundary read off.
struct OpenedSurface {
  CutMesh cut;
  std::vector<int> cutEdges;
  /// Disk boundary (disk vertices), rotated to start at a segment start.
  std::vector<int> boundaryLoop;
  /// Segment start positions in boundaryLoop, increasing; segment k ends where k+1 starts.
  std::vector<std::size_t> segmentBegins;
};

std::vector<int> segmentVertices(const OpenedSurface& opened, std::size_t k) {
  const std::size_t n = opened.boundaryLoop.size();
  const std::size_t begin = opened.segmentBegins[k];
  std::size_t end = k + 1 < opened.segmentBegins.size() ? opened.segmentBegins[k + 1] : n;
  if (opened.segmentBegins.size() == 1) end = begin + n;
  std::vector<int> vertices;
  for (std::size_t p = begin; p <= end; ++p)
    vertices.push_back(opened.cut.sourceVertex[opened.boundaryLoop[p % n]]);
  return vertices;
}

/// Cuts `surface` along `cutEdges` and splits the (first) boundary loop of the result at copies of
/// branch vertices: those where the number of cut and boundary edges is not 2.
OpenedSurface openSurface(const TriMesh& surface, std::vector<int> cutEdges) {
  std::sort(cutEdges.begin(), cutEdges.end());
  cutEdges.erase(std::unique(cutEdges.begin(), cutEdges.end()), cutEdges.end());
  OpenedSurface opened{cutAlongEdges(surface, cutEdges), cutEdges, {}, {}};

  std::vector<int> degree(surface.n_vertices(), 0);
  std::vector<char> isCut(surface.n_edges(), 0);
  for (int e : cutEdges) isCut[e] = 1;
  for (auto e : surface.edges())
    if (isCut[e.idx()] || surface.is_boundary(e)) {
      ++degree[surface.from_vertex_handle(surface.halfedge_handle(e, 0)).idx()];
      ++degree[surface.to_vertex_handle(surface.halfedge_handle(e, 0)).idx()];
    }

  const TriMesh& disk = opened.cut.mesh;
  TriMesh::HalfedgeHandle start;
  for (auto h : disk.halfedges())
    if (disk.is_boundary(h)) {
      start = h;
      break;
    }
  if (!start.is_valid()) return opened;
  for (auto h = start;;) {
    opened.boundaryLoop.push_back(disk.from_vertex_handle(h).idx());
    h = disk.next_halfedge_handle(h);
    if (h == start) break;
  }
  auto isBranch = [&](int diskVertex) { return degree[opened.cut.sourceVertex[diskVertex]] != 2; };
  const auto firstBranch =
      std::find_if(opened.boundaryLoop.begin(), opened.boundaryLoop.end(), isBranch);
  if (firstBranch != opened.boundaryLoop.end())
    std::rotate(opened.boundaryLoop.begin(), firstBranch, opened.boundaryLoop.end());
  opened.segmentBegins.push_back(0);
  for (std::size_t p = 1; p < opened.boundaryLoop.size(); ++p)
    if (isBranch(opened.boundaryLoop[p])) opened.segmentBegins.push_back(p);
  return opened;
}

std::vector<int> edgesOfPaths(const TriMesh& mesh, const std::vector<std::vector<int>>& paths) {
  std::vector<int> edges;
  for (const auto& path : paths)
    for (std::size_t k = 0; k + 1 < path.size(); ++k)
      edges.push_back(edgeBetween(mesh, path[k], path[k + 1]));
  return edges;
}

/// 2g loops at one vertex `center`, pairwise disjoint elsewhere, whose complement is a disk.
struct LoopSystem {
  int center = -1;
  std::vector<std::vector<int>> loops;
};

/// Which loop each segment of a one-vertex cut copies, and in which direction.
struct LoopWord {
  std::vector<int> loop;
  std::vector<int> sign;
};

LoopWord readLoopWord(const TriMesh& surface, const LoopSystem& system,
                      const OpenedSurface& opened) {
  std::map<VertexPair, int> loopOfEdge;
  for (std::size_t i = 0; i < system.loops.size(); ++i)
    for (std::size_t k = 0; k + 1 < system.loops[i].size(); ++k)
      loopOfEdge[key(system.loops[i][k], system.loops[i][k + 1])] = static_cast<int>(i);
  LoopWord word;
  for (std::size_t s = 0; s < opened.segmentBegins.size(); ++s) {
    const std::vector<int> vertices = segmentVertices(opened, s);
    const auto found = loopOfEdge.find(key(vertices[0], vertices[1]));
    MSPLINE_ASSERT(found != loopOfEdge.end(), "a boundary segment of the cut is on no loop");
    const auto& loop = system.loops[found->second];
    int sign = 0;
    if (vertices == loop) sign = 1;
    if (std::equal(vertices.begin(), vertices.end(), loop.rbegin(), loop.rend())) sign = -1;
    MSPLINE_ASSERT(sign != 0, "a boundary segment is not a whole copy of its loop");
    word.loop.push_back(found->second);
    word.sign.push_back(sign);
  }
  return word;
}

OpenedSurface openAlongLoops(const TriMesh& surface, const LoopSystem& system) {
  OpenedSurface opened = openSurface(surface, edgesOfPaths(surface, system.loops));
  const TopologyReport disk = analyzeTopology(opened.cut.mesh);
  MSPLINE_ASSERT(disk.euler == 1 && disk.boundaryLoops == 1 && disk.components == 1,
                 "cutting along the one-vertex system did not give a disk");
  MSPLINE_ASSERT(opened.segmentBegins.size() == 2 * system.loops.size(),
                 "the one-vertex cut has the wrong number of boundary segments");
  return opened;
}

/// The surface being modified and what was done to it. The mesh lives behind a pointer so that
/// refining replaces it without assigning an OpenMesh mesh (see openSurface).
struct Work {
  std::unique_ptr<TriMesh> surface;
  int refinements = 0;
  int edgeSplits = 0;
  int maxRefinements = 0;
  std::size_t maxVertices = 0;
};

/// Throws TopologyError once the surface has grown past the budget.
void checkGrowth(const Work& work) {
  if (work.surface->n_vertices() <= work.maxVertices) return;
  throw TopologyError("the one-vertex system of loops needs more than " +
                      std::to_string(work.maxVertices) +
                      " vertices on this mesh (genus too high for its resolution); raise "
                      "CutOptions::maxGrowth or cut with oneVertexSchema off");
}

void refine(Work& work, std::vector<std::vector<int>>& paths) {
  if (work.refinements >= work.maxRefinements)
    throw TopologyError("the mesh is too coarse to cut into a disk as asked even after " +
                        std::to_string(work.refinements) +
                        " midpoint refinements; raise CutOptions::maxRefinements (or, for the "
                        "one-vertex schema, turn oneVertexSchema off)");
  for (auto& path : paths) path = refinePath(*work.surface, path);
  work.surface = std::make_unique<TriMesh>(subdivideMidpoint(*work.surface));
  ++work.refinements;
}

/// Builds 2g loops delta_i at one vertex, delta_i crossing the cut graph once, on an edge only
/// basis loop i runs along (once); so delta_i . loop_j = [i == j] and the delta_i are independent
/// in homology, disjoint except at their common vertex: cutting along them leaves one disk.
LoopSystem buildLoopSystem(Work& work, const HomotopyBasis& basis) {
  const int loopCount = static_cast<int>(basis.loops.size());
  // The basis loops (the cut graph) are carried through refinements as paths.
  std::vector<std::vector<int>> basisLoops = basis.loops;

  // One crossing edge per loop, used once by all loops together, whose two opposite vertices
  // (the sinks: where delta_i reaches the cut from either side) are off the cut graph and not
  // shared; prefer edges in the middle of the loop, away from the branch vertices near the base.
  std::vector<int> sinks;
  std::vector<VertexPair> crossings;
  for (;;) {
    const TriMesh& mesh = *work.surface;
    std::map<VertexPair, int> uses;
    std::vector<char> onCut(mesh.n_vertices(), 0);
    for (const auto& loop : basisLoops)
      for (std::size_t k = 0; k + 1 < loop.size(); ++k) {
        ++uses[key(loop[k], loop[k + 1])];
        onCut[loop[k]] = 1;
      }
    sinks.clear();
    crossings.clear();
    std::vector<char> taken(mesh.n_vertices(), 0);
    for (const auto& loop : basisLoops) {
      std::vector<std::size_t> order(loop.size() - 1);
      for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
      const double middle = 0.5 * static_cast<double>(order.size());
      std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return std::abs(double(a) + 0.5 - middle) < std::abs(double(b) + 0.5 - middle);
      });
      for (std::size_t k : order) {
        const int a = loop[k], b = loop[k + 1];
        if (uses[key(a, b)] != 1) continue;
        const auto h = mesh.find_halfedge(VH(a), VH(b));
        const auto o = mesh.opposite_halfedge_handle(h);
        const int p = mesh.to_vertex_handle(mesh.next_halfedge_handle(h)).idx();
        const int q = mesh.to_vertex_handle(mesh.next_halfedge_handle(o)).idx();
        if (onCut[p] || onCut[q] || taken[p] || taken[q] || p == q) continue;
        taken[p] = taken[q] = 1;
        sinks.push_back(p);
        sinks.push_back(q);
        crossings.push_back({a, b});
        break;
      }
    }
    if (static_cast<int>(crossings.size()) == loopCount) break;
    refine(work, basisLoops);
  }

  // Split the crossing edges so that delta_i crosses the cut graph at a vertex m_i.
  std::vector<int> midpoints;
  for (int i = 0; i < loopCount; ++i) {
    const auto [a, b] = crossings[i];
    const int m = splitEdge(*work.surface, a, b);
    ++work.edgeSplits;
    midpoints.push_back(m);
    auto& loop = basisLoops[i];
    for (std::size_t k = 0; k + 1 < loop.size(); ++k)
      if (key(loop[k], loop[k + 1]) == key(a, b)) {
        loop.insert(loop.begin() + static_cast<long>(k) + 1, m);
        break;
      }
  }

  // Route in the order the sinks appear around the disk the cut graph leaves: each new path then
  // runs beside the previous one instead of threading between two earlier paths, which would
  // make it (and the splits opening its contacts) as long as both together.
  std::vector<std::size_t> order;
  {
    const TriMesh& mesh = *work.surface;
    const OpenedSurface opened = openSurface(mesh, edgesOfPaths(mesh, basisLoops));
    std::map<int, std::size_t> sinkIndex;
    for (std::size_t k = 0; k < sinks.size(); ++k) sinkIndex[sinks[k]] = k;
    std::vector<char> placed(sinks.size(), 0);
    const TriMesh& disk = opened.cut.mesh;
    for (int corner : opened.boundaryLoop) {
      const int m = opened.cut.sourceVertex[corner];
      for (auto w : disk.vv_range(VH(corner))) {
        const auto found = sinkIndex.find(opened.cut.sourceVertex[w.idx()]);
        if (found == sinkIndex.end() || placed[found->second] || midpoints[found->second / 2] != m)
          continue;
        placed[found->second] = 1;
        order.push_back(found->second);
      }
    }
    MSPLINE_ASSERT(order.size() == sinks.size(), "a sink is not beside its crossing");
  }

  // The common vertex: as far from the cut graph as possible.
  int center = -1;
  {
    const TriMesh& mesh = *work.surface;
    std::vector<char> onCut(mesh.n_vertices(), 0);
    for (const auto& loop : basisLoops)
      for (int v : loop) onCut[v] = 1;
    const std::vector<int> dist = hopDistance(mesh, onCut);
    std::vector<char> isSink(mesh.n_vertices(), 0);
    for (int s : sinks) isSink[s] = 1;
    for (auto v : mesh.vertices())
      if (!onCut[v.idx()] && !isSink[v.idx()] && (center == -1 || dist[v.idx()] > dist[center]))
        center = v.idx();
    MSPLINE_ASSERT(center != -1, "no vertex off the cut graph");
  }

  // Route the 4g paths one by one, sink by sink. The walls are the cut graph, the sinks and the
  // paths routed so far. Each region they leave is a disk with a copy of the center on its
  // boundary, so a path exists, provided walls meet only where they are meant to (along their own
  // edges, at the center and at the crossings): an edge joining two walls closes a pocket that
  // the vertex graph cannot enter, so such contacts are split open (new points on old edges: the
  // geometry does not change). Refinement remains as a fallback should a route still fail.
  std::vector<std::vector<int>> paths;
  bool everywhere = true;
  for (;;) {
    TriMesh& mesh = *work.surface;
    std::vector<char> walled(mesh.n_vertices(), 0);
    std::set<VertexPair> wallEdges;
    auto addWall = [&](const std::vector<int>& path) {
      for (std::size_t k = 0; k < path.size(); ++k) {
        walled[path[k]] = 1;
        if (k + 1 < path.size()) wallEdges.insert(key(path[k], path[k + 1]));
      }
    };
    for (const auto& loop : basisLoops) addWall(loop);
    for (const auto& path : paths) addWall(path);
    for (std::size_t k = 0; k < sinks.size(); ++k) {
      walled[sinks[k]] = 1;
      wallEdges.insert(key(sinks[k], midpoints[k / 2]));
    }
    walled[center] = 0;
    // Split contacts at the newest path's vertices (everywhere at the start and after a
    // refinement).
    std::vector<int> around;
    if (everywhere) {
      for (auto v : mesh.vertices())
        if (walled[v.idx()]) around.push_back(v.idx());
      everywhere = false;
    } else {
      around.assign(paths.back().begin() + 1, paths.back().end());
    }
    std::vector<VertexPair> contacts;
    for (int v : around)
      for (auto w : mesh.vv_range(VH(v)))
        if (walled[w.idx()] && !wallEdges.count(key(v, w.idx())))
          contacts.push_back(key(v, w.idx()));
    std::sort(contacts.begin(), contacts.end());
    contacts.erase(std::unique(contacts.begin(), contacts.end()), contacts.end());
    for (const auto& [x, y] : contacts) {
      splitEdge(mesh, x, y);
      ++work.edgeSplits;
    }
    if (paths.size() == sinks.size()) break;
    checkGrowth(work);

    walled.resize(mesh.n_vertices(), 0);
    const int target = sinks[order[paths.size()]];
    walled[target] = 0;
    std::vector<int> pending;
    for (std::size_t k = paths.size() + 1; k < order.size(); ++k)
      pending.push_back(sinks[order[k]]);
    std::vector<int> path = routeToCenter(mesh, center, target, walled, pending);
    if (!path.empty()) {
      paths.push_back(std::move(path));
      continue;
    }
    // Refine. A sink stops being adjacent to its m_i, so the midpoint between them takes over
    // (appended to the path already routed to it).
    std::vector<int> nextSinks;
    const int nv = static_cast<int>(mesh.n_vertices());
    for (std::size_t k = 0; k < sinks.size(); ++k)
      nextSinks.push_back(nv + edgeBetween(mesh, sinks[k], midpoints[k / 2]));
    std::vector<std::vector<int>> carried = basisLoops;
    carried.insert(carried.end(), paths.begin(), paths.end());
    refine(work, carried);
    basisLoops.assign(carried.begin(), carried.begin() + loopCount);
    paths.assign(carried.begin() + loopCount, carried.end());
    for (std::size_t k = 0; k < paths.size(); ++k) paths[k].push_back(nextSinks[order[k]]);
    sinks = nextSinks;
    everywhere = true;
  }

  std::vector<std::size_t> pathOfSink(sinks.size());
  for (std::size_t k = 0; k < order.size(); ++k) pathOfSink[order[k]] = k;
  LoopSystem system;
  system.center = center;
  for (int i = 0; i < loopCount; ++i) {
    std::vector<int> loop = paths[pathOfSink[2 * i]];
    const auto& back = paths[pathOfSink[2 * i + 1]];
    loop.push_back(midpoints[i]);
    loop.insert(loop.end(), back.rbegin(), back.rend());
    system.loops.push_back(std::move(loop));
  }
  return system;
}

/// Positions where a canonical block x y x^-1 y^-1 starts (cyclically).
std::vector<std::size_t> canonicalBlocks(const LoopWord& word) {
  std::vector<std::size_t> blocks;
  const std::size_t n = word.loop.size();
  for (std::size_t r = 0; r < n; ++r) {
    const std::size_t r1 = (r + 1) % n, r2 = (r + 2) % n, r3 = (r + 3) % n;
    if (word.loop[r] != word.loop[r1] && word.loop[r2] == word.loop[r] &&
        word.loop[r3] == word.loop[r1] && word.sign[r2] == -word.sign[r] &&
        word.sign[r3] == -word.sign[r1])
      blocks.push_back(r);
  }
  return blocks;
}

/// Rotation r at which the word reads as consecutive canonical blocks, or -1.
long canonicalRotation(const LoopWord& word) {
  const std::size_t n = word.loop.size();
  if (n == 0) return -1;
  const auto blocks = canonicalBlocks(word);
  for (std::size_t r : blocks) {
    bool all = true;
    for (std::size_t k = 4; k < n && all; k += 4)
      all = std::binary_search(blocks.begin(), blocks.end(), (r + k) % n);
    if (all) return static_cast<long>(r);
  }
  return -1;
}

/// A corner of the disk, named by the segment that starts there: (loop, sign). The name survives
/// re-cutting, whereas positions on the boundary do not.
using Corner = std::pair<int, int>;

Corner cornerAt(const LoopWord& word, std::size_t k) {
  return {word.loop[k], word.sign[k]};
}

/// Replaces loop `eliminated` by a new loop from corner `from` to corner `to` through the
/// interior of the disk (a cut-and-paste of the polygon: cut along the new diagonal, glue the two
/// pieces back along the eliminated loop).
void replaceLoop(Work& work, LoopSystem& system, Corner from, Corner to, int eliminated) {
  for (;;) {
    checkGrowth(work);
    // Split the chords of the disk (edges joining two loop vertices that no loop runs along):
    // each separates the disk's inner vertices, and without them the inner vertices are
    // connected and every corner has an inner neighbour. New points lie on old edges.
    {
      TriMesh& mesh = *work.surface;
      std::vector<char> onLoop(mesh.n_vertices(), 0);
      std::set<VertexPair> loopEdges;
      for (const auto& loop : system.loops)
        for (std::size_t k = 0; k < loop.size(); ++k) {
          onLoop[loop[k]] = 1;
          if (k + 1 < loop.size()) loopEdges.insert(key(loop[k], loop[k + 1]));
        }
      std::vector<VertexPair> chords;
      for (auto e : mesh.edges()) {
        const auto h = mesh.halfedge_handle(e, 0);
        const int x = mesh.from_vertex_handle(h).idx(), y = mesh.to_vertex_handle(h).idx();
        if (onLoop[x] && onLoop[y] && !loopEdges.count(key(x, y))) chords.push_back({x, y});
      }
      for (const auto& [x, y] : chords) {
        splitEdge(mesh, x, y);
        ++work.edgeSplits;
      }
    }
    const OpenedSurface opened = openAlongLoops(*work.surface, system);
    const LoopWord word = readLoopWord(*work.surface, system, opened);
    const TriMesh& disk = opened.cut.mesh;
    int cornerVertex[2] = {-1, -1};
    for (std::size_t k = 0; k < word.loop.size(); ++k) {
      if (cornerAt(word, k) == from) cornerVertex[0] = opened.boundaryLoop[opened.segmentBegins[k]];
      if (cornerAt(word, k) == to) cornerVertex[1] = opened.boundaryLoop[opened.segmentBegins[k]];
    }
    MSPLINE_ASSERT(cornerVertex[0] != -1 && cornerVertex[1] != -1, "lost a corner of the disk");
    std::vector<int> near[2];
    for (int side = 0; side < 2; ++side)
      for (auto w : disk.vv_range(VH(cornerVertex[side])))
        if (!disk.is_boundary(w)) near[side].push_back(w.idx());

    // Shortest path through inner disk vertices between the two corner fans; vertices next to
    // the boundary cost four times their length, so the new loop keeps off the old ones where it
    // can (each contact becomes a chord to split next time).
    std::vector<double> factor(disk.n_vertices(), 1.0);
    for (int v : opened.boundaryLoop)
      for (auto w : disk.vv_range(VH(v))) factor[w.idx()] = 4.0;
    std::vector<double> dist(disk.n_vertices(), std::numeric_limits<double>::infinity());
    std::vector<int> previous(disk.n_vertices(), -1);
    std::vector<char> target(disk.n_vertices(), 0);
    for (int v : near[1]) target[v] = 1;
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    for (int v : near[0]) {
      dist[v] = (disk.point(VH(v)) - disk.point(VH(cornerVertex[0]))).norm();
      queue.push({dist[v], v});
    }
    int reached = -1;
    while (!queue.empty() && reached == -1) {
      const auto [d, v] = queue.top();
      queue.pop();
      if (d > dist[v]) continue;
      if (target[v]) {
        reached = v;
        break;
      }
      for (auto h : disk.voh_range(VH(v))) {
        const int w = disk.to_vertex_handle(h).idx();
        if (disk.is_boundary(VH(w))) continue;
        const double nd = d + disk.calc_edge_length(h) * factor[w];
        if (nd < dist[w]) {
          dist[w] = nd;
          previous[w] = v;
          queue.push({nd, w});
        }
      }
    }
    if (reached == -1) {
      // Without chords this does not happen; refining is the fallback should it still.
      refine(work, system.loops);
      continue;
    }
    std::vector<int> loop{system.center};
    std::vector<int> inner;
    for (int v = reached; v != -1; v = previous[v]) inner.push_back(opened.cut.sourceVertex[v]);
    loop.insert(loop.end(), inner.rbegin(), inner.rend());
    loop.push_back(system.center);
    system.loops[eliminated] = std::move(loop);
    return;
  }
}

LoopWord currentWord(const Work& work, const LoopSystem& system) {
  return readLoopWord(*work.surface, system, openAlongLoops(*work.surface, system));
}

/// Brings the one-vertex system to canonical form. For an interleaved pair x A y B x^-1 C y^-1 D
/// (read from the corner before x) two cut-and-paste moves give A D w^-1 z^-1 w z C B, which adds
/// the canonical block w^-1 z^-1 w z and keeps A..D (hence the blocks already made) intact.
/// Gives up, leaving a one-vertex but non-canonical system, should a round add no block.
void canonicalize(Work& work, LoopSystem& system) {
  const std::size_t n = 2 * system.loops.size();
  for (std::size_t round = 0; round <= system.loops.size(); ++round) {
    checkGrowth(work);
    LoopWord word = currentWord(work, system);
    if (canonicalRotation(word) != -1) return;
    const auto blocks = canonicalBlocks(word);
    std::vector<char> done(system.loops.size(), 0);
    for (std::size_t r : blocks) done[word.loop[r]] = done[word.loop[(r + 1) % n]] = 1;

    // An interleaved pair of loops outside the blocks: x at i1, x^-1 at i2, y once between them.
    std::size_t i1 = n, i2 = n;
    int y = -1;
    for (std::size_t a = 0; a < n && y == -1; ++a) {
      if (done[word.loop[a]]) continue;
      std::size_t b = a + 1;
      while (word.loop[b % n] != word.loop[a]) ++b;
      std::vector<int> count(system.loops.size(), 0);
      for (std::size_t k = a + 1; k < b; ++k) ++count[word.loop[k % n]];
      for (std::size_t k = a + 1; k < b && y == -1; ++k)
        if (count[word.loop[k % n]] == 1 && !done[word.loop[k % n]]) y = word.loop[k % n];
      if (y != -1) {
        i1 = a;
        i2 = b % n;
      }
    }
    if (y == -1) return;
    const int x = word.loop[i1];
    const std::size_t blocksBefore = blocks.size();

    // Move 1: diagonal z from the corner before x to the corner after x^-1, glue along y.
    replaceLoop(work, system, cornerAt(word, i1), cornerAt(word, (i2 + 1) % n), y);
    const int z = y;
    // Move 2: diagonal w from the corner before z^-1 to the corner before z, glue along x.
    word = currentWord(work, system);
    std::size_t zNegative = n, zPositive = n;
    for (std::size_t k = 0; k < n; ++k)
      if (word.loop[k] == z) (word.sign[k] < 0 ? zNegative : zPositive) = k;
    MSPLINE_ASSERT(zNegative < n && zPositive < n, "the new loop is not on the boundary twice");
    replaceLoop(work, system, cornerAt(word, zNegative), cornerAt(word, zPositive), x);

    word = currentWord(work, system);
    if (canonicalBlocks(word).size() <= blocksBefore) return;
  }
}

std::string curveName(char letter, int number) {
  return letter + std::to_string(number);
}

void fillWord(CutResult& result) {
  result.word.clear();
  for (const auto& segment : result.segments) {
    if (!result.word.empty()) result.word += ' ';
    result.word += result.curveNames[segment.curve];
    if (segment.orientation < 0) result.word += "^-1";
  }
}

void fillSegments(CutResult& result, const OpenedSurface& opened) {
  const std::size_t n = opened.boundaryLoop.size();
  for (std::size_t k = 0; k < opened.segmentBegins.size(); ++k) {
    BoundarySegment segment;
    segment.begin = opened.segmentBegins[k];
    segment.end = k + 1 < opened.segmentBegins.size() ? opened.segmentBegins[k + 1] : 0;
    if (n == 0) segment.end = 0;
    result.segments.push_back(segment);
  }
}

/// General cut: curves are the chains of the cut graph (c_k) and of the boundary (d_k).
void describeGeneralCut(CutResult& result, const OpenedSurface& opened) {
  fillSegments(result, opened);
  std::map<VertexPair, std::size_t> curveOfEdge;
  int cutChains = 0, boundaryChains = 0;
  for (std::size_t k = 0; k < result.segments.size(); ++k) {
    const std::vector<int> vertices = segmentVertices(opened, k);
    const VertexPair first = key(vertices[0], vertices[1]);
    const bool onBoundary = result.surface.is_boundary(
        TriMesh::EdgeHandle(edgeBetween(result.surface, vertices[0], vertices[1])));
    auto& segment = result.segments[k];
    segment.boundary = onBoundary;
    const auto found = curveOfEdge.find(first);
    if (found == curveOfEdge.end()) {
      segment.curve = result.curves.size();
      segment.orientation = 1;
      for (std::size_t p = 0; p + 1 < vertices.size(); ++p)
        curveOfEdge[key(vertices[p], vertices[p + 1])] = segment.curve;
      result.curves.push_back(vertices);
      result.curveNames.push_back(onBoundary ? curveName('d', ++boundaryChains)
                                             : curveName('c', ++cutChains));
    } else {
      segment.curve = found->second;
      const auto& curve = result.curves[segment.curve];
      segment.orientation =
          std::equal(vertices.begin(), vertices.end(), curve.rbegin(), curve.rend()) ? -1 : 1;
    }
  }
  fillWord(result);
}

void describeLoopCut(CutResult& result, const LoopSystem& system, const OpenedSurface& opened) {
  const LoopWord word = readLoopWord(result.surface, system, opened);
  const std::size_t n = word.loop.size();
  const long rotation = canonicalRotation(word);
  result.canonical = rotation != -1;
  // Curve order and direction: a1 b1 a2 b2 ... read from the rotation when canonical, otherwise
  // x_k in order of first appearance.
  const std::size_t shift = result.canonical ? static_cast<std::size_t>(rotation) : 0;
  std::vector<long> curveOfLoop(system.loops.size(), -1);
  std::vector<int> flip(system.loops.size(), 1);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t s = (shift + k) % n;
    const int loop = word.loop[s];
    if (curveOfLoop[loop] != -1) continue;
    curveOfLoop[loop] = static_cast<long>(result.curves.size());
    flip[loop] = word.sign[s];
    std::vector<int> curve = system.loops[loop];
    if (flip[loop] < 0) std::reverse(curve.begin(), curve.end());
    result.curves.push_back(curve);
    const int number = static_cast<int>(result.curves.size());
    result.curveNames.push_back(result.canonical
                                    ? curveName(number % 2 ? 'a' : 'b', (number + 1) / 2)
                                    : curveName('x', number));
  }
  // Rotate the boundary loop so that it starts at the first segment of the word.
  const std::size_t offset = opened.segmentBegins[shift];
  std::rotate(result.boundaryLoop.begin(), result.boundaryLoop.begin() + static_cast<long>(offset),
              result.boundaryLoop.end());
  const std::size_t length = result.boundaryLoop.size();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t s = (shift + k) % n;
    BoundarySegment segment;
    segment.begin = (opened.segmentBegins[s] + length - offset) % length;
    segment.end = (opened.segmentBegins[(s + 1) % n] + length - offset) % length;
    segment.curve = static_cast<std::size_t>(curveOfLoop[word.loop[s]]);
    segment.orientation = word.sign[s] * flip[word.loop[s]];
    result.segments.push_back(segment);
  }
  fillWord(result);
}

}  // namespace

CutResult cutToDisk(const TriMesh& mesh, const CutOptions& options) {
  HomotopyBasisOptions basisOptions;
  basisOptions.baseVertex = options.baseVertex;
  const HomotopyBasis basis = computeHomotopyBasis(mesh, basisOptions);

  const std::size_t maxVertices =
      std::max<std::size_t>(options.maxGrowth * mesh.n_vertices(), 100000);
  Work work{std::make_unique<TriMesh>(mesh), 0, 0, options.maxRefinements, maxVertices};
  const bool loopCut = options.oneVertexSchema && basis.boundaryLoops.empty() && basis.genus > 0;
  LoopSystem system;
  std::vector<int> cutEdges;
  if (loopCut) {
    system = buildLoopSystem(work, basis);
    if (options.canonicalSchema) canonicalize(work, system);
    cutEdges = edgesOfPaths(*work.surface, system.loops);
  } else {
    // Where every path to a boundary must pass another boundary vertex, the cut graph touches a
    // boundary off its anchor and the surface falls apart; refining makes room (rarely needed).
    for (;;) {
      const HomotopyBasis current =
          work.refinements == 0 ? basis : computeHomotopyBasis(*work.surface, basisOptions);
      cutEdges = computeCutGraph(*work.surface, current).edges;
      const TopologyReport opened = analyzeTopology(cutAlongEdges(*work.surface, cutEdges).mesh);
      if (opened.euler == 1 && opened.boundaryLoops == 1 && opened.components == 1) break;
      std::vector<std::vector<int>> noPaths;
      refine(work, noPaths);
    }
  }
  const OpenedSurface opened = openSurface(*work.surface, cutEdges);

  CutResult result(opened.cut.mesh, *work.surface);
  result.genus = basis.genus;
  result.refinements = work.refinements;
  result.edgeSplits = work.edgeSplits;
  result.surfaceVertex = opened.cut.sourceVertex;
  result.cutEdges = opened.cutEdges;
  result.boundaryLoop = opened.boundaryLoop;
  const int inputVertices = static_cast<int>(mesh.n_vertices());
  for (int v : result.surfaceVertex) result.inputVertex.push_back(v < inputVertices ? v : -1);
  if (loopCut) {
    result.oneVertexSchema = true;
    result.baseVertex = system.center;
    describeLoopCut(result, system, opened);
  } else {
    result.baseVertex = basis.baseVertex;
    describeGeneralCut(result, opened);
  }

  const TopologyReport disk = analyzeTopology(result.disk);
  result.diskEuler = disk.euler;
  result.diskBoundaryLoops = disk.boundaryLoops;
  result.diskComponents = disk.components;
  MSPLINE_ASSERT(disk.euler == 1 && disk.boundaryLoops == 1 && disk.components == 1,
                 "the cut surface is not a disk");
  return result;
}

}  // namespace mspline::structure
