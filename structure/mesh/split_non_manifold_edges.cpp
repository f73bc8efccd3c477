// The split works on corners, like splitting bow-tie vertices: at each end of a non-manifold edge
// the corners there are grouped into fans through the edges that stay glued (manifold edges and the
// kept pairs), and every fan beyond the first gets a copy of the vertex. Pairs can meet again
// around both ends (a surface touching itself along the edge), so the result is checked and such
// edges are detached completely, which always succeeds: with every face at the edge on its own,
// each fan at an end is a chain of faces (no edge at the vertex glues more than two) and holds at
// most its two end faces of the edge.
#include "mspline/structure/mesh/split_non_manifold_edges.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>
#include <utility>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/min_union_find.h"
#include "mspline/structure/mesh/validate.h"

namespace mspline::structure {
namespace {

using Index = std::uint32_t;
constexpr Index kNone = SoupConnectivity::none;

using Vector = std::array<double, 3>;

Vector minus(const Vector& a, const Vector& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Vector cross(const Vector& a, const Vector& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vector& a, const Vector& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

std::uint64_t edgeKey(Index a, Index b) {
  return (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
}

// Where a face meets the edge (v0, v1): its corners at both ends, whether it runs from v0 to v1,
// and the vertex that follows the edge in the face (its wing).
struct EdgeCorner {
  Index face = 0;
  Index cornerAt0 = 0, cornerAt1 = 0;
  bool forward = false;
  Index wing = 0;
};

EdgeCorner locate(const PolygonSoup& soup, const SoupConnectivity& c, Index face, Index v0,
                  Index v1) {
  const auto& vs = soup.faces[face];
  const std::size_t k = vs.size();
  const auto first = static_cast<Index>(c.cornerOffset[face]);
  for (std::size_t i = 0; i < k; ++i) {
    if (vs[i] != v0) continue;
    const std::size_t next = (i + 1) % k, prev = (i + k - 1) % k;
    const bool forward = vs[next] == v1;
    const std::size_t at1 = forward ? next : prev;
    const std::size_t wing = forward ? (next + 1) % k : next;
    return {face, first + static_cast<Index>(i), first + static_cast<Index>(at1), forward,
            static_cast<Index>(vs[wing])};
  }
  MSPLINE_ASSERT(false, "a face listed at an edge does not hold the edge");
  return {};
}

// The wing's angle about the axis from v0 to v1; 0 when undefined (a zero-length edge, a wing on
// the axis, non-finite coordinates), which only makes the order among such faces arbitrary. Both
// vectors are divided by their largest coordinate first, so that no unit under- or overflows.
double wingAngle(const PolygonSoup& soup, Index v0, Index v1, Index wing) {
  auto scaled = [](Vector x) {
    const double largest = std::max({std::abs(x[0]), std::abs(x[1]), std::abs(x[2])});
    for (double& coordinate : x) coordinate /= largest;
    return x;
  };
  const Vector& p0 = soup.positions[v0];
  const Vector axis = scaled(minus(soup.positions[v1], p0));
  const Vector w = scaled(minus(soup.positions[wing], p0));
  // A reference direction across the axis: the cross product with the coordinate axis the edge
  // is least aligned with; then u, v, axis are right-handed and |v| = |axis| |u|.
  std::size_t least = 0;
  for (std::size_t i = 1; i < 3; ++i)
    if (std::abs(axis[i]) < std::abs(axis[least])) least = i;
  Vector basis{0.0, 0.0, 0.0};
  basis[least] = 1.0;
  const Vector u = cross(axis, basis);
  const Vector v = cross(axis, u);
  const double angle = std::atan2(dot(w, v) / std::sqrt(dot(axis, axis)), dot(w, u));
  return std::isfinite(angle) ? angle : 0.0;
}

// The faces at one non-manifold edge and the pairs among them that stay glued.
struct SplitEdge {
  Index v0 = 0, v1 = 0;
  std::vector<EdgeCorner> corners;          // in angular order about the axis v0 -> v1
  std::vector<std::array<Index, 2>> pairs;  // faces glued to each other
};

std::vector<std::array<Index, 2>> consistentPairs(const std::vector<EdgeCorner>& around) {
  std::vector<std::array<Index, 2>> pairs;
  const std::size_t k = around.size();
  for (std::size_t i = 0; i < k; ++i) {
    const EdgeCorner& here = around[i];
    const EdgeCorner& next = around[(i + 1) % k];
    if (!here.forward && next.forward) pairs.push_back({here.face, next.face});
  }
  return pairs;
}

// The corners of usable faces at each vertex of a split edge, in corner order.
struct VertexCorners {
  std::vector<Index> vertices;     // the split edges' vertices, ascending
  std::vector<Index> start;        // per listed vertex, its first entry in `corners`; one extra
  std::vector<Index> corners;      // global corner indices
  std::vector<Index> cornerFace;   // the face of each entry
  std::vector<Index> cornerIndex;  // the corner's position in its face
};

VertexCorners cornersAtVertices(const PolygonSoup& soup, const SoupConnectivity& c,
                                const std::vector<SplitEdge>& edges) {
  VertexCorners at;
  for (const auto& edge : edges) {
    at.vertices.push_back(edge.v0);
    at.vertices.push_back(edge.v1);
  }
  std::sort(at.vertices.begin(), at.vertices.end());
  at.vertices.erase(std::unique(at.vertices.begin(), at.vertices.end()), at.vertices.end());
  std::vector<Index> slot(soup.positions.size(), kNone);
  for (std::size_t i = 0; i < at.vertices.size(); ++i) slot[at.vertices[i]] = static_cast<Index>(i);
  at.start.assign(at.vertices.size() + 1, 0);
  auto forEachCorner = [&](auto&& visit) {
    for (std::size_t f = 0; f < soup.faces.size(); ++f) {
      if (!c.usable[f]) continue;
      for (std::size_t i = 0; i < soup.faces[f].size(); ++i) {
        const Index s = slot[static_cast<std::size_t>(soup.faces[f][i])];
        if (s != kNone) visit(s, static_cast<Index>(f), static_cast<Index>(i));
      }
    }
  };
  forEachCorner([&](Index s, Index, Index) { ++at.start[s + 1]; });
  std::partial_sum(at.start.begin(), at.start.end(), at.start.begin());
  at.corners.resize(at.start.back());
  at.cornerFace.resize(at.start.back());
  at.cornerIndex.resize(at.start.back());
  std::vector<Index> fill(at.start.begin(), at.start.end() - 1);
  forEachCorner([&](Index s, Index f, Index i) {
    const Index entry = fill[s]++;
    at.corners[entry] = static_cast<Index>(c.cornerOffset[f]) + i;
    at.cornerFace[entry] = f;
    at.cornerIndex[entry] = i;
  });
  return at;
}

// Per corner at a split edge's vertex: the smallest corner of its fan, where faces are joined
// across the manifold edges at the vertex and across split edges by their pairs (none when
// detached); `splitEdgeOf` finds a split edge by its key.
std::vector<Index> fansAtVertices(const PolygonSoup& soup, const VertexCorners& at,
                                  const std::unordered_map<std::uint64_t, Index>& splitEdgeOf,
                                  const std::vector<SplitEdge>& edges,
                                  const std::vector<std::uint8_t>& detached,
                                  std::size_t cornerCount) {
  std::vector<Index> fan(cornerCount, kNone);
  // (neighbour vertex, local corner) for both edges of every corner at the vertex.
  std::vector<std::pair<Index, Index>> spokes;
  for (std::size_t s = 0; s < at.vertices.size(); ++s) {
    const Index v = at.vertices[s];
    const Index begin = at.start[s], count = at.start[s + 1] - begin;
    MinUnionFind local(count);
    spokes.clear();
    for (Index j = 0; j < count; ++j) {
      const auto& face = soup.faces[at.cornerFace[begin + j]];
      const std::size_t k = face.size(), i = at.cornerIndex[begin + j];
      spokes.push_back({static_cast<Index>(face[(i + 1) % k]), j});
      spokes.push_back({static_cast<Index>(face[(i + k - 1) % k]), j});
    }
    std::sort(spokes.begin(), spokes.end());
    for (std::size_t r = 0; r < spokes.size();) {
      std::size_t end = r;
      while (end < spokes.size() && spokes[end].first == spokes[r].first) ++end;
      if (end - r == 2) {
        local.unite(spokes[r].second, spokes[r + 1].second);
      } else if (end - r > 2) {
        const Index e = splitEdgeOf.at(edgeKey(v, spokes[r].first));
        if (!detached[e]) {
          for (const auto& pair : edges[e].pairs) {
            Index a = kNone, b = kNone;
            for (std::size_t q = r; q < end; ++q) {
              const Index face = at.cornerFace[begin + spokes[q].second];
              if (face == pair[0]) a = spokes[q].second;
              if (face == pair[1]) b = spokes[q].second;
            }
            local.unite(a, b);
          }
        }
      }
      r = end;
    }
    // Local roots are the smallest local entries, and entries follow corner order.
    for (Index j = 0; j < count; ++j)
      fan[at.corners[begin + j]] = at.corners[begin + local.find(j)];
  }
  return fan;
}

// Whether more than two faces at the edge still share both ends' fans.
bool stillNonManifold(const SplitEdge& edge, const std::vector<Index>& fan) {
  std::vector<std::pair<Index, Index>> ends;
  for (const auto& corner : edge.corners)
    ends.push_back({fan[corner.cornerAt0], fan[corner.cornerAt1]});
  std::sort(ends.begin(), ends.end());
  for (std::size_t i = 2; i < ends.size(); ++i)
    if (ends[i] == ends[i - 2]) return true;
  return false;
}

}  // namespace

SplitNonManifoldEdgesResult splitNonManifoldEdges(PolygonSoup soup,
                                                  const SplitNonManifoldEdgesOptions& options) {
  SplitNonManifoldEdgesResult result;
  const std::size_t nv = soup.positions.size();
  const SoupConnectivity c = analyzeConnectivity(soup);
  std::vector<SplitEdge> edges;
  std::unordered_map<std::uint64_t, Index> splitEdgeOf;
  for (const auto& found : c.nonManifoldEdges) {
    SplitEdge edge;
    edge.v0 = found.v0;
    edge.v1 = found.v1;
    std::vector<std::pair<double, EdgeCorner>> around;
    for (Index face : found.faces) {
      const EdgeCorner corner = locate(soup, c, face, edge.v0, edge.v1);
      around.push_back({wingAngle(soup, edge.v0, edge.v1, corner.wing), corner});
    }
    std::sort(around.begin(), around.end(), [](const auto& x, const auto& y) {
      return x.first != y.first ? x.first < y.first : x.second.face < y.second.face;
    });
    for (const auto& entry : around) edge.corners.push_back(entry.second);
    if (options.pairFaces) edge.pairs = consistentPairs(edge.corners);
    splitEdgeOf.emplace(edgeKey(edge.v0, edge.v1), static_cast<Index>(edges.size()));
    edges.push_back(std::move(edge));
  }
  result.edgesSplit = edges.size();
  if (edges.empty()) {
    result.soup = std::move(soup);
    return result;
  }

  const VertexCorners at = cornersAtVertices(soup, c, edges);
  const std::size_t cornerCount = c.cornerOffset.back();
  std::vector<std::uint8_t> detached(edges.size(), options.pairFaces ? 0 : 1);
  std::vector<Index> fan = fansAtVertices(soup, at, splitEdgeOf, edges, detached, cornerCount);
  bool anyDetached = false;
  for (std::size_t e = 0; e < edges.size(); ++e) {
    if (detached[e] || !stillNonManifold(edges[e], fan)) continue;
    detached[e] = 1;
    anyDetached = true;
  }
  // Detaching only splits fans, so the edges that passed still pass, and the detached ones pass by
  // the argument at the top: one recomputation is final.
  if (anyDetached) fan = fansAtVertices(soup, at, splitEdgeOf, edges, detached, cornerCount);

  // The first fan at a vertex (by corner order) keeps it, every later fan gets a copy.
  std::vector<Index> fanVertex(cornerCount, kNone);
  for (std::size_t s = 0; s < at.vertices.size(); ++s) {
    for (Index entry = at.start[s]; entry < at.start[s + 1]; ++entry) {
      const Index corner = at.corners[entry];
      const Index root = fan[corner];
      if (root == corner) {
        fanVertex[root] =
            entry == at.start[s] ? at.vertices[s] : static_cast<Index>(soup.positions.size());
        if (entry != at.start[s]) soup.positions.push_back(soup.positions[at.vertices[s]]);
      }
      soup.faces[at.cornerFace[entry]][at.cornerIndex[entry]] = fanVertex[root];
    }
  }
  result.verticesAdded = soup.positions.size() - nv;

  for (std::size_t e = 0; e < edges.size(); ++e) {
    const std::size_t kept = detached[e] ? 0 : edges[e].pairs.size();
    result.pairsKept += kept;
    result.facesDetached += edges[e].corners.size() - 2 * kept;
    if (detached[e] && options.pairFaces) ++result.edgesFullyDetached;
  }
  result.soup = std::move(soup);
  return result;
}

}  // namespace mspline::structure
