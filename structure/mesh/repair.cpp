// Each repair recomputes the connectivity it needs with analyzeConnectivity(), so it acts on
// exactly the defects validate() reports for the soup as the previous repairs left it.
#include "mspline/structure/mesh/repair.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <numeric>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/split_non_manifold_edges.h"
#include "mspline/structure/mesh/validate.h"

namespace mspline::structure {
namespace {

using Index = std::uint32_t;

std::string countOf(std::size_t n, const std::string& singular, const std::string& plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

// Keeps the faces (and their corner UVs) with keep[f] set; returns how many were removed.
std::size_t removeFaces(PolygonSoup& soup, const std::vector<std::uint8_t>& keep) {
  const bool uvs = !soup.cornerUVs.empty();
  std::size_t kept = 0;
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    if (!keep[f]) continue;
    if (kept != f) {  // self-move-assignment would empty the vector
      soup.faces[kept] = std::move(soup.faces[f]);
      if (uvs) soup.cornerUVs[kept] = std::move(soup.cornerUVs[f]);
    }
    ++kept;
  }
  const std::size_t removed = soup.faces.size() - kept;
  soup.faces.resize(kept);
  if (uvs) soup.cornerUVs.resize(kept);
  return removed;
}

// Keeps the vertices with keep[v] set, in order, and renumbers faces through `target`, which maps
// every old vertex to the old vertex that replaces it (itself when kept).
void compactVertices(PolygonSoup& soup, const std::vector<std::uint8_t>& keep,
                     const std::vector<Index>& target) {
  std::vector<Index> renumber(soup.positions.size(), 0);
  std::size_t kept = 0;
  for (std::size_t v = 0; v < soup.positions.size(); ++v) {
    if (!keep[v]) continue;
    renumber[v] = static_cast<Index>(kept);
    soup.positions[kept++] = soup.positions[v];
  }
  soup.positions.resize(kept);
  for (auto& face : soup.faces)
    for (auto& v : face) v = renumber[target[static_cast<std::size_t>(v)]];
}

RepairAction mergeDuplicateVertices(PolygonSoup& soup) {
  const std::size_t nv = soup.positions.size();
  // Bit patterns, so that only truly identical coordinates merge (0.0 and -0.0 stay apart).
  std::vector<std::array<std::uint64_t, 3>> bits(nv);
  for (std::size_t v = 0; v < nv; ++v) std::memcpy(bits[v].data(), soup.positions[v].data(), 24);
  std::vector<Index> order(nv);
  std::iota(order.begin(), order.end(), Index{0});
  std::sort(order.begin(), order.end(),
            [&](Index a, Index b) { return bits[a] != bits[b] ? bits[a] < bits[b] : a < b; });
  std::vector<Index> target(nv);
  std::vector<std::uint8_t> keep(nv, 1);
  std::size_t merged = 0, groups = 0;
  for (std::size_t i = 0; i < nv; ++i) {
    const bool repeat = i > 0 && bits[order[i]] == bits[order[i - 1]];
    target[order[i]] = repeat ? target[order[i - 1]] : order[i];
    if (repeat) {
      keep[order[i]] = 0;
      ++merged;
      if (i < 2 || bits[order[i - 2]] != bits[order[i]]) ++groups;
    }
  }
  compactVertices(soup, keep, target);
  return {"merge_duplicate_vertices", merged,
          soup.sourceName + ": merged " + countOf(merged, "vertex", "vertices") + " into " +
              countOf(groups, "vertex", "vertices") + " with bit-identical coordinates"};
}

RepairAction removeDegenerateFaces(PolygonSoup& soup, double tolerance) {
  std::vector<std::uint8_t> keep(soup.faces.size());
  for (std::size_t f = 0; f < soup.faces.size(); ++f)
    keep[f] = !isDegenerateFace(soup, f, tolerance);
  const std::size_t removed = removeFaces(soup, keep);
  return {"remove_degenerate_faces", removed,
          soup.sourceName + ": removed " + countOf(removed, "degenerate face", "degenerate faces") +
              " (repeated vertex, fewer than 3 vertices or zero area)"};
}

RepairAction removeDuplicateFaces(PolygonSoup& soup) {
  const SoupConnectivity c = analyzeConnectivity(soup);
  std::vector<std::uint8_t> keep(soup.faces.size());
  for (std::size_t f = 0; f < soup.faces.size(); ++f)
    keep[f] = c.duplicateOf[f] == SoupConnectivity::none;
  const std::size_t removed = removeFaces(soup, keep);
  return {"remove_duplicate_faces", removed,
          soup.sourceName + ": removed " + countOf(removed, "duplicate face", "duplicate faces") +
              " (same vertices as an earlier face)"};
}

RepairAction splitEdges(PolygonSoup& soup) {
  SplitNonManifoldEdgesResult split = splitNonManifoldEdges(std::move(soup));
  soup = std::move(split.soup);
  std::string message =
      soup.sourceName + ": split " +
      countOf(split.edgesSplit, "non-manifold edge", "non-manifold edges") +
      " (shared by 3 or more faces), keeping " +
      countOf(split.pairsKept, "consistently oriented pair", "consistently oriented pairs") +
      " of faces glued, detaching " + countOf(split.facesDetached, "other face", "other faces") +
      " and adding " + countOf(split.verticesAdded, "vertex", "vertices");
  if (split.edgesFullyDetached > 0)
    message += "; at " + countOf(split.edgesFullyDetached, "edge", "edges") +
               " the pairs met again around both ends, so all faces there were detached";
  return {"split_non_manifold_edges", split.edgesSplit, message};
}

RepairAction splitNonManifoldVertices(PolygonSoup& soup) {
  const SoupConnectivity c = analyzeConnectivity(soup);
  const std::size_t nv = soup.positions.size();
  std::size_t split = 0;
  for (std::size_t v = 0; v < nv; ++v)
    if (c.fanCount[v] >= 2) ++split;
  // Corners are visited in order, so a fan's first corner (its id) comes before its others: the
  // first fan at a vertex keeps it, every later fan gets a copy.
  std::vector<std::uint8_t> taken(nv, 0);
  std::vector<Index> fanVertex(c.cornerFan.size(), SoupConnectivity::none);
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    if (!c.usable[f]) continue;
    for (std::size_t i = 0; i < soup.faces[f].size(); ++i) {
      const std::size_t corner = c.cornerOffset[f] + i;
      auto& v = soup.faces[f][i];
      const Index fan = c.cornerFan[corner];
      if (fan == corner) {
        const auto old = static_cast<std::size_t>(v);
        if (!taken[old]) {
          taken[old] = 1;
          fanVertex[corner] = static_cast<Index>(old);
        } else {
          fanVertex[corner] = static_cast<Index>(soup.positions.size());
          soup.positions.push_back(soup.positions[old]);
        }
      }
      v = fanVertex[fan];
    }
  }
  const std::size_t added = soup.positions.size() - nv;
  return {"split_non_manifold_vertices", split,
          soup.sourceName + ": split " +
              countOf(split, "non-manifold vertex", "non-manifold vertices") + ", adding " +
              countOf(added, "vertex", "vertices") + " (one per extra fan)"};
}

RepairAction orientConsistently(PolygonSoup& soup) {
  const SoupConnectivity c = analyzeConnectivity(soup);
  std::size_t flipped = 0, nonOrientable = 0;
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    if (!c.usable[f]) continue;
    if (!c.patchOrientable[f]) {
      if (c.facePatch[f] == f) ++nonOrientable;
      continue;
    }
    if (!c.faceFlip[f]) continue;
    std::reverse(soup.faces[f].begin(), soup.faces[f].end());
    if (!soup.cornerUVs.empty()) std::reverse(soup.cornerUVs[f].begin(), soup.cornerUVs[f].end());
    ++flipped;
  }
  std::string message = soup.sourceName + ": flipped " + countOf(flipped, "face", "faces") +
                        " to agree with the first face of their edge-connected patch";
  if (nonOrientable > 0)
    message += "; left " +
               countOf(nonOrientable, "non-orientable patch", "non-orientable patches") + " as " +
               (nonOrientable == 1 ? "it is" : "they are") + " (no orientation is consistent)";
  return {"orient_consistently", flipped, message};
}

RepairAction keepLargestComponent(PolygonSoup& soup) {
  const SoupConnectivity c = analyzeConnectivity(soup);
  const std::size_t nf = soup.faces.size();
  std::vector<std::size_t> size(nf, 0);
  std::size_t components = 0;
  Index largest = SoupConnectivity::none;
  for (std::size_t f = 0; f < nf; ++f)
    if (c.faceComponent[f] != SoupConnectivity::none) ++size[c.faceComponent[f]];
  for (std::size_t f = 0; f < nf; ++f) {
    if (c.faceComponent[f] != f) continue;
    ++components;
    if (largest == SoupConnectivity::none || size[f] > size[largest])
      largest = static_cast<Index>(f);
  }
  std::size_t removed = 0;
  if (largest != SoupConnectivity::none) {
    std::vector<std::uint8_t> keep(nf);
    for (std::size_t f = 0; f < nf; ++f) keep[f] = c.faceComponent[f] == largest;
    removed = removeFaces(soup, keep);
  }
  return {"keep_largest_component", removed,
          soup.sourceName + ": kept the largest of " +
              countOf(components, "component", "components") + " (" +
              countOf(largest == SoupConnectivity::none ? 0 : size[largest], "face", "faces") +
              "), removing " + countOf(removed, "face", "faces")};
}

RepairAction dropUnreferencedVertices(PolygonSoup& soup) {
  const std::size_t nv = soup.positions.size();
  std::vector<std::uint8_t> keep(nv, 0);
  for (const auto& face : soup.faces)
    for (std::int64_t v : face) keep[static_cast<std::size_t>(v)] = 1;
  std::vector<Index> identity(nv);
  std::iota(identity.begin(), identity.end(), Index{0});
  compactVertices(soup, keep, identity);
  const std::size_t dropped = nv - soup.positions.size();
  return {"drop_unreferenced_vertices", dropped,
          soup.sourceName + ": dropped " +
              countOf(dropped, "unreferenced vertex", "unreferenced vertices")};
}

}  // namespace

RepairResult repair(PolygonSoup soup, const RepairOptions& options) {
  MSPLINE_ASSERT(soup.cornerUVs.empty() || soup.cornerUVs.size() == soup.faces.size(),
                 "corner UVs are not parallel to the faces");
  const std::size_t nv = soup.positions.size();
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    MSPLINE_ASSERT(soup.cornerUVs.empty() || soup.cornerUVs[f].size() == soup.faces[f].size(),
                   "corner UVs of face " + std::to_string(f) + " do not match its vertices");
    for (std::int64_t v : soup.faces[f])
      if (v < 0 || static_cast<std::uint64_t>(v) >= nv)
        throw InputError(soup.sourceName + ": face " + std::to_string(f) + " uses vertex " +
                         std::to_string(v) + " but there are " + std::to_string(nv) +
                         " vertices; repair cannot fix out-of-range indices");
  }

  RepairResult result;
  if (options.mergeDuplicateVertices) result.actions.push_back(mergeDuplicateVertices(soup));
  if (options.removeDegenerateFaces)
    result.actions.push_back(removeDegenerateFaces(soup, options.degenerateTolerance));
  if (options.removeDuplicateFaces) result.actions.push_back(removeDuplicateFaces(soup));
  if (options.splitNonManifoldEdges) result.actions.push_back(splitEdges(soup));
  if (options.splitNonManifoldVertices) result.actions.push_back(splitNonManifoldVertices(soup));
  if (options.orientConsistently) result.actions.push_back(orientConsistently(soup));
  if (options.keepLargestComponent) result.actions.push_back(keepLargestComponent(soup));
  if (options.dropUnreferencedVertices) result.actions.push_back(dropUnreferencedVertices(soup));
  result.soup = std::move(soup);
  return result;
}

}  // namespace mspline::structure
