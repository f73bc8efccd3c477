#include "mspline/structure/layout/flat_torus_voronoi.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <unordered_map>

#include <Eigen/Dense>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/layout/planar_delaunay.h"

namespace mspline::structure {

namespace {

// The deck translations m p0 + n p1 of a flat torus, with the layout's Gauss-reduced periods
// (|p0| <= |p1|, |p0 . p1| <= |p0|^2 / 2), and the fundamental parallelogram P = o + [0, 1)^2.
//
// One copy of P around P holds the nearest copy of every site for every point: let x, y lie in
// P, so y - x = a p0 + b p1 with |a|, |b| < 1, and let m p0 + n p1 be the deck translation
// nearest to y - x. The periods make an angle t with |cos t| <= 1/2, so the triangle 0, p0, p1
// (p1 negated if p0 . p1 < 0) is not obtuse and the lattice's covering radius is its
// circumradius, |p1 - p0| / (2 sin t) <= |p1| / (sqrt(2) sin t). That distance is at least
// |b - n| |p1| sin t (the rows of the lattice are |p1| sin t apart), so
// |b - n| <= 1 / (sqrt(2) sin^2 t) <= 0.943 and |n| <= 1. For that n, m is the integer nearest
// to a + c (b - n), c = p0 . p1 / |p0|^2 in [-1/2, 1/2], so |m| <= 1.
struct Lattice {
  Eigen::Vector2d origin;
  /// Columns p0, p1.
  Eigen::Matrix2d basis;
  Eigen::Matrix2d inverse;

  explicit Lattice(const FlatLayout& layout) : origin(layout.fundamentalParallelogram[0]) {
    const Eigen::Vector2d &p0 = layout.periods[0], &p1 = layout.periods[1];
    MSPLINE_ASSERT(p0.squaredNorm() <= p1.squaredNorm() * (1 + 1e-9) &&
                       std::abs(p0.dot(p1)) <= 0.5 * p0.squaredNorm() * (1 + 1e-9),
                   "the layout's periods are not Gauss-reduced");
    basis << p0, p1;
    inverse = basis.inverse();
  }

  /// The deck translation (integer coordinates) that moves P onto the copy of P holding z.
  Eigen::Vector2d cellOf(const Eigen::Vector2d& z) const {
    return (inverse * (z - origin)).array().floor().matrix();
  }

  /// The copy of z in P (up to round-off).
  Eigen::Vector2d reduce(const Eigen::Vector2d& z) const { return z - basis * cellOf(z); }

  /// The deck translation (integer coordinates) that moves `home`, a point of P, nearest to z.
  Eigen::Vector2d nearestCopy(const Eigen::Vector2d& home, const Eigen::Vector2d& z) const {
    const Eigen::Vector2d shift = cellOf(z);
    const Eigen::Vector2d reduced = z - basis * shift;
    Eigen::Vector2d best = Eigen::Vector2d::Zero();
    for (int m = -1; m <= 1; ++m)
      for (int n = -1; n <= 1; ++n)
        if ((home + basis * Eigen::Vector2d(m, n) - reduced).squaredNorm() <
            (home + basis * best - reduced).squaredNorm())
          best = {m, n};
    return best + shift;
  }

  /// The flat distance on the torus between z and the site at `home`.
  double distance(const Eigen::Vector2d& home, const Eigen::Vector2d& z) const {
    return (home + basis * nearestCopy(home, z) - z).norm();
  }
};

Eigen::Vector2d layoutPoint(const FlatLayout& layout, int face, const Eigen::Vector3d& b) {
  return layout.cornerUV.middleRows(3 * face, 3).transpose() * b;
}

// The corner of face(h) at to_vertex(h); from_vertex(h) is the corner before it.
int cornerOf(const TriMesh& mesh, TriMesh::HalfedgeHandle h) {
  int k = 0;
  for (auto g = mesh.halfedge_handle(mesh.face_handle(h)); g != h; g = mesh.next_halfedge_handle(g))
    ++k;
  return k;
}

std::array<int, 2> ordered(int a, int b) {
  return {std::min(a, b), std::max(a, b)};
}

// Chains the segments of one pair of cells: a crossing has two of them (one per face of its
// edge), a junction one, so the chains run between junctions or close.
void chainSegments(const std::vector<int>& pairSegments,
                   const std::vector<std::array<int, 2>>& segmentNodes,
                   const std::vector<std::array<Eigen::Vector3d, 2>>& segmentPoints,
                   const std::array<int, 2>& cells, std::vector<char>& used,
                   std::vector<VoronoiPolyline>& polylines) {
  std::unordered_map<int, std::vector<int>> atNode;
  for (int s : pairSegments)
    for (int node : segmentNodes[s]) atNode[node].push_back(s);
  auto walk = [&](int s, int end) {
    VoronoiPolyline& line = polylines.emplace_back();
    line.cells = cells;
    line.points.push_back(segmentPoints[s][end]);
    const int first = segmentNodes[s][end];
    for (int node = first;;) {
      used[s] = 1;
      end = segmentNodes[s][0] == node ? 1 : 0;
      node = segmentNodes[s][end];
      line.points.push_back(segmentPoints[s][end]);
      const auto& next = atNode[node];
      MSPLINE_ASSERT(next.size() <= 2, "a cell boundary branches");
      const auto it = std::find_if(next.begin(), next.end(), [&](int t) { return !used[t]; });
      if (it == next.end()) {
        line.closed = node == first;
        if (line.closed) line.points.back() = line.points.front();
        return;
      }
      s = *it;
    }
  };
  for (int s : pairSegments)
    for (int end = 0; end < 2; ++end)
      if (!used[s] && atNode[segmentNodes[s][end]].size() == 1) walk(s, end);
  for (int s : pairSegments)
    if (!used[s]) walk(s, 0);
}

}  // namespace

TorusVoronoi flatTorusVoronoi(const TriMesh& mesh, const FlatLayout& layout,
                              const std::vector<SurfacePoint>& sites,
                              const TorusVoronoiOptions& options) {
  if (!layout.hasPeriods)
    throw InputError(
        "voronoi: the layout has no periods (a flat torus is a closed genus-1 surface laid out "
        "without cones)");
  MSPLINE_ASSERT(layout.cornerUV.rows() == static_cast<Eigen::Index>(3 * mesh.n_faces()),
                 "layout does not belong to this mesh");
  if (options.windowRadius < 1) throw InputError("voronoi: the window radius must be at least 1");
  if (sites.empty()) throw InputError("voronoi: no sites");
  for (std::size_t i = 0; i < sites.size(); ++i)
    checkSurfacePoint(mesh, sites[i], "voronoi: site " + std::to_string(i));

  // The planar Voronoi diagram of the sites' copies around P, through its Delaunay dual.
  const Lattice lattice(layout);
  const int siteCount = static_cast<int>(sites.size());
  std::vector<Eigen::Vector2d> home;
  for (const SurfacePoint& site : sites)
    home.push_back(lattice.reduce(layoutPoint(layout, site.face, site.barycentric)));
  const int r = options.windowRadius;
  std::vector<Eigen::Vector2d> copies;  // copy c is a copy of site c % siteCount
  for (int m = -r; m <= r; ++m)
    for (int n = -r; n <= r; ++n)
      for (const Eigen::Vector2d& h : home)
        copies.push_back(h + lattice.basis * Eigen::Vector2d(m, n));
  const PlanarDelaunay delaunay(copies);
  if (!delaunay.duplicates().empty()) {
    const auto [copy, earlier] = delaunay.duplicates().front();
    throw InputError("voronoi: sites " + std::to_string(earlier % siteCount) + " and " +
                     std::to_string(copy % siteCount) + " are the same point of the torus");
  }
  int hint = 0;
  auto siteAt = [&](const Eigen::Vector2d& z) {
    hint = delaunay.nearest(lattice.reduce(z), hint);
    return hint % siteCount;
  };

  TorusVoronoi result;
  result.replicatedSites = static_cast<int>(copies.size());
  std::vector<char> nonEmpty(siteCount, 0);
  result.vertexLabel.assign(mesh.n_vertices(), -1);
  for (auto f : mesh.faces()) {
    const int label = siteAt(layoutPoint(layout, f.idx(), Eigen::Vector3d::Constant(1.0 / 3.0)));
    result.faceLabel.push_back(label);
    result.cells += !nonEmpty[label];
    nonEmpty[label] = 1;
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      if (result.vertexLabel[v.idx()] < 0)
        result.vertexLabel[v.idx()] = siteAt(layout.cornerUV.row(3 * f.idx() + k).transpose());
      ++k;
    }
  }

  // Edges whose ends lie in different cells: where the bisector crosses them, as the fraction
  // from from_vertex to to_vertex of halfedge 0, laid out in its face.
  auto uvAt = [&](int face, int corner) -> Eigen::Vector2d {
    return layout.cornerUV.row(3 * face + corner).transpose();
  };
  std::vector<double> crossing(mesh.n_edges(), -1.0);
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    const int a = result.vertexLabel[mesh.from_vertex_handle(h).idx()];
    const int b = result.vertexLabel[mesh.to_vertex_handle(h).idx()];
    if (a == b) continue;
    const int f = mesh.face_handle(h).idx(), k = cornerOf(mesh, h);
    const Eigen::Vector2d y0 = uvAt(f, (k + 2) % 3), y1 = uvAt(f, k);
    // g(t) = d(x, a)^2 - d(x, b)^2 at x = (1 - t) y0 + t y1 is piecewise linear (the copies'
    // quadratic terms cancel), <= 0 at 0 and >= 0 at 1. Bisect until each site's nearest copy is
    // the same at both ends of the bracket: it is then the same all along (the copy's cell among
    // the site's copies is convex), and g is linear there.
    auto at = [&](double t) { return Eigen::Vector2d((1.0 - t) * y0 + t * y1); };
    auto g = [&](double t, const Eigen::Vector2d& ma, const Eigen::Vector2d& mb) {
      return (at(t) - home[a] - lattice.basis * ma).squaredNorm() -
             (at(t) - home[b] - lattice.basis * mb).squaredNorm();
    };
    double lo = 0.0, hi = 1.0;
    std::array<Eigen::Vector2d, 2> copiesLo = {lattice.nearestCopy(home[a], y0),
                                               lattice.nearestCopy(home[b], y0)};
    std::array<Eigen::Vector2d, 2> copiesHi = {lattice.nearestCopy(home[a], y1),
                                               lattice.nearestCopy(home[b], y1)};
    for (int step = 0; step < 60 && copiesLo != copiesHi; ++step) {
      const double mid = 0.5 * (lo + hi);
      const std::array<Eigen::Vector2d, 2> nearest = {lattice.nearestCopy(home[a], at(mid)),
                                                      lattice.nearestCopy(home[b], at(mid))};
      const bool below = g(mid, nearest[0], nearest[1]) <= 0.0;
      (below ? lo : hi) = mid;
      (below ? copiesLo : copiesHi) = nearest;
    }
    const double gLo = g(lo, copiesLo[0], copiesLo[1]), gHi = g(hi, copiesLo[0], copiesLo[1]);
    const double t =
        gLo == gHi ? 0.5 * (lo + hi) : std::clamp(lo + (hi - lo) * gLo / (gLo - gHi), lo, hi);
    crossing[e.idx()] = t;
    const double da = lattice.distance(home[a], at(t)), db = lattice.distance(home[b], at(t));
    result.maxEquidistanceError =
        std::max(result.maxEquidistanceError, std::abs(da - db) / std::max(da, db));
  }
  auto crossingPoint = [&](TriMesh::HalfedgeHandle h) {
    const auto e = mesh.edge_handle(h);
    const double t = h == mesh.halfedge_handle(e, 0) ? crossing[e.idx()] : 1.0 - crossing[e.idx()];
    const int k = cornerOf(mesh, h);
    SurfacePoint p{mesh.face_handle(h).idx(), Eigen::Vector3d::Zero()};
    p.barycentric[(k + 2) % 3] = 1.0 - t;
    p.barycentric[k] = t;
    return p;
  };

  // Segments inside the faces; nodes name their ends (edge index for a crossing, edges + face
  // for a junction) to chain them.
  const int edgeCount = static_cast<int>(mesh.n_edges());
  std::vector<std::array<int, 2>> segmentNodes;
  std::vector<std::array<Eigen::Vector3d, 2>> segmentPoints;
  auto addSegment = [&](TriMesh::HalfedgeHandle h, const SurfacePoint& end, int endNode) {
    const int a = result.vertexLabel[mesh.from_vertex_handle(h).idx()];
    const int b = result.vertexLabel[mesh.to_vertex_handle(h).idx()];
    const SurfacePoint start = crossingPoint(h);
    result.segments.push_back({ordered(a, b), {start, end}});
    segmentNodes.push_back({mesh.edge_handle(h).idx(), endNode});
    segmentPoints.push_back({surfacePosition(mesh, start), surfacePosition(mesh, end)});
  };
  for (auto f : mesh.faces()) {
    std::array<TriMesh::HalfedgeHandle, 3> h;
    std::array<int, 3> label;
    std::vector<int> crossed;  // k: halfedge k (to corner k) joins two cells
    int k = 0;
    for (auto g : mesh.fh_range(f)) {
      h[k] = g;
      label[k++] = result.vertexLabel[mesh.to_vertex_handle(g).idx()];
    }
    for (k = 0; k < 3; ++k)
      if (label[(k + 2) % 3] != label[k]) crossed.push_back(k);
    if (crossed.size() == 2) {
      addSegment(h[crossed[0]], crossingPoint(h[crossed[1]]),
                 mesh.edge_handle(h[crossed[1]]).idx());
    } else if (crossed.size() == 3) {
      // Three cells meet at the point equidistant to their copies (the circumcenter) when it is
      // inside the face; otherwise the mean of the crossings stands in.
      std::array<Eigen::Vector2d, 3> c, u;
      for (k = 0; k < 3; ++k) {
        u[k] = uvAt(f.idx(), k);
        c[k] = home[label[k]] + lattice.basis * lattice.nearestCopy(home[label[k]], u[k]);
      }
      Eigen::Matrix2d rows;
      rows << (c[1] - c[0]).transpose(), (c[2] - c[0]).transpose();
      const Eigen::Vector2d center =
          c[0] + rows.inverse() *
                     Eigen::Vector2d((c[1] - c[0]).squaredNorm(), (c[2] - c[0]).squaredNorm()) /
                     2.0;
      Eigen::Matrix2d edges;
      edges << u[1] - u[0], u[2] - u[0];
      const Eigen::Vector2d beta = edges.inverse() * (center - u[0]);
      SurfacePoint junction{f.idx(), Eigen::Vector3d(1.0 - beta.sum(), beta.x(), beta.y())};
      if (!junction.barycentric.allFinite() || junction.barycentric.minCoeff() < 0.0) {
        junction.barycentric.setZero();
        for (k = 0; k < 3; ++k) junction.barycentric += crossingPoint(h[k]).barycentric / 3.0;
      }
      for (k = 0; k < 3; ++k) addSegment(h[k], junction, edgeCount + f.idx());
    }
  }

  std::map<std::array<int, 2>, std::vector<int>> byPair;
  for (std::size_t s = 0; s < result.segments.size(); ++s)
    byPair[result.segments[s].cells].push_back(static_cast<int>(s));
  std::vector<char> used(result.segments.size(), 0);
  for (const auto& [cells, pairSegments] : byPair)
    chainSegments(pairSegments, segmentNodes, segmentPoints, cells, used, result.polylines);
  return result;
}

}  // namespace mspline::structure
