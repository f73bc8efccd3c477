#include "mspline/structure/topology/canonical_schema.h"

#include <algorithm>
#include <limits>
#include <map>
#include <queue>
#include <set>
#include <utility>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/topology/topology.h"

namespace mspline::structure {

namespace {

using VH = TriMesh::VertexHandle;

OpenedSurface openAlongLoops(const TriMesh& surface, const LoopSystem& system) {
  OpenedSurface opened = openSurface(surface, edgesOfPaths(surface, system.loops));
  const TopologyReport disk = analyzeTopology(opened.cut.mesh);
  MSPLINE_ASSERT(disk.euler == 1 && disk.boundaryLoops == 1 && disk.components == 1,
                 "cutting along the one-vertex system did not give a disk");
  MSPLINE_ASSERT(opened.segmentBegins.size() == 2 * system.loops.size(),
                 "the one-vertex cut has the wrong number of boundary segments");
  return opened;
}

LoopWord currentWord(const GrowingSurface& work, const LoopSystem& system) {
  return readLoopWord(system, openAlongLoops(*work.surface, system));
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

/// A corner of the disk, named by the segment that starts there: (loop, sign). The name survives
/// re-cutting, whereas positions on the boundary do not.
using Corner = std::pair<int, int>;

Corner cornerAt(const LoopWord& word, std::size_t k) {
  return {word.loop[k], word.sign[k]};
}

/// The disk vertex at `corner`, or -1.
int cornerVertex(const OpenedSurface& opened, const LoopWord& word, Corner corner) {
  int vertex = -1;
  for (std::size_t k = 0; k < word.loop.size(); ++k)
    if (cornerAt(word, k) == corner) vertex = opened.boundaryLoop[opened.segmentBegins[k]];
  return vertex;
}

/// Splits the chords of the disk (edges joining two loop vertices that no loop runs along): each
/// separates the disk's inner vertices, and without them the inner vertices are connected and
/// every corner has an inner neighbour. New points lie on old edges.
void splitChords(GrowingSurface& work, const LoopSystem& system) {
  const TriMesh& mesh = *work.surface;
  std::vector<char> onLoop(mesh.n_vertices(), 0);
  std::set<VertexPair> loopEdges;
  for (const auto& loop : system.loops)
    for (std::size_t k = 0; k < loop.size(); ++k) {
      onLoop[loop[k]] = 1;
      if (k + 1 < loop.size()) loopEdges.insert(edgeKey(loop[k], loop[k + 1]));
    }
  std::vector<VertexPair> chords;
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    const int x = mesh.from_vertex_handle(h).idx(), y = mesh.to_vertex_handle(h).idx();
    if (onLoop[x] && onLoop[y] && !loopEdges.count(edgeKey(x, y))) chords.push_back({x, y});
  }
  for (const auto& [x, y] : chords) splitEdge(work, x, y);
}

/// The inner neighbours of a disk vertex.
std::vector<int> innerNeighbours(const TriMesh& disk, int vertex) {
  std::vector<int> near;
  for (auto w : disk.vv_range(VH(vertex)))
    if (!disk.is_boundary(w)) near.push_back(w.idx());
  return near;
}

/// Shortest path through inner disk vertices between the fans of two boundary vertices of the
/// disk, as disk vertices from the fan of `from` to the fan of `to` (empty when there is none).
/// Vertices next to the boundary cost four times their length, so the new loop keeps off the old
/// ones where it can (each contact becomes a chord to split next time).
std::vector<int> innerPath(const TriMesh& disk, const std::vector<int>& boundaryLoop, int from,
                           int to) {
  std::vector<double> factor(disk.n_vertices(), 1.0);
  for (int v : boundaryLoop)
    for (auto w : disk.vv_range(VH(v))) factor[w.idx()] = 4.0;
  std::vector<double> dist(disk.n_vertices(), std::numeric_limits<double>::infinity());
  std::vector<int> previous(disk.n_vertices(), -1);
  std::vector<char> target(disk.n_vertices(), 0);
  for (int v : innerNeighbours(disk, to)) target[v] = 1;
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (int v : innerNeighbours(disk, from)) {
    dist[v] = (disk.point(VH(v)) - disk.point(VH(from))).norm();
    queue.push({dist[v], v});
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v]) continue;
    if (target[v]) {
      std::vector<int> path;
      for (int w = v; w != -1; w = previous[w]) path.push_back(w);
      std::reverse(path.begin(), path.end());
      return path;
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
  return {};
}

/// Replaces loop `eliminated` by a new loop from corner `from` to corner `to` through the
/// interior of the disk (a cut-and-paste of the polygon: cut along the new diagonal, glue the two
/// pieces back along the eliminated loop).
void replaceLoop(GrowingSurface& work, LoopSystem& system, Corner from, Corner to, int eliminated) {
  for (;;) {
    checkGrowth(work);
    splitChords(work, system);
    const OpenedSurface opened = openAlongLoops(*work.surface, system);
    const LoopWord word = readLoopWord(system, opened);
    const int fromVertex = cornerVertex(opened, word, from);
    const int toVertex = cornerVertex(opened, word, to);
    MSPLINE_ASSERT(fromVertex != -1 && toVertex != -1, "lost a corner of the disk");
    const std::vector<int> inner =
        innerPath(opened.cut.mesh, opened.boundaryLoop, fromVertex, toVertex);
    if (inner.empty()) {
      // Without chords this does not happen; refining is the fallback should it still.
      refineSurface(work, system.loops);
      continue;
    }
    std::vector<int> loop{system.center};
    for (int v : inner) loop.push_back(opened.cut.sourceVertex[v]);
    loop.push_back(system.center);
    system.loops[eliminated] = std::move(loop);
    return;
  }
}

/// An interleaved pair of loops outside the blocks: loop x at `first` and again at `second`, loop
/// y once between them; y == -1 when there is none.
struct InterleavedPair {
  std::size_t first = 0;
  std::size_t second = 0;
  int y = -1;
};

InterleavedPair findInterleavedPair(const LoopWord& word, const std::vector<char>& done) {
  const std::size_t n = word.loop.size();
  for (std::size_t a = 0; a < n; ++a) {
    if (done[word.loop[a]]) continue;
    std::size_t b = a + 1;
    while (word.loop[b % n] != word.loop[a]) ++b;
    std::vector<int> count(done.size(), 0);
    for (std::size_t k = a + 1; k < b; ++k) ++count[word.loop[k % n]];
    for (std::size_t k = a + 1; k < b; ++k)
      if (count[word.loop[k % n]] == 1 && !done[word.loop[k % n]])
        return {a, b % n, word.loop[k % n]};
  }
  return {};
}

}  // namespace

LoopWord readLoopWord(const LoopSystem& system, const OpenedSurface& opened) {
  std::map<VertexPair, int> loopOfEdge;
  for (std::size_t i = 0; i < system.loops.size(); ++i)
    for (std::size_t k = 0; k + 1 < system.loops[i].size(); ++k)
      loopOfEdge[edgeKey(system.loops[i][k], system.loops[i][k + 1])] = static_cast<int>(i);
  LoopWord word;
  for (std::size_t s = 0; s < opened.segmentBegins.size(); ++s) {
    const std::vector<int> vertices = segmentVertices(opened, s);
    const auto found = loopOfEdge.find(edgeKey(vertices[0], vertices[1]));
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

void canonicalizeLoops(GrowingSurface& work, LoopSystem& system) {
  const std::size_t n = 2 * system.loops.size();
  for (std::size_t round = 0; round <= system.loops.size(); ++round) {
    checkGrowth(work);
    LoopWord word = currentWord(work, system);
    if (canonicalRotation(word) != -1) return;
    const auto blocks = canonicalBlocks(word);
    std::vector<char> done(system.loops.size(), 0);
    for (std::size_t r : blocks) done[word.loop[r]] = done[word.loop[(r + 1) % n]] = 1;
    const InterleavedPair pair = findInterleavedPair(word, done);
    if (pair.y == -1) return;
    const int x = word.loop[pair.first];

    // Move 1: diagonal z from the corner before x to the corner after x^-1, glue along y.
    replaceLoop(work, system, cornerAt(word, pair.first), cornerAt(word, (pair.second + 1) % n),
                pair.y);
    const int z = pair.y;
    // Move 2: diagonal w from the corner before z^-1 to the corner before z, glue along x.
    word = currentWord(work, system);
    std::size_t zNegative = n, zPositive = n;
    for (std::size_t k = 0; k < n; ++k)
      if (word.loop[k] == z) (word.sign[k] < 0 ? zNegative : zPositive) = k;
    MSPLINE_ASSERT(zNegative < n && zPositive < n, "the new loop is not on the boundary twice");
    replaceLoop(work, system, cornerAt(word, zNegative), cornerAt(word, zPositive), x);

    if (canonicalBlocks(currentWord(work, system)).size() <= blocks.size()) return;
  }
}

}  // namespace mspline::structure
