#include "mspline/structure/topology/one_vertex_loops.h"

#include <algorithm>
#include <array>
#include <utility>

#include "mspline/structure/core/errors.h"

namespace mspline::structure {

namespace {

using VH = TriMesh::VertexHandle;
using HH = TriMesh::HalfedgeHandle;

/// Where a loop leaves the dual tree: face `face` through its halfedge `halfedge`, which lies on a
/// leftover edge.
struct Port {
  int face = -1;
  int halfedge = -1;
};

/// The dual spanning tree (faces joined across the edges in neither the vertex tree nor the
/// leftover set), rooted at `root`, walked once around (an Euler tour that turns counter-clockwise
/// inside every face).
struct DualTour {
  int root = -1;
  /// Per face, the halfedge of the face by which it is entered from its parent (-1 at the root).
  std::vector<int> entry;
  /// The ports in the order the tour meets them.
  std::vector<Port> ports;
  /// Per face, the range [first, last) of ports met inside its subtree.
  std::vector<int> first, last;
};

/// The halfedges of face f in counter-clockwise order, starting after `after` (or at the face's
/// own first halfedge when `after` is -1).
std::array<HH, 3> faceSlots(const TriMesh& mesh, int f, int after) {
  HH h = after < 0 ? mesh.halfedge_handle(TriMesh::FaceHandle(f))
                   : mesh.next_halfedge_handle(HH(after));
  return {h, mesh.next_halfedge_handle(h), mesh.prev_halfedge_handle(h)};
}

DualTour tourDualTree(const TriMesh& mesh, const std::vector<char>& treeEdge,
                      const std::vector<char>& leftover, int root) {
  DualTour tour;
  const std::size_t nf = mesh.n_faces();
  tour.root = root;
  tour.entry.assign(nf, -1);
  tour.first.assign(nf, 0);
  tour.last.assign(nf, 0);
  std::vector<char> seen(nf, 0);
  // Iterative depth-first walk: (face, next slot to look at).
  std::vector<std::pair<int, int>> stack{{root, 0}};
  seen[std::size_t(root)] = 1;
  tour.first[std::size_t(root)] = 0;
  while (!stack.empty()) {
    auto& [f, slot] = stack.back();
    if (slot == 3) {
      tour.last[std::size_t(f)] = int(tour.ports.size());
      stack.pop_back();
      continue;
    }
    const HH h = faceSlots(mesh, f, tour.entry[std::size_t(f)])[std::size_t(slot++)];
    const int e = mesh.edge_handle(h).idx();
    if (leftover[std::size_t(e)]) {
      tour.ports.push_back({f, h.idx()});
      continue;
    }
    if (treeEdge[std::size_t(e)]) continue;
    const HH o = mesh.opposite_halfedge_handle(h);
    const int g = mesh.face_handle(o).idx();
    if (int(h.idx()) == tour.entry[std::size_t(f)] || seen[std::size_t(g)]) continue;
    seen[std::size_t(g)] = 1;
    tour.entry[std::size_t(g)] = o.idx();
    tour.first[std::size_t(g)] = int(tour.ports.size());
    stack.push_back({g, 0});
  }
  MSPLINE_ASSERT(std::all_of(seen.begin(), seen.end(), [](char s) { return s != 0; }),
                 "the dual tree does not reach every face");
  return tour;
}

/// The face from which the ports' paths are shortest in all: rerooting the dual tree, the summed
/// depth changes by (ports outside a subtree) - (ports inside) when the root moves into it.
int bestRoot(const TriMesh& mesh, const DualTour& tour) {
  const int total = int(tour.ports.size());
  const std::size_t nf = mesh.n_faces();
  std::vector<long> depthSum(nf, 0);
  std::vector<int> order{tour.root};  // parents before children
  std::vector<std::vector<int>> children(nf);
  for (std::size_t f = 0; f < nf; ++f)
    if (tour.entry[f] >= 0)
      children[std::size_t(
                   mesh.face_handle(mesh.opposite_halfedge_handle(HH(tour.entry[f]))).idx())]
          .push_back(int(f));
  for (std::size_t k = 0; k < order.size(); ++k)
    for (int c : children[std::size_t(order[k])]) order.push_back(c);
  // Summed depth (in dual edges) of the ports at the original root.
  long atRoot = 0;
  for (int f : order)
    if (f != tour.root) atRoot += tour.last[std::size_t(f)] - tour.first[std::size_t(f)];
  depthSum[std::size_t(tour.root)] = atRoot;
  int best = tour.root;
  for (int f : order) {
    for (int c : children[std::size_t(f)]) {
      const int inside = tour.last[std::size_t(c)] - tour.first[std::size_t(c)];
      depthSum[std::size_t(c)] = depthSum[std::size_t(f)] + (total - inside) - inside;
      if (depthSum[std::size_t(c)] < depthSum[std::size_t(best)]) best = c;
    }
  }
  return best;
}

/// The polygon `corners` (counter-clockwise, convex, no three corners on a line) split along the
/// chords (pairs of its corners that do not cross), then fanned into triangles.
void triangulatePolygon(std::vector<int> corners, std::vector<std::pair<int, int>> chords,
                        std::vector<std::array<int, 3>>& triangles) {
  while (!chords.empty()) {
    const auto [a, b] = chords.back();
    chords.pop_back();
    const auto ia = std::find(corners.begin(), corners.end(), a);
    const auto ib = std::find(corners.begin(), corners.end(), b);
    MSPLINE_ASSERT(ia != corners.end() && ib != corners.end(), "a chord leaves its piece");
    std::size_t i = std::size_t(ia - corners.begin()), j = std::size_t(ib - corners.begin());
    if (i > j) std::swap(i, j);
    MSPLINE_ASSERT(j > i + 1 && !(i == 0 && j + 1 == corners.size()), "a chord is a side");
    std::vector<int> inner(corners.begin() + long(i), corners.begin() + long(j) + 1);
    std::vector<int> outer(corners.begin() + long(j), corners.end());
    outer.insert(outer.end(), corners.begin(), corners.begin() + long(i) + 1);
    std::vector<std::pair<int, int>> innerChords, outerChords;
    for (const auto& chord : chords) {
      const bool inInner = std::count(inner.begin(), inner.end(), chord.first) &&
                           std::count(inner.begin(), inner.end(), chord.second);
      (inInner ? innerChords : outerChords).push_back(chord);
    }
    triangulatePolygon(std::move(inner), std::move(innerChords), triangles);
    corners = std::move(outer);
    chords = std::move(outerChords);
  }
  for (std::size_t k = 1; k + 1 < corners.size(); ++k)
    triangles.push_back({corners[0], corners[k], corners[k + 1]});
}

}  // namespace

LoopSystem buildOneVertexLoops(GrowingSurface& work, const HomotopyBasis& basis) {
  const TriMesh& mesh = *work.surface;
  const std::size_t nv = mesh.n_vertices(), ne = mesh.n_edges(), nf = mesh.n_faces();
  std::vector<char> treeEdge(ne, 0), leftover(ne, 0);
  for (std::size_t v = 0; v < nv; ++v)
    if (basis.parent[v] >= 0) treeEdge[std::size_t(edgeBetween(mesh, int(v), basis.parent[v]))] = 1;
  for (int e : basis.leftoverEdges) leftover[std::size_t(e)] = 1;

  DualTour tour = tourDualTree(mesh, treeEdge, leftover, 0);
  tour = tourDualTree(mesh, treeEdge, leftover, bestRoot(mesh, tour));
  MSPLINE_ASSERT(tour.ports.size() == 2 * basis.leftoverEdges.size(),
                 "every leftover edge is met once from each side");

  // Points on the edges the paths cross: a dual tree edge carries one point per port beyond it,
  // ordered along the halfedge by which the parent face is left as the tour meets them; a
  // leftover edge carries one point, shared by the two ports of its loop.
  TriMesh out;
  for (std::size_t v = 0; v < nv; ++v) out.add_vertex(mesh.point(VH(int(v))));
  // Per halfedge, the points on its edge in its own direction (empty for most).
  std::vector<std::vector<int>> pointsAlong(mesh.n_halfedges());
  auto placePoints = [&](HH h, int count) {
    const auto from = mesh.point(mesh.from_vertex_handle(h)),
               to = mesh.point(mesh.to_vertex_handle(h));
    std::vector<int>& along = pointsAlong[std::size_t(h.idx())];
    for (int k = 0; k < count; ++k) {
      const double t = double(k + 1) / double(count + 1);
      along.push_back(out.add_vertex((1.0 - t) * from + t * to).idx());
    }
    const HH o = mesh.opposite_halfedge_handle(h);
    pointsAlong[std::size_t(o.idx())].assign(along.rbegin(), along.rend());
  };
  for (std::size_t f = 0; f < nf; ++f) {
    if (tour.entry[f] < 0) continue;
    const HH down = mesh.opposite_halfedge_handle(HH(tour.entry[f]));
    placePoints(down, tour.last[f] - tour.first[f]);
  }
  for (int e : basis.leftoverEdges) placePoints(mesh.halfedge_handle(TriMesh::EdgeHandle(e), 0), 1);
  const int center = int(out.n_vertices());
  {
    OpenMesh::Vec3d centroid(0.0, 0.0, 0.0);
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(tour.root))) centroid += mesh.point(v);
    out.add_vertex(centroid / 3.0);
  }
  work.edgeSplits += int(out.n_vertices() - nv - 1);

  // Each port's path, from the center down the dual tree: the point it takes on every edge is its
  // rank among the ports beyond that edge.
  std::vector<std::vector<int>> paths(tour.ports.size());
  std::vector<std::vector<std::pair<int, int>>> chordsIn(nf);
  for (std::size_t p = 0; p < tour.ports.size(); ++p) {
    std::vector<int> faces;
    for (int f = tour.ports[p].face; f != tour.root;
         f = mesh.face_handle(mesh.opposite_halfedge_handle(HH(tour.entry[std::size_t(f)]))).idx())
      faces.push_back(f);
    std::reverse(faces.begin(), faces.end());
    std::vector<int>& path = paths[p];
    path.push_back(center);
    for (int f : faces) {
      const HH down = mesh.opposite_halfedge_handle(HH(tour.entry[std::size_t(f)]));
      path.push_back(
          pointsAlong[std::size_t(down.idx())][p - std::size_t(tour.first[std::size_t(f)])]);
    }
    path.push_back(pointsAlong[std::size_t(tour.ports[p].halfedge)].front());
    // The piece of the path inside each face it crosses.
    chordsIn[std::size_t(tour.root)].push_back({path[0], path[1]});
    for (std::size_t k = 0; k < faces.size(); ++k)
      chordsIn[std::size_t(faces[k])].push_back({path[k + 1], path[k + 2]});
  }

  std::vector<std::array<int, 3>> triangles;
  for (std::size_t f = 0; f < nf; ++f) {
    std::vector<int> polygon;
    for (const HH h : faceSlots(mesh, int(f), -1)) {
      polygon.push_back(mesh.from_vertex_handle(h).idx());
      const auto& along = pointsAlong[std::size_t(h.idx())];
      polygon.insert(polygon.end(), along.begin(), along.end());
    }
    if (int(f) != tour.root) {
      triangulatePolygon(std::move(polygon), std::move(chordsIn[f]), triangles);
      continue;
    }
    // The root: sectors between consecutive spokes out of the center (every point on its sides is
    // a spoke's end).
    std::vector<std::size_t> spokes;
    for (std::size_t k = 0; k < polygon.size(); ++k)
      if (polygon[k] >= int(nv)) spokes.push_back(k);
    MSPLINE_ASSERT(!spokes.empty(), "no loop leaves the root face");
    for (std::size_t s = 0; s < spokes.size(); ++s) {
      std::vector<int> sector{center};
      for (std::size_t k = spokes[s];; k = (k + 1) % polygon.size()) {
        sector.push_back(polygon[k]);
        if (k == spokes[(s + 1) % spokes.size()] && sector.size() > 2) break;
      }
      triangulatePolygon(std::move(sector), {}, triangles);
    }
  }
  for (const auto& t : triangles) {
    const auto face = out.add_face(VH(t[0]), VH(t[1]), VH(t[2]));
    MSPLINE_ASSERT(face.is_valid(), "the loops' triangulation is not a manifold");
  }
  MSPLINE_ASSERT(out.n_faces() == triangles.size(), "the loops' triangulation lost a face");

  // Loop i: out along the path to one side of its leftover edge, back along the other.
  LoopSystem system;
  system.center = center;
  std::vector<int> portOfHalfedge(mesh.n_halfedges(), -1);
  for (std::size_t p = 0; p < tour.ports.size(); ++p)
    portOfHalfedge[std::size_t(tour.ports[p].halfedge)] = int(p);
  for (int e : basis.leftoverEdges) {
    const HH h = mesh.halfedge_handle(TriMesh::EdgeHandle(e), 0);
    const int a = portOfHalfedge[std::size_t(h.idx())];
    const int b = portOfHalfedge[std::size_t(mesh.opposite_halfedge_handle(h).idx())];
    MSPLINE_ASSERT(a >= 0 && b >= 0, "a leftover edge is not met from both sides");
    std::vector<int> loop = paths[std::size_t(a)];
    loop.insert(loop.end(), paths[std::size_t(b)].rbegin() + 1, paths[std::size_t(b)].rend());
    system.loops.push_back(std::move(loop));
  }
  work.surface = std::make_unique<TriMesh>(std::move(out));
  checkGrowth(work);
  return system;
}

}  // namespace mspline::structure
