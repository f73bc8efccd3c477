#include "mspline/structure/layout/coarse_triangulation.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <random>
#include <string>
#include <utility>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/surface_point.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "mspline/structure/topology/topology.h"

namespace mspline::structure {

namespace {

// A flip that lowers a vertex's degree must leave the quadrilateral's angles at the ends of the
// old diagonal this far below pi (radians): nearly flat quadrilaterals give needles. A vertex
// whose angle between two neighbours is within this of pi on both sides lies between them.
constexpr double kConvexityMargin = 1e-8;
// An edge is flipped to Delaunay when cos(alpha) + cos(beta) < -this (alpha + beta > pi).
constexpr double kDelaunayTolerance = 1e-12;
// Narrower wedges are not developed further (radians): they are rays grazing a vertex.
constexpr double kMinWedge = 1e-14;
// A direction this close to a copy's wedge (radians) is seen through it: points on its rays.
constexpr double kDirectionTolerance = 1e-9;
// An origin with a barycentric coordinate this close to 1 is the vertex of that corner.
constexpr double kCornerTolerance = 1e-12;

using Vector2 = Eigen::Vector2d;
using Corners = std::array<Vector2, 3>;

double cross(const Vector2& a, const Vector2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// The third corner p2 of the counter-clockwise triangle (p0, p1, p2) with side lengths
// |p0 p1| = l01, |p0 p2| = l02, |p1 p2| = l12.
Vector2 apex(const Vector2& p0, const Vector2& p1, double l01, double l02, double l12) {
  const Vector2 u = (p1 - p0).normalized();
  const double x = (l02 * l02 - l12 * l12 + l01 * l01) / (2.0 * l01);
  const double y = fourTimesArea(l01, l02, l12) / (2.0 * l01);
  return p0 + x * u + y * Vector2(-u.y(), u.x());
}

Eigen::Vector3d barycentricIn(const Vector2& x, const Corners& p) {
  const double area = cross(p[1] - p[0], p[2] - p[0]);
  Eigen::Vector3d b;
  for (int k = 0; k < 3; ++k) b[k] = cross(p[(k + 1) % 3] - x, p[(k + 2) % 3] - x) / area;
  return b;
}

Vector2 pointAt(const Corners& p, const Eigen::Vector3d& b) {
  return b[0] * p[0] + b[1] * p[1] + b[2] * p[2];
}

// A removed fine vertex and where it lies in the face whose list holds it (corner k = slot k).
struct TrackedPoint {
  int vertex;
  Eigen::Vector3d barycentric;
};

// A face being formed, with its corners laid out, and the points that go into it.
struct Destination {
  Corners corners;
  std::vector<TrackedPoint> points;
};

// Sends the points of a face laid out with `corners` to whichever destination holds them best
// (largest least barycentric coordinate). The coordinates change by the linear map that takes
// the face's corners to their coordinates in the destination: exact unit vectors for shared
// corners, so only the other corners' rounding enters.
void distribute(const std::vector<TrackedPoint>& points, const Corners& corners,
                std::array<Destination, 2>& into) {
  Eigen::Matrix3d to0, to1;
  for (int k = 0; k < 3; ++k) {
    to0.col(k) = barycentricIn(corners[k], into[0].corners);
    to1.col(k) = barycentricIn(corners[k], into[1].corners);
  }
  for (const TrackedPoint& point : points) {
    const Eigen::Vector3d a = to0 * point.barycentric, b = to1 * point.barycentric;
    if (a.minCoeff() >= b.minCoeff())
      into[0].points.push_back({point.vertex, a});
    else
      into[1].points.push_back({point.vertex, b});
  }
}

// The intrinsic triangulation being coarsened, as a corner table: slot h = 3 f + k is corner k of
// face f (at vertex vert_[h]) and side k, from that corner to the next (length len_[h], the same
// side seen from the neighbouring face is twin_[h]). Faces are counter-clockwise.
class Coarsening {
 public:
  Coarsening(const TriMesh& surface, const Eigen::VectorXd& lengths, bool delaunay)
      : delaunay_(delaunay) {
    const std::size_t slots = 3 * surface.n_faces();
    vert_.assign(slots, -1);
    twin_.assign(slots, -1);
    len_.assign(slots, 0.0);
    std::vector<int> sideSlot(surface.n_halfedges(), -1);
    for (const auto f : surface.faces()) {
      auto h = surface.halfedge_handle(f);
      for (int k = 0; k < 3; ++k, h = surface.next_halfedge_handle(h)) {
        // Corner k is the to-vertex of the k-th halfedge (fv_range order); side k is the next one.
        const auto side = surface.next_halfedge_handle(h);
        const int s = 3 * f.idx() + k;
        vert_[s] = surface.to_vertex_handle(h).idx();
        len_[s] = lengths[surface.edge_handle(side).idx()];
        sideSlot[side.idx()] = s;
      }
    }
    for (const auto h : surface.halfedges())
      twin_[sideSlot[h.idx()]] = sideSlot[surface.opposite_halfedge_handle(h).idx()];
    alive_.assign(surface.n_faces(), 1);
    points_.resize(surface.n_faces());
    corner_.assign(surface.n_vertices(), -1);
    for (std::size_t s = 0; s < slots; ++s) corner_[vert_[s]] = int(s);
    flipLimit_ = 100L * long(slots + 1);
  }

  // Lawson flips of every edge that is not Delaunay.
  void flipToDelaunay() {
    for (int h = 0; h < int(vert_.size()); ++h)
      if (alive_[h / 3]) pending_.push_back(h);
    restoreDelaunay();
  }

  // Flips edges at the flat vertex v down to degree 3 and merges its three triangles, or, when it
  // is stuck at degree 4 on a straight line, merges its four into two. False (after whatever flips
  // it made) when neither works. With delaunay_, the Delaunay property is restored around.
  bool remove(int v) {
    bool removed = false;
    for (;;) {
      const int d = degree(v);
      if (d == 3) {
        removed = merge(v);
        break;
      }
      const int h = d > 3 ? reductionFlip(v) : -1;
      if (h < 0) {
        removed = d == 4 && mergeStraight(v);
        break;
      }
      flip(h);
      ++removalFlips_;
    }
    restoreDelaunay();
    return removed;
  }

  CoarseTriangulation result(const std::vector<int>& isCone) const;

 private:
  int next(int h) const { return h - h % 3 + (h + 1) % 3; }
  int prev(int h) const { return h - h % 3 + (h + 2) % 3; }
  // The corner after h counter-clockwise around its vertex.
  int ccw(int h) const { return twin_[prev(h)]; }
  // The angle at corner h.
  double angle(int h) const { return triangleAngles(len_[next(h)], len_[h], len_[prev(h)])[0]; }
  double cosineOpposite(int h) const {
    const double a = len_[h], b = len_[next(h)], c = len_[prev(h)];
    return (b * b + c * c - a * a) / (2.0 * b * c);
  }

  int degree(int v) const {
    int d = 0;
    const int start = corner_[v];
    int h = start;
    do {
      h = ccw(h);
      ++d;
    } while (h != start);
    return d;
  }

  // The quadrilateral of side h (face (i, j, k) from slot h) and its twin (face (j, i, l)) laid
  // out with i at the origin and j on the positive x axis: positions of i, j, k, l.
  std::array<Vector2, 4> quad(int h) const {
    const int t = twin_[h];
    const double d = len_[h];
    const Vector2 i(0.0, 0.0), j(d, 0.0);
    return {i, j, apex(i, j, d, len_[prev(h)], len_[next(h)]),
            apex(j, i, d, len_[prev(t)], len_[next(t)])};
  }

  // Of the flips of edges at v that lower its degree and keep every triangle proper, the one
  // whose ear (the triangle the flip cuts off v's star) has the circumcircle of least power with
  // respect to v (Devillers); -1 when there is none.
  int reductionFlip(int v) const {
    int best = -1;
    double bestPower = std::numeric_limits<double>::infinity();
    const int start = corner_[v];
    int h = start;
    do {
      const int t = twin_[h];
      // The new diagonal must not end at v. (A loop at v may flip: v loses two corners.)
      const bool proper = t / 3 != h / 3 && vert_[prev(h)] != v && vert_[prev(t)] != v;
      if (proper && angle(h) + angle(next(t)) < kPi - kConvexityMargin &&
          angle(next(h)) + angle(t) < kPi - kConvexityMargin) {
        // v = q[0] at the origin; the ear is (k, j, l).
        const auto q = quad(h);
        const Vector2 b = q[2] - q[1], d = q[3] - q[1];
        const double det = 2.0 * cross(b, d);
        const Vector2 center(d.y() * b.squaredNorm() - b.y() * d.squaredNorm(),
                             b.x() * d.squaredNorm() - d.x() * b.squaredNorm());
        const double power = q[1].squaredNorm() + 2.0 * q[1].dot(center / det);
        if (power < bestPower) {
          bestPower = power;
          best = h;
        }
      }
      h = ccw(h);
    } while (h != start);
    return best;
  }

  // Euclidean flip of side h: faces (i, j, k) and (j, i, l) become (l, k, i) and (k, l, j) in the
  // same slots, the new diagonal's length from the quadrilateral laid out in the plane, and the
  // points of both faces are re-expressed in whichever new face holds them.
  void flip(int h) {
    const int t = twin_[h];
    const int n = next(h), p = prev(h), tn = next(t), tp = prev(t);
    const int vi = vert_[h], vj = vert_[n], vk = vert_[p], vl = vert_[tp];
    const auto q = quad(h);
    Corners oldA, oldB, newA, newB;
    oldA[h % 3] = q[0], oldA[n % 3] = q[1], oldA[p % 3] = q[2];
    oldB[t % 3] = q[1], oldB[tn % 3] = q[0], oldB[tp % 3] = q[3];
    newA[h % 3] = q[3], newA[n % 3] = q[2], newA[p % 3] = q[0];
    newB[t % 3] = q[2], newB[tn % 3] = q[3], newB[tp % 3] = q[1];
    std::array<Destination, 2> into = {Destination{newA, {}}, Destination{newB, {}}};
    distribute(points_[h / 3], oldA, into);
    distribute(points_[t / 3], oldB, into);
    points_[h / 3] = std::move(into[0].points);
    points_[t / 3] = std::move(into[1].points);

    // The quadrilateral's sides move round by one slot: k -> i to n, i -> l to p, l -> j to tn,
    // j -> k to tp.
    const int from[4] = {p, tn, tp, n};
    const int to[4] = {n, p, tn, tp};
    move(from, to, 4);
    vert_[h] = vl, vert_[n] = vk, vert_[p] = vi;
    vert_[t] = vk, vert_[tn] = vl, vert_[tp] = vj;
    len_[h] = len_[t] = (q[2] - q[3]).norm();
    corner_[vi] = p, corner_[vj] = tp, corner_[vk] = n, corner_[vl] = h;
    if (delaunay_)
      for (int s : {h, n, p, tn, tp}) pending_.push_back(s);
  }

  // Moves the sides (length and twin) in slots from[m] to slots to[m]; a twin among the moved
  // slots moves with them (loops and double edges of a Delta-complex).
  void move(const int* from, const int* to, int count) {
    std::array<double, 4> length;
    std::array<int, 4> twin;
    for (int m = 0; m < count; ++m) length[m] = len_[from[m]], twin[m] = twin_[from[m]];
    const auto moved = [&](int s) {
      for (int m = 0; m < count; ++m)
        if (from[m] == s) return to[m];
      return s;
    };
    for (int m = 0; m < count; ++m) {
      len_[to[m]] = length[m];
      twin_[to[m]] = moved(twin[m]);
      twin_[twin_[to[m]]] = to[m];
    }
  }

  // Merges the three triangles (v, x, y), (v, y, z), (v, z, x) around v into (x, y, z) in the
  // first one's slots. v and the points of the three faces are placed by the areas of the three
  // triangles (a flat vertex lies inside the triangle of its neighbours).
  bool merge(int v) {
    const int c0 = corner_[v], c1 = ccw(c0), c2 = ccw(c1);
    const int f0 = c0 / 3, f1 = c1 / 3, f2 = c2 / 3;
    const int o0 = next(c0), o1 = next(c1), o2 = next(c2);
    if (f0 == f1 || f1 == f2 || f2 == f0 || vert_[o0] == v || vert_[o1] == v || vert_[o2] == v)
      return false;
    const int x = vert_[o0], y = vert_[o1], z = vert_[o2];
    const auto area = [&](int c) { return fourTimesArea(len_[c], len_[next(c)], len_[prev(c)]); };
    const double a0 = area(c0), a1 = area(c1), a2 = area(c2), total = a0 + a1 + a2;
    // The new face: slot c0 is corner x, o0 corner y, prev(c0) corner z.
    const int ix = c0 % 3, iy = o0 % 3, iz = prev(c0) % 3;
    Eigen::Vector3d placed;
    placed[ix] = a1 / total, placed[iy] = a2 / total, placed[iz] = a0 / total;
    std::vector<TrackedPoint> inside = {{v, placed}};
    // Corner c of a merged face is v; its other corners become new corners first and second.
    const auto reexpress = [&](int c, int first, int second) {
      for (const TrackedPoint& point : points_[c / 3]) {
        const Eigen::Vector3d& b = point.barycentric;
        Eigen::Vector3d moved = b[c % 3] * placed;
        moved[first] += b[next(c) % 3];
        moved[second] += b[prev(c) % 3];
        inside.push_back({point.vertex, moved});
      }
      points_[c / 3].clear();
    };
    reexpress(c0, ix, iy);
    reexpress(c1, iy, iz);
    reexpress(c2, iz, ix);
    points_[f0] = std::move(inside);

    const int from[3] = {o0, o1, o2};
    const int to[3] = {c0, o0, prev(c0)};
    move(from, to, 3);
    vert_[c0] = x, vert_[o0] = y, vert_[prev(c0)] = z;
    alive_[f1] = alive_[f2] = 0;
    corner_[v] = -1;
    corner_[x] = c0, corner_[y] = o0, corner_[z] = prev(c0);
    if (delaunay_)
      for (int s : {c0, o0, prev(c0)}) pending_.push_back(s);
    return true;
  }

  // Removes a vertex v of degree 4 that lies on the straight segment between two opposite
  // neighbours a and b (within kConvexityMargin; no flip may then lower its degree): its four
  // triangles (v, a, c), (v, c, b), (v, b, d), (v, d, a) become (a, c, b) and (b, d, a), laid out
  // together so that v and the points go to the side of ab they lie on.
  bool mergeStraight(int v) {
    std::array<int, 4> corner;
    corner[0] = corner_[v];
    for (int m = 1; m < 4; ++m) corner[m] = ccw(corner[m - 1]);
    // Rotate so that the angle at v from a (corner 0's neighbour) to b is the straight one.
    const double through0 = angle(corner[0]) + angle(corner[1]);
    const double through1 = angle(corner[1]) + angle(corner[2]);
    if (std::abs(through1 - kPi) < std::abs(through0 - kPi))
      std::rotate(corner.begin(), corner.begin() + 1, corner.end());
    const auto [c0, c1, c2, c3] = corner;
    const int o0 = next(c0), o1 = next(c1), o2 = next(c2), o3 = next(c3);
    const std::array<int, 4> face = {c0 / 3, c1 / 3, c2 / 3, c3 / 3};
    for (int m = 0; m < 4; ++m)
      for (int n = m + 1; n < 4; ++n)
        if (face[m] == face[n]) return false;
    for (int o : {o0, o1, o2, o3})
      if (vert_[o] == v) return false;
    const double straight = angle(c0) + angle(c1);
    // c and d must not lie on the line ab either.
    if (std::abs(straight - kPi) > kConvexityMargin ||
        angle(prev(c0)) + angle(o1) >= kPi - kConvexityMargin ||
        angle(prev(c2)) + angle(o3) >= kPi - kConvexityMargin)
      return false;
    const int a = vert_[o0], c = vert_[o1], b = vert_[o2], d = vert_[o3];
    // Laid out around v by its angles, which place v off the line ab exactly as far as it is.
    const auto polar = [](double r, double phi) {
      return Vector2(r * std::cos(phi), r * std::sin(phi));
    };
    const Vector2 pv(0.0, 0.0), pa(len_[c0], 0.0);
    const Vector2 pc = polar(len_[c1], angle(c0)), pb = polar(len_[c2], straight);
    const Vector2 pd = polar(len_[c3], -angle(c3));
    const double ab = (pb - pa).norm();
    Corners old0, old1, old2, old3, newF, newG;
    old0[c0 % 3] = pv, old0[o0 % 3] = pa, old0[prev(c0) % 3] = pc;
    old1[c1 % 3] = pv, old1[o1 % 3] = pc, old1[prev(c1) % 3] = pb;
    old2[c2 % 3] = pv, old2[o2 % 3] = pb, old2[prev(c2) % 3] = pd;
    old3[c3 % 3] = pv, old3[o3 % 3] = pd, old3[prev(c3) % 3] = pa;
    newF[c0 % 3] = pa, newF[o0 % 3] = pc, newF[prev(c0) % 3] = pb;
    newG[c2 % 3] = pb, newG[o2 % 3] = pd, newG[prev(c2) % 3] = pa;
    std::array<Destination, 2> into = {Destination{newF, {}}, Destination{newG, {}}};
    distribute({{v, Eigen::Vector3d::Unit(c0 % 3)}}, old0, into);
    distribute(points_[face[0]], old0, into);
    distribute(points_[face[1]], old1, into);
    distribute(points_[face[2]], old2, into);
    distribute(points_[face[3]], old3, into);
    for (int f : face) points_[f].clear();
    points_[face[0]] = std::move(into[0].points);
    points_[face[2]] = std::move(into[1].points);

    const int from[4] = {o0, o1, o2, o3};
    const int to[4] = {c0, o0, c2, o2};
    move(from, to, 4);
    vert_[c0] = a, vert_[o0] = c, vert_[prev(c0)] = b;
    vert_[c2] = b, vert_[o2] = d, vert_[prev(c2)] = a;
    twin_[prev(c0)] = prev(c2), twin_[prev(c2)] = prev(c0);
    len_[prev(c0)] = len_[prev(c2)] = ab;
    alive_[face[1]] = alive_[face[3]] = 0;
    corner_[v] = -1;
    corner_[a] = c0, corner_[c] = o0, corner_[b] = prev(c0), corner_[d] = o2;
    if (delaunay_)
      for (int s : {c0, o0, prev(c0), c2, o2, prev(c2)}) pending_.push_back(s);
    return true;
  }

  void restoreDelaunay() {
    while (!pending_.empty()) {
      const int h = pending_.back();
      pending_.pop_back();
      const int t = twin_[h];
      if (!alive_[h / 3] || t / 3 == h / 3) continue;
      if (cosineOpposite(h) + cosineOpposite(t) >= -kDelaunayTolerance) continue;
      if (++delaunayFlips_ > flipLimit_)
        throw InternalError("coarsening: Delaunay flipping did not terminate after " +
                            std::to_string(flipLimit_) + " flips");
      flip(h);
    }
  }

  bool delaunay_;
  std::vector<int> vert_, twin_;
  std::vector<double> len_;
  std::vector<char> alive_;
  // A corner at every vertex still present, -1 once removed.
  std::vector<int> corner_;
  std::vector<std::vector<TrackedPoint>> points_;
  // Slots whose side may have stopped being Delaunay.
  std::vector<int> pending_;
  long removalFlips_ = 0, delaunayFlips_ = 0, flipLimit_ = 0;
};

CoarseTriangulation Coarsening::result(const std::vector<int>& isCone) const {
  CoarseTriangulation coarse;
  const int fineCount = int(corner_.size());
  coarse.coarseVertex.assign(std::size_t(fineCount), -1);
  for (int v = 0; v < fineCount; ++v) {
    if (corner_[v] < 0) continue;
    coarse.coarseVertex[v] = int(coarse.vertices.size());
    coarse.vertices.push_back(v);
    coarse.isCone.push_back(char(isCone[v]));
  }
  std::vector<int> newFace(alive_.size(), -1);
  int faces = 0;
  for (std::size_t f = 0; f < alive_.size(); ++f)
    if (alive_[f]) newFace[f] = faces++;
  coarse.faces.resize(std::size_t(faces));
  coarse.sideLengths.resize(std::size_t(faces));
  coarse.neighbour.resize(std::size_t(faces));
  coarse.neighbourSide.resize(std::size_t(faces));
  coarse.fineVertices.resize(std::size_t(fineCount));
  for (std::size_t f = 0; f < alive_.size(); ++f) {
    if (!alive_[f]) continue;
    const int g = newFace[f];
    for (int k = 0; k < 3; ++k) {
      const int h = 3 * int(f) + k;
      coarse.faces[g][k] = coarse.coarseVertex[vert_[h]];
      coarse.sideLengths[g][k] = len_[h];
      coarse.neighbour[g][k] = newFace[twin_[h] / 3];
      coarse.neighbourSide[g][k] = twin_[h] % 3;
    }
    for (const TrackedPoint& point : points_[f])
      coarse.fineVertices[point.vertex] = {g, point.barycentric};
  }
  for (int v : coarse.vertices)
    coarse.fineVertices[v] = {newFace[corner_[v] / 3], Eigen::Vector3d::Unit(corner_[v] % 3)};
  coarse.removedVertices = fineCount - int(coarse.vertices.size());
  coarse.curvature.assign(coarse.vertices.size(), 2.0 * kPi);
  for (int f = 0; f < faces; ++f) {
    const auto& l = coarse.sideLengths[f];
    const auto angles = triangleAngles(l[0], l[1], l[2]);
    // The angle opposite side k is at corner k + 2.
    for (int k = 0; k < 3; ++k) coarse.curvature[coarse.faces[f][(k + 2) % 3]] -= angles[k];
  }
  coarse.removalFlips = removalFlips_;
  coarse.delaunayFlips = delaunayFlips_;
  return coarse;
}

// Every cone, then farthest-point samples (Dijkstra on the flat edge lengths, seeded from the
// cones or from vertex 0; the farthest in units of the local spacing 1 / sqrt(density)) until
// `target` vertices are kept.
std::vector<char> sampleVertices(const TriMesh& surface, const Eigen::VectorXd& lengths,
                                 const std::vector<int>& isCone, const std::vector<int>& extra,
                                 int target, const Eigen::VectorXd& density) {
  const int n = int(surface.n_vertices());
  std::vector<char> kept(std::size_t(n), 0);
  std::vector<double> distance(std::size_t(n), std::numeric_limits<double>::infinity());
  // 1 / spacing; exactly 1 without a density, so that uniform sampling is unchanged.
  const Eigen::VectorXd scale =
      density.size() > 0 ? Eigen::VectorXd(density.cwiseSqrt()) : Eigen::VectorXd::Ones(n);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> near;
  // Lazy max-heap of scaled distances: an entry is current while it equals distance[v] scale[v].
  std::priority_queue<Entry> far;
  int count = 0;
  const auto keep = [&](int v) {
    kept[v] = 1;
    ++count;
    distance[v] = 0.0;
    near.push({0.0, v});
  };
  for (int v = 0; v < n; ++v)
    if (isCone[v] || std::find(extra.begin(), extra.end(), v) != extra.end()) keep(v);
  if (count == 0) keep(0);
  for (;;) {
    while (!near.empty()) {
      const auto [d, v] = near.top();
      near.pop();
      if (d > distance[v]) continue;
      for (const auto h : surface.voh_range(TriMesh::VertexHandle(v))) {
        const int w = surface.to_vertex_handle(h).idx();
        const double dw = d + lengths[surface.edge_handle(h).idx()];
        if (dw >= distance[w]) continue;
        distance[w] = dw;
        near.push({dw, w});
        far.push({dw * scale[w], w});
      }
    }
    if (count >= std::min(target, n)) return kept;
    while (kept[far.top().second] ||
           far.top().first != distance[far.top().second] * scale[far.top().second])
      far.pop();
    keep(far.top().second);
  }
}

// The neighbour of `face` across `side`, laid out on the other side of that side in the plane of
// `corners` (face's corners).
DevelopedFace unfoldAcross(const CoarseTriangulation& coarse, int face, const Corners& corners,
                           int side) {
  const int g = coarse.neighbour[face][side], m = coarse.neighbourSide[face][side];
  const auto& l = coarse.sideLengths[g];
  DevelopedFace next;
  next.face = g;
  next.corners[m] = corners[(side + 1) % 3];
  next.corners[(m + 1) % 3] = corners[side];
  next.corners[(m + 2) % 3] =
      apex(next.corners[m], next.corners[(m + 1) % 3], l[m], l[(m + 2) % 3], l[(m + 1) % 3]);
  return next;
}

double distanceToSegment(const Vector2& a, const Vector2& b) {
  const Vector2 d = b - a;
  const double t = std::clamp(-a.dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (a + t * d).norm();
}

// Whether the ray from the origin in direction `phi` (radians) passes through `copy`'s wedge.
bool seenThrough(const DevelopedFace& copy, double phi) {
  const double from = copy.fromAngle - kDirectionTolerance;
  phi += 2.0 * kPi * std::ceil((from - phi) / (2.0 * kPi));
  return phi <= copy.toAngle + kDirectionTolerance;
}

// The fine edge's length measured on the coarse triangulation between its endpoints' locations,
// relative to its flat length (infinite when no straight segment of at most 1.5 lengths is found).
double trackingError(const CoarseTriangulation& coarse, int u, int w, double length) {
  // Prefer an origin inside a face: its development starts from one copy.
  if (coarse.coarseVertex[u] >= 0) std::swap(u, w);
  const auto copies = developFromPoint(coarse, coarse.fineVertices[u], 1.5 * length);
  double error = std::numeric_limits<double>::infinity();
  for (const Vector2& x : sightingsOfFineVertex(coarse, copies, w))
    error = std::min(error, std::abs(x.norm() - length) / length);
  return error;
}

void checkInput(const TriMesh& surface, const Eigen::VectorXd& flatLengths,
                const CoarseningOptions& options) {
  if (options.targetVertices < 1)
    throw InputError("coarsening: targetVertices must be at least 1, not " +
                     std::to_string(options.targetVertices));
  if (!(options.coneTolerance >= 0.0)) throw InputError("coarsening: coneTolerance must be >= 0");
  if (surface.n_faces() == 0) throw InputError("coarsening: the surface has no faces");
  if (flatLengths.size() != Eigen::Index(surface.n_edges()))
    throw InputError("coarsening: " + std::to_string(flatLengths.size()) + " edge lengths for " +
                     std::to_string(surface.n_edges()) + " edges");
  if (!flatLengths.allFinite() || (flatLengths.array() <= 0.0).any())
    throw InputError("coarsening: edge lengths must be finite and positive");
  if (options.density.size() != 0 && options.density.size() != Eigen::Index(surface.n_vertices()))
    throw InputError("coarsening: " + std::to_string(options.density.size()) + " densities for " +
                     std::to_string(surface.n_vertices()) + " vertices");
  if (!options.density.allFinite() || (options.density.array() <= 0.0).any())
    throw InputError("coarsening: densities must be finite and positive");
  const TopologyReport topology = analyzeTopology(surface);
  if (!topology.closed)
    throw TopologyError("coarsening: the surface has " + std::to_string(topology.boundaryLoops) +
                        " boundary loops; only closed surfaces can be coarsened for now");
  if (topology.components != 1)
    throw TopologyError("coarsening: the surface has " + std::to_string(topology.components) +
                        " components; it must be connected");
  for (const auto f : surface.faces()) {
    std::array<double, 3> l;
    int k = 0;
    for (const auto e : surface.fe_range(f)) l[k++] = flatLengths[e.idx()];
    if (!satisfiesTriangleInequality(l[0], l[1], l[2]))
      throw InputError("coarsening: the lengths of face " + std::to_string(f.idx()) +
                       " violate the triangle inequality");
  }
}

CoarseTriangulation coarsenKeeping(const TriMesh& surface, const Eigen::VectorXd& flatLengths,
                                   const CoarseningOptions& options,
                                   const std::vector<int>& extra) {
  const Eigen::VectorXd fineCurvature = vertexCurvatures(surface, flatLengths);
  const int n = int(surface.n_vertices());
  std::vector<int> isCone(std::size_t(n), 0);
  for (int v = 0; v < n; ++v) isCone[v] = std::abs(fineCurvature[v]) > options.coneTolerance;
  const std::vector<char> kept =
      sampleVertices(surface, flatLengths, isCone, extra, options.targetVertices, options.density);

  Coarsening coarsening(surface, flatLengths, options.delaunay);
  if (options.delaunay) coarsening.flipToDelaunay();
  std::vector<int> order;
  for (int v = 0; v < n; ++v)
    if (!kept[v]) order.push_back(v);
  std::shuffle(order.begin(), order.end(), std::mt19937(options.seed));
  // Vertices that fail are retried while others go: their neighbourhoods change.
  for (;;) {
    std::vector<int> failed;
    for (int v : order)
      if (!coarsening.remove(v)) failed.push_back(v);
    const bool progress = failed.size() < order.size();
    order = std::move(failed);
    if (order.empty() || !progress) break;
  }

  CoarseTriangulation coarse = coarsening.result(isCone);
  std::sort(order.begin(), order.end());
  coarse.unremovedVertices = std::move(order);
  coarse.complete = coarse.unremovedVertices.empty();
  coarse.fineLengths = flatLengths;
  for (std::size_t k = 0; k < coarse.vertices.size(); ++k)
    coarse.maxCurvatureError =
        std::max(coarse.maxCurvatureError,
                 std::abs(coarse.curvature[k] - fineCurvature[coarse.vertices[k]]));
  for (const auto e : surface.edges()) {
    const auto h = surface.halfedge_handle(e, 0);
    coarse.maxTrackingError =
        std::max(coarse.maxTrackingError,
                 trackingError(coarse, surface.from_vertex_handle(h).idx(),
                               surface.to_vertex_handle(h).idx(), flatLengths[e.idx()]));
  }
  return coarse;
}

// Sides joining two cones, and for each the fine vertex nearest its midpoint (in one of the two
// faces at it), or -1 when no fine vertex lies in them.
std::vector<int> coneSideSeparators(const CoarseTriangulation& coarse, int& coneSides) {
  std::vector<int> separators;
  coneSides = 0;
  std::vector<std::vector<int>> located(coarse.faces.size());
  for (std::size_t v = 0; v < coarse.fineVertices.size(); ++v)
    if (coarse.coarseVertex[v] < 0)
      located[std::size_t(coarse.fineVertices[v].face)].push_back(int(v));
  for (std::size_t f = 0; f < coarse.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = coarse.faces[f][std::size_t(k)], b = coarse.faces[f][std::size_t((k + 1) % 3)];
      if (!coarse.isCone[std::size_t(a)] || !coarse.isCone[std::size_t(b)]) continue;
      const int g = coarse.neighbour[f][std::size_t(k)];
      if (int(f) > g) continue;  // each side once
      ++coneSides;
      // Barycentric distance to the side's midpoint: good enough to pick a vertex near it.
      int best = -1;
      double bestDistance = std::numeric_limits<double>::infinity();
      for (int face : {int(f), g}) {
        const int side = face == int(f) ? k : coarse.neighbourSide[f][std::size_t(k)];
        for (int v : located[std::size_t(face)]) {
          Eigen::Vector3d midpoint = Eigen::Vector3d::Zero();
          midpoint[side] = midpoint[(side + 1) % 3] = 0.5;
          const double distance =
              (coarse.fineVertices[std::size_t(v)].barycentric - midpoint).norm();
          if (distance < bestDistance) {
            bestDistance = distance;
            best = v;
          }
        }
      }
      if (best >= 0) separators.push_back(best);
    }
  return separators;
}

}  // namespace

CoarseTriangulation coarsenFlatMetric(const TriMesh& surface, const Eigen::VectorXd& flatLengths,
                                      const CoarseningOptions& options) {
  checkInput(surface, flatLengths, options);
  std::vector<int> extra;
  CoarseTriangulation coarse = coarsenKeeping(surface, flatLengths, options, extra);
  for (int round = 0; options.separateCones && round < 4; ++round) {
    const std::vector<int> separators = coneSideSeparators(coarse, coarse.coneSides);
    if (separators.empty()) break;
    extra.insert(extra.end(), separators.begin(), separators.end());
    CoarseningOptions more = options;
    more.targetVertices = options.targetVertices + int(extra.size());
    coarse = coarsenKeeping(surface, flatLengths, more, extra);
    coarse.separatingVertices = int(extra.size());
  }
  if (options.separateCones) coneSideSeparators(coarse, coarse.coneSides);
  return coarse;
}

std::vector<DevelopedFace> developFromPoint(const CoarseTriangulation& coarse,
                                            const SurfacePoint& origin, double radius) {
  const int faceCount = int(coarse.faces.size());
  if (origin.face < 0 || origin.face >= faceCount)
    throw InputError("coarse development: face " + std::to_string(origin.face) +
                     " is out of range (" + std::to_string(faceCount) + " faces)");
  const int f = origin.face;
  const auto& l = coarse.sideLengths[f];
  Corners base = {Vector2(0.0, 0.0), Vector2(l[0], 0.0), Vector2(0.0, 0.0)};
  base[2] = apex(base[0], base[1], l[0], l[2], l[1]);

  std::vector<DevelopedFace> copies;
  // Per copy, the sides through which rays leave it (bit k: side k).
  std::vector<int> exits;
  const std::size_t limit = 100000 + 100 * std::size_t(faceCount);
  const auto add = [&](const DevelopedFace& copy, int exitMask) {
    if (copies.size() >= limit)
      throw InternalError("coarse development: more than " + std::to_string(limit) +
                          " faces within radius " + std::to_string(radius));
    copies.push_back(copy);
    exits.push_back(exitMask);
  };
  int c = 0;
  origin.barycentric.maxCoeff(&c);
  const bool atVertex = origin.barycentric[c] >= 1.0 - kCornerTolerance;
  if (atVertex) {
    // The faces around the vertex, turning counter-clockwise from the origin's face; rays leave
    // each through the side opposite the vertex.
    DevelopedFace copy;
    copy.face = f;
    for (int k = 0; k < 3; ++k) copy.corners[k] = base[k] - base[c];
    copy.fromAngle = std::atan2(copy.corners[(c + 1) % 3].y(), copy.corners[(c + 1) % 3].x());
    int k = c;
    do {
      const Vector2& a = copy.corners[(k + 1) % 3];
      const Vector2& b = copy.corners[(k + 2) % 3];
      copy.toAngle = copy.fromAngle + std::atan2(cross(a, b), a.dot(b));
      add(copy, 1 << ((k + 1) % 3));
      const int side = (k + 2) % 3;
      const double turned = copy.toAngle;
      const int face = copy.face;
      copy = unfoldAcross(coarse, face, copy.corners, side);
      copy.fromAngle = turned;
      k = coarse.neighbourSide[face][side];
    } while (copy.face != f || k != c);
  } else {
    const Vector2 p = pointAt(base, origin.barycentric);
    DevelopedFace copy;
    copy.face = f;
    for (int k = 0; k < 3; ++k) copy.corners[k] = base[k] - p;
    copy.fromAngle = -kPi;
    copy.toAngle = kPi;
    add(copy, 7);
  }
  for (std::size_t i = 0; i < copies.size(); ++i) {
    for (int side = 0; side < 3; ++side) {
      if (!(exits[i] >> side & 1)) continue;
      const DevelopedFace copy = copies[i];
      const Vector2& a = copy.corners[side];
      const Vector2& b = copy.corners[(side + 1) % 3];
      if (distanceToSegment(a, b) > radius) continue;
      // The directions through the side, counter-clockwise from a to b (the face lies on the
      // origin's side of it).
      double width = std::atan2(cross(a, b), a.dot(b));
      const bool root = i == 0 && !atVertex;
      if (width <= 0.0) {
        // Only the origin's own face may have it on a side (width pi, up to rounding).
        if (!root) continue;
        width += 2.0 * kPi;
      }
      const double start = std::atan2(a.y(), a.x());
      std::vector<std::pair<double, double>> pieces;
      if (root) {
        pieces.push_back({start, start + width});
      } else {
        const double first = start + 2.0 * kPi * std::floor((copy.fromAngle - start) / (2.0 * kPi));
        for (double s = first; s < copy.toAngle; s += 2.0 * kPi)
          pieces.push_back({std::max(copy.fromAngle, s), std::min(copy.toAngle, s + width)});
      }
      for (const auto& [from, to] : pieces) {
        if (to - from <= kMinWedge) continue;
        DevelopedFace next = unfoldAcross(coarse, copy.face, copy.corners, side);
        next.fromAngle = from;
        next.toAngle = to;
        add(next, 7 & ~(1 << coarse.neighbourSide[copy.face][side]));
      }
    }
  }
  return copies;
}

std::vector<Eigen::Vector2d> sightingsOfFineVertex(const CoarseTriangulation& coarse,
                                                   const std::vector<DevelopedFace>& development,
                                                   int fineVertex) {
  const SurfacePoint& at = coarse.fineVertices[fineVertex];
  const int vertex = coarse.coarseVertex[fineVertex];
  std::vector<Vector2> found;
  const auto consider = [&](const DevelopedFace& copy, const Vector2& x) {
    if (seenThrough(copy, std::atan2(x.y(), x.x()))) found.push_back(x);
  };
  for (const DevelopedFace& copy : development) {
    if (vertex >= 0) {
      for (int k = 0; k < 3; ++k)
        if (coarse.faces[copy.face][k] == vertex) consider(copy, copy.corners[k]);
    } else if (copy.face == at.face) {
      consider(copy, pointAt(copy.corners, at.barycentric));
    }
  }
  return found;
}

SurfacePoint locateOnCoarse(const TriMesh& surface, const CoarseTriangulation& coarse, int fineFace,
                            const Eigen::Vector3d& barycentric) {
  checkSurfacePoint(surface, {fineFace, barycentric}, "coarse location");
  if (coarse.fineVertices.size() != surface.n_vertices() ||
      coarse.fineLengths.size() != Eigen::Index(surface.n_edges()))
    throw InputError("coarse location: the coarse triangulation is not one of this surface");
  // Corner k of the fine face and the length of its side from corner k to corner k + 1.
  std::array<int, 3> vertex;
  std::array<double, 3> length;
  auto h = surface.halfedge_handle(TriMesh::FaceHandle(fineFace));
  for (int k = 0; k < 3; ++k, h = surface.next_halfedge_handle(h)) {
    vertex[k] = surface.to_vertex_handle(h).idx();
    length[k] = coarse.fineLengths[surface.edge_handle(surface.next_halfedge_handle(h)).idx()];
  }
  // Start from a removed vertex (inside a coarse face) if there is one, else from one that is not
  // a cone.
  const auto rank = [&](int k) {
    const int c = coarse.coarseVertex[vertex[k]];
    return c < 0 ? 0 : coarse.isCone[c] ? 2 : 1;
  };
  int s = 0;
  for (int k = 1; k < 3; ++k)
    if (rank(k) < rank(s)) s = k;
  const int j = (s + 1) % 3, k = (s + 2) % 3;
  const double lj = length[s], lk = length[k], ljk = length[j];
  const auto copies =
      developFromPoint(coarse, coarse.fineVertices[vertex[s]], 1.5 * std::max(lj, lk));
  const auto atJ = sightingsOfFineVertex(coarse, copies, vertex[j]);
  const auto atK = sightingsOfFineVertex(coarse, copies, vertex[k]);
  // The counter-clockwise pair whose distances best match the fine face's lengths.
  double bestError = std::numeric_limits<double>::infinity();
  std::array<Vector2, 3> corner;
  corner[s] = Vector2::Zero();
  for (const Vector2& x : atJ)
    for (const Vector2& y : atK) {
      if (cross(x, y) <= 0.0) continue;
      const double error = std::abs(x.norm() - lj) / lj + std::abs(y.norm() - lk) / lk +
                           std::abs((x - y).norm() - ljk) / ljk;
      if (error < bestError) {
        bestError = error;
        corner[j] = x;
        corner[k] = y;
      }
    }
  if (!(bestError <= 1e-6))
    throw InternalError("coarse location: fine face " + std::to_string(fineFace) +
                        " does not lay out on the coarse triangulation (relative length error " +
                        std::to_string(bestError) + ")");
  const Vector2 q = pointAt(corner, barycentric);
  if (q.norm() <= kCornerTolerance * std::max(lj, lk)) return coarse.fineVertices[vertex[s]];
  const double phi = std::atan2(q.y(), q.x());
  SurfacePoint best;
  double bestMin = -std::numeric_limits<double>::infinity();
  for (const DevelopedFace& copy : copies) {
    if (!seenThrough(copy, phi)) continue;
    const Eigen::Vector3d b = barycentricIn(q, copy.corners);
    if (b.minCoeff() > bestMin) {
      bestMin = b.minCoeff();
      best = {copy.face, b};
    }
  }
  if (!(bestMin >= -1e-6))
    throw InternalError("coarse location: the point of fine face " + std::to_string(fineFace) +
                        " lies in no developed coarse face");
  return best;
}

}  // namespace mspline::structure
