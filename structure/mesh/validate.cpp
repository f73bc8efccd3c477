// Validation works on flat arrays only: half-edges bucketed by their smaller vertex instead of a
// map of edges, union-find over corners (fans), faces (orientation) and vertices (components), so
// that a million triangles are checked in a fraction of a second.
#include "mspline/structure/mesh/validate.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <utility>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/exact_scale.h"
#include "mspline/structure/core/min_union_find.h"

namespace mspline::structure {
namespace {

using Index = std::uint32_t;
constexpr Index kNone = SoupConnectivity::none;

// Union-find over faces that also keeps every face's flip parity relative to its root (the
// smallest face of the set): a 2-colouring across manifold edges. A constraint contradicting the
// colouring marks the set non-orientable.
class ParityUnionFind {
 public:
  explicit ParityUnionFind(std::size_t n) : parent_(n), parity_(n, 0), orientable_(n, 1) {
    std::iota(parent_.begin(), parent_.end(), Index{0});
  }
  // Root of x and x's parity relative to it; iterative so long chains cannot overflow the stack.
  std::pair<Index, std::uint8_t> find(Index x) {
    Index root = x;
    std::uint8_t total = 0;
    while (parent_[root] != root) {
      total ^= parity_[root];
      root = parent_[root];
    }
    std::uint8_t toRoot = total;
    for (Index node = x; node != root;) {
      const Index next = parent_[node];
      const std::uint8_t step = parity_[node];
      parent_[node] = root;
      parity_[node] = toRoot;
      toRoot ^= step;
      node = next;
    }
    return {root, total};
  }
  // Requires parity(a) xor parity(b) == relative.
  void unite(Index a, Index b, std::uint8_t relative) {
    auto [ra, pa] = find(a);
    auto [rb, pb] = find(b);
    if (ra == rb) {
      if ((pa ^ pb) != relative) orientable_[ra] = 0;
      return;
    }
    if (rb < ra) std::swap(ra, rb);
    parent_[rb] = ra;
    parity_[rb] = static_cast<std::uint8_t>(pa ^ pb ^ relative);
    orientable_[ra] = static_cast<std::uint8_t>(orientable_[ra] & orientable_[rb]);
  }
  bool orientable(Index root) const { return orientable_[root] != 0; }

 private:
  std::vector<Index> parent_;
  std::vector<std::uint8_t> parity_;
  std::vector<std::uint8_t> orientable_;
};

// Marks faces whose sorted vertex set equals an earlier valid face's. Faces are bucketed by their
// smallest vertex (counting sort), so only faces sharing it are ever compared.
void findDuplicates(const PolygonSoup& soup, SoupConnectivity& c, std::vector<Index>& setStart,
                    std::vector<Index>& setVertices) {
  const std::size_t nf = soup.faces.size();
  const std::size_t nv = soup.positions.size();
  setStart.assign(nf + 1, 0);
  setVertices.clear();
  setVertices.reserve(c.cornerOffset[nf]);
  for (std::size_t f = 0; f < nf; ++f) {
    setStart[f] = static_cast<Index>(setVertices.size());
    if (!c.valid[f]) continue;
    const std::size_t begin = setVertices.size();
    for (std::int64_t v : soup.faces[f]) setVertices.push_back(static_cast<Index>(v));
    std::sort(setVertices.begin() + static_cast<std::ptrdiff_t>(begin), setVertices.end());
    setVertices.erase(
        std::unique(setVertices.begin() + static_cast<std::ptrdiff_t>(begin), setVertices.end()),
        setVertices.end());
  }
  setStart[nf] = static_cast<Index>(setVertices.size());

  std::vector<Index> bucketStart(nv + 1, 0);
  for (std::size_t f = 0; f < nf; ++f)
    if (c.valid[f]) ++bucketStart[setVertices[setStart[f]] + 1];
  std::partial_sum(bucketStart.begin(), bucketStart.end(), bucketStart.begin());
  std::vector<Index> byMinVertex(bucketStart[nv]);
  {
    std::vector<Index> fill(bucketStart.begin(), bucketStart.end() - 1);
    for (std::size_t f = 0; f < nf; ++f)
      if (c.valid[f]) byMinVertex[fill[setVertices[setStart[f]]]++] = static_cast<Index>(f);
  }
  auto setOf = [&](Index f) {
    return std::make_pair(setVertices.begin() + setStart[f], setVertices.begin() + setStart[f + 1]);
  };
  auto lessSet = [&](Index a, Index b) {
    const auto [a0, a1] = setOf(a);
    const auto [b0, b1] = setOf(b);
    if (std::lexicographical_compare(a0, a1, b0, b1)) return true;
    if (std::lexicographical_compare(b0, b1, a0, a1)) return false;
    return a < b;
  };
  auto equalSet = [&](Index a, Index b) {
    const auto [a0, a1] = setOf(a);
    const auto [b0, b1] = setOf(b);
    return std::equal(a0, a1, b0, b1);
  };
  for (std::size_t v = 0; v < nv; ++v) {
    const auto begin = byMinVertex.begin() + bucketStart[v];
    const auto end = byMinVertex.begin() + bucketStart[v + 1];
    if (end - begin < 2) continue;
    std::sort(begin, end, lessSet);
    for (auto first = begin, it = begin + 1; it != end; ++it) {
      if (equalSet(*first, *it))
        c.duplicateOf[*it] = *first;
      else
        first = it;
    }
  }
}

struct HalfEdge {
  Index hi;        // larger vertex of the undirected edge (the smaller one is its bucket)
  Index cornerLo;  // the face's corner at the smaller vertex
  Index cornerHi;  // the face's corner at the larger vertex
  Index face : 31;
  Index forward : 1;  // whether the face runs from the smaller to the larger vertex
};

std::string countOf(std::size_t n, const std::string& singular, const std::string& plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

// "at face 4" or "first at faces 4, 9, ..." for the listed elements.
std::string location(const std::vector<std::int64_t>& elements, bool more, const char* singular,
                     const char* plural) {
  std::ostringstream out;
  if (elements.size() == 1 && !more) {
    out << "at " << singular << " " << elements.front();
    return out.str();
  }
  out << "first at " << plural << " ";
  for (std::size_t i = 0; i < elements.size(); ++i) out << (i ? ", " : "") << elements[i];
  if (more) out << ", ...";
  return out.str();
}

MeshProblem problem(const std::string& source, std::string kind, std::size_t count,
                    std::vector<std::int64_t> elements, bool more, const std::string& what,
                    const char* singular, const char* plural) {
  MeshProblem p;
  p.kind = std::move(kind);
  p.count = count;
  p.message = source + ": " + what + ", " + location(elements, more, singular, plural);
  p.elements = std::move(elements);
  return p;
}

// Appends the first maxListed indices i with predicate(i) and returns how many there are.
template <typename Predicate>
std::size_t collect(std::size_t n, std::size_t maxListed, std::vector<std::int64_t>& listed,
                    Predicate predicate) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!predicate(i)) continue;
    if (listed.size() < maxListed) listed.push_back(static_cast<std::int64_t>(i));
    ++count;
  }
  return count;
}

// Adds faces to `listed` (without repeats) until maxListed; returns whether any did not fit.
template <typename Faces>
bool listFaces(const Faces& faces, std::size_t maxListed, std::vector<std::int64_t>& listed) {
  bool more = false;
  for (Index f : faces) {
    if (std::find(listed.begin(), listed.end(), static_cast<std::int64_t>(f)) != listed.end())
      continue;
    if (listed.size() < maxListed)
      listed.push_back(f);
    else
      more = true;
  }
  return more;
}

}  // namespace

SoupConnectivity analyzeConnectivity(const PolygonSoup& soup) {
  const std::size_t nv = soup.positions.size();
  const std::size_t nf = soup.faces.size();
  MSPLINE_ASSERT(nv < kNone && nf < (Index{1} << 31), "soup too large for 32-bit indices");
  SoupConnectivity c;
  c.valid.assign(nf, 0);
  c.usable.assign(nf, 0);
  c.duplicateOf.assign(nf, kNone);
  c.cornerOffset.assign(nf + 1, 0);
  for (std::size_t f = 0; f < nf; ++f) {
    const auto& face = soup.faces[f];
    c.cornerOffset[f + 1] = c.cornerOffset[f] + face.size();
    c.valid[f] = face.size() >= 3 && std::all_of(face.begin(), face.end(), [&](std::int64_t v) {
                   return v >= 0 && static_cast<std::uint64_t>(v) < nv;
                 });
  }
  const std::size_t corners = c.cornerOffset[nf];
  MSPLINE_ASSERT(corners < kNone, "soup too large for 32-bit corner indices");

  std::vector<Index> setStart, setVertices;
  findDuplicates(soup, c, setStart, setVertices);
  for (std::size_t f = 0; f < nf; ++f) {
    const bool repeated = setStart[f + 1] - setStart[f] < soup.faces[f].size();
    c.usable[f] = c.valid[f] && !repeated && c.duplicateOf[f] == kNone;
  }
  setVertices = {};

  // Components of valid faces through shared vertices.
  {
    MinUnionFind vertices(nv);
    for (std::size_t f = 0; f < nf; ++f) {
      if (!c.valid[f]) continue;
      const auto& face = soup.faces[f];
      for (std::size_t i = 1; i < face.size(); ++i)
        vertices.unite(static_cast<Index>(face[0]), static_cast<Index>(face[i]));
    }
    std::vector<Index> firstFace(nv, kNone);
    c.faceComponent.assign(nf, kNone);
    for (std::size_t f = 0; f < nf; ++f) {
      if (!c.valid[f]) continue;
      Index& first = firstFace[vertices.find(static_cast<Index>(soup.faces[f][0]))];
      if (first == kNone) first = static_cast<Index>(f);
      c.faceComponent[f] = first;
    }
  }

  // Half-edges of usable faces, bucketed by their smaller vertex (counting sort). Each entry
  // carries everything the edge pass needs, so that pass reads no other per-corner array.
  auto forEachHalfEdge = [&](auto&& visit) {
    for (std::size_t f = 0; f < nf; ++f) {
      if (!c.usable[f]) continue;
      const auto& face = soup.faces[f];
      const auto first = static_cast<Index>(c.cornerOffset[f]);
      const auto k = static_cast<Index>(face.size());
      for (Index i = 0; i < k; ++i) {
        const Index j = i + 1 == k ? 0 : i + 1;
        visit(static_cast<Index>(f), static_cast<Index>(face[i]), static_cast<Index>(face[j]),
              first + i, first + j);
      }
    }
  };
  std::vector<Index> bucketStart(nv + 1, 0);
  forEachHalfEdge(
      [&](Index, Index a, Index b, Index, Index) { ++bucketStart[std::min(a, b) + 1]; });
  std::partial_sum(bucketStart.begin(), bucketStart.end(), bucketStart.begin());
  std::vector<HalfEdge> halfEdges(bucketStart[nv]);
  {
    std::vector<Index> fill(bucketStart.begin(), bucketStart.end() - 1);
    forEachHalfEdge([&](Index f, Index a, Index b, Index ca, Index cb) {
      halfEdges[fill[std::min(a, b)]++] =
          a < b ? HalfEdge{b, ca, cb, f, true} : HalfEdge{a, cb, ca, f, false};
    });
  }

  MinUnionFind fans(corners);
  ParityUnionFind orientation(nf);
  for (Index lo = 0; lo < nv; ++lo) {
    const auto bucketBegin = halfEdges.begin() + bucketStart[lo];
    const auto bucketEnd = halfEdges.begin() + bucketStart[lo + 1];
    std::sort(bucketBegin, bucketEnd, [](const HalfEdge& x, const HalfEdge& y) {
      return x.hi != y.hi ? x.hi < y.hi : x.face < y.face;
    });
    for (auto run = bucketBegin; run != bucketEnd;) {
      auto runEnd = run;
      while (runEnd != bucketEnd && runEnd->hi == run->hi) ++runEnd;
      ++c.edges;
      // Every face at the edge joins the fans at both ends; at a non-manifold edge the fans
      // cannot be told apart, which non_manifold_edge reports.
      for (auto h = run + 1; h != runEnd; ++h) {
        fans.unite(run->cornerLo, h->cornerLo);
        fans.unite(run->cornerHi, h->cornerHi);
      }
      const auto uses = runEnd - run;
      if (uses == 2) {
        const auto& h0 = run[0];
        const auto& h1 = run[1];
        const bool sameDirection = h0.forward == h1.forward;
        orientation.unite(h0.face, h1.face, sameDirection ? 1 : 0);
        if (sameDirection) c.inconsistentEdges.push_back({h0.face, h1.face});
      } else if (uses >= 3) {
        SoupConnectivity::NonManifoldEdge edge;
        edge.v0 = lo;
        edge.v1 = run->hi;
        for (auto h = run; h != runEnd; ++h) edge.faces.push_back(h->face);
        c.nonManifoldEdges.push_back(std::move(edge));
      }
      run = runEnd;
    }
  }
  halfEdges = {};
  std::sort(c.nonManifoldEdges.begin(), c.nonManifoldEdges.end(),
            [](const auto& x, const auto& y) { return x.faces < y.faces; });
  std::sort(c.inconsistentEdges.begin(), c.inconsistentEdges.end());

  c.cornerFan.resize(corners);
  std::iota(c.cornerFan.begin(), c.cornerFan.end(), Index{0});
  c.fanCount.assign(nv, 0);
  forEachHalfEdge([&](Index, Index a, Index, Index ca, Index) {
    c.cornerFan[ca] = fans.find(ca);
    if (c.cornerFan[ca] == ca) ++c.fanCount[a];
  });

  c.facePatch.resize(nf);
  c.faceFlip.resize(nf);
  c.patchOrientable.resize(nf);
  for (Index f = 0; f < nf; ++f) {
    const auto [root, parity] = orientation.find(f);
    c.facePatch[f] = root;
    c.faceFlip[f] = parity;
    c.patchOrientable[f] = orientation.orientable(root) ? 1 : 0;
  }
  return c;
}

bool isDegenerateFace(const PolygonSoup& soup, std::size_t face, double tolerance) {
  const auto& vs = soup.faces[face];
  if (vs.size() < 3) return true;
  for (std::size_t i = 0; i < vs.size(); ++i)
    for (std::size_t j = i + 1; j < vs.size(); ++j)
      if (vs[i] == vs[j]) return true;
  for (std::int64_t v : vs)
    for (double x : soup.positions[static_cast<std::size_t>(v)])
      if (!std::isfinite(x)) return false;

  // Coordinates relative to the first vertex, scaled by a power of two to magnitude ~1: the
  // answer does not depend on the unit and squares neither overflow nor underflow (1e+-300).
  const auto& p0 = soup.positions[static_cast<std::size_t>(vs[0])];
  double extent = 0.0;
  for (std::int64_t v : vs)
    for (int k = 0; k < 3; ++k)
      extent = std::max(extent, std::abs(soup.positions[static_cast<std::size_t>(v)][k] - p0[k]));
  const double scale = exactUnitScale(extent);
  auto scaledDifference = [scale](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return std::array<double, 3>{(a[0] - b[0]) * scale, (a[1] - b[1]) * scale,
                                 (a[2] - b[2]) * scale};
  };
  // Newell normal as a sum of cross products from the first vertex: for a triangle it is the
  // plain cross product, whose length is twice the area without cancellation.
  std::array<double, 3> normal{0.0, 0.0, 0.0};
  double longest2 = 0.0;
  for (std::size_t i = 0; i < vs.size(); ++i) {
    const auto& p = soup.positions[static_cast<std::size_t>(vs[i])];
    const auto& q = soup.positions[static_cast<std::size_t>(vs[(i + 1) % vs.size()])];
    const auto e = scaledDifference(q, p);
    longest2 = std::max(longest2, e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    if (i == 0 || i + 1 == vs.size()) continue;
    const auto a = scaledDifference(p, p0), b = scaledDifference(q, p0);
    normal[0] += a[1] * b[2] - a[2] * b[1];
    normal[1] += a[2] * b[0] - a[0] * b[2];
    normal[2] += a[0] * b[1] - a[1] * b[0];
  }
  const double twiceArea =
      std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
  return twiceArea <= tolerance * longest2;
}

ValidationReport validate(const PolygonSoup& soup, const ValidationOptions& options) {
  const std::size_t nv = soup.positions.size();
  const std::size_t nf = soup.faces.size();
  const std::string& src = soup.sourceName;
  const std::size_t maxListed = options.maxListed;
  ValidationReport report;
  report.vertices = nv;
  report.faces = nf;

  if (nf == 0 || nv == 0) {
    MeshProblem p;
    p.kind = "empty_mesh";
    p.count = 1;
    p.message = src + ": the mesh is empty (" + countOf(nf, "face", "faces") + ", " +
                countOf(nv, "vertex", "vertices") + ")";
    report.problems.push_back(std::move(p));
  }

  const SoupConnectivity c = analyzeConnectivity(soup);
  report.edges = c.edges;

  {
    std::vector<std::int64_t> listed;
    std::int64_t firstBad = 0;
    const std::size_t n = collect(nf, maxListed, listed, [&](std::size_t f) {
      const auto& face = soup.faces[f];
      if (face.size() < 3 || c.valid[f]) return false;
      if (listed.empty())
        firstBad = *std::find_if(face.begin(), face.end(), [&](std::int64_t v) {
          return v < 0 || static_cast<std::uint64_t>(v) >= nv;
        });
      return true;
    });
    if (n > 0) {
      const std::string range =
          nv == 0 ? "there are no vertices" : "valid indices are 0 to " + std::to_string(nv - 1);
      report.problems.push_back(problem(
          src, "face_index_out_of_range", n, listed, n > listed.size(),
          countOf(n, "face", "faces") + " with vertex indices out of range (" + range + "; face " +
              std::to_string(listed.front()) + " uses " + std::to_string(firstBad) + ")",
          "face", "faces"));
    }
  }
  {
    std::vector<std::int64_t> listed;
    const std::size_t n =
        collect(nf, maxListed, listed, [&](std::size_t f) { return soup.faces[f].size() < 3; });
    if (n > 0)
      report.problems.push_back(problem(src, "too_few_face_vertices", n, listed, n > listed.size(),
                                        countOf(n, "face", "faces") + " with fewer than 3 vertices",
                                        "face", "faces"));
  }
  {
    std::vector<std::int64_t> listed;
    const std::size_t n = collect(nv, maxListed, listed, [&](std::size_t v) {
      const auto& p = soup.positions[v];
      return !(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]));
    });
    if (n > 0)
      report.problems.push_back(problem(
          src, "non_finite_coordinate", n, listed, n > listed.size(),
          countOf(n, "vertex", "vertices") + " with a non-finite coordinate (NaN or infinity)",
          "vertex", "vertices"));
  }
  if (!c.nonManifoldEdges.empty()) {
    const std::size_t n = c.nonManifoldEdges.size();
    std::vector<std::int64_t> listed;
    bool more = false;
    for (const auto& edge : c.nonManifoldEdges) {
      more = listFaces(edge.faces, maxListed, listed);
      if (more) break;
    }
    const auto& first = c.nonManifoldEdges.front();
    std::sort(listed.begin(), listed.end());
    report.problems.push_back(
        problem(src, "non_manifold_edge", n, listed, more,
                countOf(n, "non-manifold edge", "non-manifold edges") +
                    " (edges shared by 3 or more faces; the first joins vertices " +
                    std::to_string(first.v0) + " and " + std::to_string(first.v1) + ")",
                "face", "faces"));
  }
  {
    std::vector<std::int64_t> listed;
    const std::size_t n =
        collect(nv, maxListed, listed, [&](std::size_t v) { return c.fanCount[v] >= 2; });
    if (n > 0)
      report.problems.push_back(
          problem(src, "non_manifold_vertex", n, listed, n > listed.size(),
                  countOf(n, "non-manifold vertex", "non-manifold vertices") +
                      " (faces around the vertex form 2 or more fans that meet only at it)",
                  "vertex", "vertices"));
  }
  {
    std::vector<std::int64_t> listed;
    const std::size_t n = collect(nf, maxListed, listed, [&](std::size_t f) {
      return c.valid[f] && isDegenerateFace(soup, f, options.degenerateTolerance);
    });
    if (n > 0)
      report.problems.push_back(problem(
          src, "degenerate_face", n, listed, n > listed.size(),
          countOf(n, "degenerate face", "degenerate faces") + " (repeated vertex or zero area)",
          "face", "faces"));
  }
  {
    std::vector<std::int64_t> listed;
    const std::size_t n =
        collect(nf, maxListed, listed, [&](std::size_t f) { return c.duplicateOf[f] != kNone; });
    if (n > 0) {
      const std::size_t first = static_cast<std::size_t>(listed.front());
      report.problems.push_back(problem(src, "duplicate_face", n, listed, n > listed.size(),
                                        countOf(n, "duplicate face", "duplicate faces") +
                                            " (same vertices as an earlier face; face " +
                                            std::to_string(first) + " repeats face " +
                                            std::to_string(c.duplicateOf[first]) + ")",
                                        "face", "faces"));
    }
  }

  std::size_t nonOrientablePatches = 0;
  for (std::size_t f = 0; f < nf; ++f)
    if (c.usable[f] && c.facePatch[f] == f && !c.patchOrientable[f]) ++nonOrientablePatches;
  report.orientable = nonOrientablePatches == 0;
  if (!c.inconsistentEdges.empty()) {
    const std::size_t n = c.inconsistentEdges.size();
    std::vector<std::int64_t> listed;
    bool more = false;
    for (const auto& pair : c.inconsistentEdges) {
      more = listFaces(pair, maxListed, listed);
      if (more) break;
    }
    std::sort(listed.begin(), listed.end());
    const std::string edges =
        countOf(n, "edge", "edges") + (n == 1 ? " is traversed" : " are traversed") +
        " in the same direction by both of " + (n == 1 ? "its" : "their") + " faces";
    const std::string what =
        report.orientable ? "inconsistent orientation (fixable by flipping faces): " + edges
                          : "the surface is non-orientable (cannot be fixed by flipping faces; " +
                                countOf(nonOrientablePatches, "patch", "patches") +
                                " like a Moebius strip): " + edges;
    report.problems.push_back(
        problem(src, "inconsistent_orientation", n, listed, more, what, "face", "faces"));
  }
  {
    std::vector<std::uint8_t> referenced(nv, 0);
    for (std::size_t f = 0; f < nf; ++f)
      if (c.valid[f])
        for (std::int64_t v : soup.faces[f]) referenced[static_cast<std::size_t>(v)] = 1;
    std::vector<std::int64_t> listed;
    const std::size_t n =
        collect(nv, maxListed, listed, [&](std::size_t v) { return !referenced[v]; });
    if (n > 0 && nf > 0)
      report.problems.push_back(problem(
          src, "unreferenced_vertex", n, listed, n > listed.size(),
          countOf(n, "unreferenced vertex", "unreferenced vertices") + " (used by no valid face)",
          "vertex", "vertices"));
  }
  {
    std::vector<std::size_t> size(nf, 0);
    for (std::size_t f = 0; f < nf; ++f)
      if (c.faceComponent[f] != kNone) ++size[c.faceComponent[f]];
    std::vector<Index> components;
    for (std::size_t f = 0; f < nf; ++f)
      if (c.faceComponent[f] == f) components.push_back(static_cast<Index>(f));
    report.components = components.size();
    if (components.size() >= 2) {
      std::stable_sort(components.begin(), components.end(),
                       [&](Index a, Index b) { return size[a] > size[b]; });
      std::vector<std::int64_t> listed;
      for (std::size_t i = 0; i < components.size() && i < maxListed; ++i)
        listed.push_back(components[i]);
      std::string sizes;
      const std::size_t shown = std::min<std::size_t>(components.size(), 5);
      for (std::size_t i = 0; i < shown; ++i)
        sizes += (i ? ", " : "") + std::to_string(size[components[i]]);
      if (shown < components.size()) sizes += ", ...";
      MeshProblem p;
      p.kind = "multiple_components";
      p.count = components.size();
      p.elements = listed;
      std::ostringstream msg;
      msg << src << ": " << components.size()
          << " components (faces connected through shared vertices) with " << sizes
          << " faces, largest first, starting at faces ";
      for (std::size_t i = 0; i < listed.size(); ++i) msg << (i ? ", " : "") << listed[i];
      if (listed.size() < components.size()) msg << ", ...";
      p.message = msg.str();
      report.problems.push_back(std::move(p));
    }
  }
  return report;
}

bool preventsManifoldMesh(const std::string& kind) {
  static const std::array<const char*, 7> kinds = {
      "empty_mesh",        "face_index_out_of_range", "too_few_face_vertices",
      "non_manifold_edge", "non_manifold_vertex",     "inconsistent_orientation",
      "duplicate_face"};
  return std::find(kinds.begin(), kinds.end(), kind) != kinds.end();
}

bool hidesTopology(const std::string& kind) {
  return preventsManifoldMesh(kind) || kind == "unreferenced_vertex";
}

std::string ValidationReport::summary() const {
  if (problems.empty()) return "no problems";
  std::string out = problems.front().message;
  for (std::size_t i = 1; i < problems.size(); ++i)
    out += (i == 1 ? "; also: " : ", ") + problems[i].kind;
  return out;
}

}  // namespace mspline::structure
