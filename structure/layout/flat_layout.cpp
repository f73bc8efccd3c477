#include "mspline/structure/layout/flat_layout.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>
#include <string>

#include <Eigen/Dense>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "mspline/structure/topology/cut_graph.h"
#include "mspline/structure/topology/homotopy_basis.h"

namespace mspline::structure {

namespace {

/// Gauss-Lagrange reduction: the same lattice spanned by a shortest vector and a shortest one
/// independent of it, so copies of the fundamental domain tile a compact patch, not a thin band.
void reduceLatticeBasis(std::array<Eigen::Vector2d, 2>& basis) {
  auto& [a, b] = basis;
  if (a.squaredNorm() > b.squaredNorm()) std::swap(a, b);
  // Each swap shrinks |a| (Gauss reduction ends in a few steps); the bound ends it on degenerate
  // or non-finite periods, where the comparison below never holds.
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double m = std::round(a.dot(b) / a.squaredNorm());
    b -= m * a;
    if (b.squaredNorm() >= a.squaredNorm()) return;
    std::swap(a, b);
  }
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

Eigen::Vector2d rotate(const Eigen::Vector2d& d, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * d.x() - s * d.y(), s * d.x() + c * d.y()};
}

// Marks the cut: the homotopy cut graph (which joins the boundary loops), and each cone joined by
// a shortest path to what is cut already. Each path stops at the first cut or boundary vertex it
// reaches, so it closes no loop and the surface stays one disk.
std::vector<char> cutEdgeFlags(const TriMesh& mesh, const HomotopyBasis& basis,
                               const std::vector<Cone>& cones) {
  std::vector<char> cut(mesh.n_edges(), 0);
  // A sphere's own cut graph is a slit that the cones do not need.
  const bool sphere = basis.loops.empty() && basis.boundaryLoops.empty();
  if (!sphere || cones.empty())
    for (int e : computeCutGraph(mesh, basis).edges) cut[e] = 1;
  if (cones.empty()) return cut;

  std::vector<char> reached(mesh.n_vertices(), 0);
  bool anyReached = false;
  for (auto v : mesh.vertices())
    if (mesh.is_boundary(v)) reached[v.idx()] = anyReached = true;
  for (auto e : mesh.edges())
    if (cut[e.idx()]) {
      const auto h = mesh.halfedge_handle(e, 0);
      reached[mesh.from_vertex_handle(h).idx()] = reached[mesh.to_vertex_handle(h).idx()] = 1;
      anyReached = true;
    }
  std::vector<TriMesh::HalfedgeHandle> parent(mesh.n_vertices());
  std::vector<int> visitedAt(mesh.n_vertices(), -1);
  for (std::size_t c = 0; c < cones.size(); ++c) {
    const TriMesh::VertexHandle cone(cones[c].vertex);
    if (!anyReached) {
      reached[cone.idx()] = anyReached = true;
      continue;
    }
    if (reached[cone.idx()]) continue;
    std::queue<TriMesh::VertexHandle> queue;
    queue.push(cone);
    visitedAt[cone.idx()] = int(c);
    TriMesh::VertexHandle hit;
    while (!queue.empty() && !hit.is_valid()) {
      const auto v = queue.front();
      queue.pop();
      for (auto h : mesh.voh_range(v)) {
        const auto w = mesh.to_vertex_handle(h);
        if (visitedAt[w.idx()] == int(c)) continue;
        visitedAt[w.idx()] = int(c);
        parent[w.idx()] = h;
        if (reached[w.idx()]) {
          hit = w;
          break;
        }
        queue.push(w);
      }
    }
    MSPLINE_ASSERT(hit.is_valid(), "a cone is not connected to the cut");
    for (auto v = hit; v != cone;) {
      const auto h = parent[v.idx()];
      cut[mesh.edge_handle(h).idx()] = 1;
      v = mesh.from_vertex_handle(h);
      reached[v.idx()] = 1;
    }
  }
  return cut;
}

// Makes sure cutting along `preferred` leaves one disk, changing it as little as possible. Faces
// are joined by a spanning tree of the dual graph that crosses preferred edges only where it must
// (where they close loops, e.g. paths between boundaries that pass other boundaries); cutting every
// edge the tree does not cross leaves a disk, and pruning branches that dangle at an interior
// vertex that is no cone keeps it one.
std::vector<char> diskCut(const TriMesh& mesh, const std::vector<char>& preferred,
                          const std::vector<Cone>& cones) {
  std::vector<char> crossed(mesh.n_edges(), 0);
  std::vector<char> reached(mesh.n_faces(), 0);
  std::vector<int> order = {0};
  reached[0] = 1;
  for (const bool acrossPreferred : {false, true}) {
    std::vector<int> queue = order;
    for (std::size_t k = 0; k < queue.size(); ++k) {
      for (auto h : mesh.fh_range(TriMesh::FaceHandle(queue[k]))) {
        const auto e = mesh.edge_handle(h);
        const auto opposite = mesh.opposite_halfedge_handle(h);
        if (mesh.is_boundary(opposite) || (preferred[e.idx()] && !acrossPreferred)) continue;
        const int g = mesh.face_handle(opposite).idx();
        if (reached[g]) continue;
        reached[g] = 1;
        crossed[e.idx()] = 1;
        queue.push_back(g);
      }
    }
    order = std::move(queue);
  }
  std::vector<char> cut(mesh.n_edges(), 0);
  std::vector<int> degree(mesh.n_vertices(), 0);
  for (auto e : mesh.edges()) {
    if (mesh.is_boundary(e) || crossed[e.idx()]) continue;
    cut[e.idx()] = 1;
    ++degree[mesh.from_vertex_handle(mesh.halfedge_handle(e, 0)).idx()];
    ++degree[mesh.to_vertex_handle(mesh.halfedge_handle(e, 0)).idx()];
  }
  std::vector<char> isCone(mesh.n_vertices(), 0);
  for (const Cone& c : cones) isCone[c.vertex] = 1;
  auto prunable = [&](TriMesh::VertexHandle v) {
    return degree[v.idx()] == 1 && !isCone[v.idx()] && !mesh.is_boundary(v);
  };
  std::vector<int> leaves;
  for (auto v : mesh.vertices())
    if (prunable(v)) leaves.push_back(v.idx());
  while (!leaves.empty()) {
    const TriMesh::VertexHandle v(leaves.back());
    leaves.pop_back();
    if (!prunable(v)) continue;
    for (auto h : mesh.voh_range(v)) {
      const auto e = mesh.edge_handle(h);
      if (!cut[e.idx()]) continue;
      cut[e.idx()] = 0;
      --degree[v.idx()];
      const auto w = mesh.to_vertex_handle(h);
      --degree[w.idx()];
      if (prunable(w)) leaves.push_back(w.idx());
      break;
    }
  }
  return cut;
}

// Breadth-first face order over uncut interior edges; returns the faces in visiting order and, for
// each face, the halfedge inside it through which it was reached (invalid for the start).
struct FaceWalk {
  std::vector<int> order;
  std::vector<TriMesh::HalfedgeHandle> entry;
};

FaceWalk walkFaces(const TriMesh& mesh, const std::vector<char>& cut, int start) {
  FaceWalk walk;
  walk.entry.assign(mesh.n_faces(), TriMesh::HalfedgeHandle());
  std::vector<char> seen(mesh.n_faces(), 0);
  std::queue<int> queue;
  queue.push(start);
  seen[start] = 1;
  while (!queue.empty()) {
    const TriMesh::FaceHandle f(queue.front());
    queue.pop();
    walk.order.push_back(f.idx());
    for (auto h : mesh.fh_range(f)) {
      const auto opposite = mesh.opposite_halfedge_handle(h);
      if (mesh.is_boundary(opposite) || cut[mesh.edge_handle(h).idx()]) continue;
      const int g = mesh.face_handle(opposite).idx();
      if (seen[g]) continue;
      seen[g] = 1;
      walk.entry[g] = opposite;
      queue.push(g);
    }
  }
  return walk;
}

// The middle of a longest breadth-first path (two sweeps): a face near the disk's dual center, so
// that no vertex is placed through a long chain of triangles.
int centralFace(const TriMesh& mesh, const std::vector<char>& cut) {
  const FaceWalk first = walkFaces(mesh, cut, 0);
  const int far = first.order.back();
  const FaceWalk second = walkFaces(mesh, cut, far);
  std::vector<int> path;
  for (int f = second.order.back(); f != far;
       f = mesh.face_handle(mesh.opposite_halfedge_handle(second.entry[f])).idx())
    path.push_back(f);
  path.push_back(far);
  return path[path.size() / 2];
}

}  // namespace

FlatLayout layoutFlatMetric(const TriMesh& mesh, const Eigen::VectorXd& edgeLengths,
                            const FlatLayoutOptions& options) {
  if (edgeLengths.size() != static_cast<Eigen::Index>(mesh.n_edges()))
    throw InputError("layout: " + std::to_string(edgeLengths.size()) + " edge lengths for " +
                     std::to_string(mesh.n_edges()) + " edges");
  for (Eigen::Index e = 0; e < edgeLengths.size(); ++e)
    if (!(edgeLengths[e] > 0.0) || !std::isfinite(edgeLengths[e]))
      throw InputError("layout: edge " + std::to_string(e) + " has length " +
                       std::to_string(edgeLengths[e]));

  HomotopyBasisOptions basisOptions;
  basisOptions.baseVertex = options.baseVertex;
  const HomotopyBasis basis = computeHomotopyBasis(mesh, basisOptions);

  FlatLayout layout;
  const Eigen::VectorXd curvature = vertexCurvatures(mesh, edgeLengths);
  for (auto v : mesh.vertices())
    if (!mesh.is_boundary(v) && std::abs(curvature[v.idx()]) > options.coneTolerance)
      layout.cones.push_back({v.idx(), curvature[v.idx()]});

  std::vector<char> cut = diskCut(mesh, cutEdgeFlags(mesh, basis, layout.cones), layout.cones);
  for (auto e : mesh.edges()) {
    if (mesh.is_boundary(e)) cut[e.idx()] = 0;
    if (cut[e.idx()]) layout.cutEdges.push_back(e.idx());
  }

  // Copies of vertices: corners (named by the face halfedge pointing at their vertex) glued across
  // uncut edges are one copy.
  std::vector<int> root(mesh.n_halfedges());
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](int x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  for (auto e : mesh.edges()) {
    if (cut[e.idx()] || mesh.is_boundary(e)) continue;
    const auto h0 = mesh.halfedge_handle(e, 0);
    const auto h1 = mesh.halfedge_handle(e, 1);
    root[find(h0.idx())] = find(mesh.prev_halfedge_handle(h1).idx());
    root[find(mesh.prev_halfedge_handle(h0).idx())] = find(h1.idx());
  }
  std::vector<int> copyOf(mesh.n_halfedges(), -1);
  for (auto v : mesh.vertices())
    for (auto h : mesh.vih_range(v)) {
      if (mesh.is_boundary(h)) continue;
      const int r = find(h.idx());
      if (copyOf[r] == -1) {
        copyOf[r] = static_cast<int>(layout.chartSourceVertex.size());
        layout.chartSourceVertex.push_back(v.idx());
      }
      copyOf[h.idx()] = copyOf[r];
    }
  const long copies = static_cast<long>(layout.chartSourceVertex.size());
  const long diskEdges = static_cast<long>(mesh.n_edges() + layout.cutEdges.size());
  const long euler = copies - diskEdges + static_cast<long>(mesh.n_faces());
  if (euler != 1)
    throw InternalError("layout: the cut surface has Euler characteristic " +
                        std::to_string(euler) + ", not a disk");

  // Trilateration: each face's third corner from the two it shares with the face it was reached
  // from, at the metric angle and length. Edge directions are carried as angles summed from the
  // metric, not re-measured from placed points: on skinny triangles a direction read off a short
  // edge would magnify the rounding of its endpoints at every step.
  const Eigen::VectorXd metricAngle = cornerAngles(mesh, edgeLengths);
  auto length = [&](TriMesh::HalfedgeHandle h) { return edgeLengths[mesh.edge_handle(h).idx()]; };
  layout.rootFace = centralFace(mesh, cut);
  const FaceWalk walk = walkFaces(mesh, cut, layout.rootFace);
  if (walk.order.size() != mesh.n_faces())
    throw InternalError("layout: the cut surface is not connected");
  layout.chartPositions = Eigen::MatrixXd::Zero(copies, 2);
  std::vector<char> placed(copies, 0);
  Eigen::VectorXd& direction = layout.halfedgeDirection;
  direction = Eigen::VectorXd::Zero(Eigen::Index(mesh.n_halfedges()));
  auto position = [&](TriMesh::HalfedgeHandle h) -> Eigen::Vector2d {
    return layout.chartPositions.row(copyOf[h.idx()]).transpose();
  };
  for (int fi : walk.order) {
    // h runs P -> Q, next(h) Q -> R, prev(h) R -> P, counter-clockwise.
    TriMesh::HalfedgeHandle h = walk.entry[fi];
    if (h.is_valid()) {
      direction[h.idx()] = direction[mesh.opposite_halfedge_handle(h).idx()] + kPi;
    } else {
      h = mesh.halfedge_handle(TriMesh::FaceHandle(fi));
      layout.chartPositions.row(copyOf[mesh.prev_halfedge_handle(h).idx()]).setZero();
      layout.chartPositions.row(copyOf[h.idx()]) = Eigen::RowVector2d(length(h), 0.0);
      placed[copyOf[mesh.prev_halfedge_handle(h).idx()]] = placed[copyOf[h.idx()]] = 1;
    }
    const auto next = mesh.next_halfedge_handle(h);
    const auto prev = mesh.prev_halfedge_handle(h);
    const double towardR = direction[h.idx()] + metricAngle[next.idx()];         // angle at P
    direction[next.idx()] = direction[h.idx()] + kPi - metricAngle[prev.idx()];  // angle at Q
    direction[prev.idx()] = towardR + kPi;
    const int third = copyOf[next.idx()];
    if (placed[third]) continue;
    layout.chartPositions.row(third) =
        (position(prev) + length(prev) * Eigen::Vector2d(std::cos(towardR), std::sin(towardR)))
            .transpose();
    placed[third] = 1;
  }

  const Eigen::Vector2d low = layout.chartPositions.colwise().minCoeff().transpose();
  const Eigen::Vector2d high = layout.chartPositions.colwise().maxCoeff().transpose();
  layout.diameter = (high - low).norm();

  // Corners and statistics.
  const Eigen::VectorXd inputAngle = cornerAngles(mesh, structure::edgeLengths(mesh));
  layout.cornerCopy.resize(3 * mesh.n_faces());
  layout.cornerUV.resize(3 * mesh.n_faces(), 2);
  layout.minAreaRatio = std::numeric_limits<double>::infinity();
  layout.maxAreaRatio = -std::numeric_limits<double>::infinity();
  double areaRatioSum = 0.0, angleDistortionSum = 0.0;
  for (auto f : mesh.faces()) {
    std::array<TriMesh::HalfedgeHandle, 3> hs;
    hs[0] = mesh.halfedge_handle(f);
    hs[1] = mesh.next_halfedge_handle(hs[0]);
    hs[2] = mesh.next_halfedge_handle(hs[1]);
    std::array<Eigen::Vector2d, 3> p;
    for (int k = 0; k < 3; ++k) {
      p[k] = position(hs[k]);
      layout.cornerCopy[3 * f.idx() + k] = copyOf[hs[k].idx()];
      layout.cornerUV.row(3 * f.idx() + k) = p[k].transpose();
    }
    const double area = 0.5 * cross(p[1] - p[0], p[2] - p[0]);
    if (area <= 0.0) ++layout.flippedTriangles;
    const double inputArea = mesh.calc_face_area(f);
    const double ratio = area / inputArea;
    layout.minAreaRatio = std::min(layout.minAreaRatio, ratio);
    layout.maxAreaRatio = std::max(layout.maxAreaRatio, ratio);
    areaRatioSum += ratio;
    for (int k = 0; k < 3; ++k) {
      // hs[k] runs from corner k-1 to corner k; the corner k sits between hs[k] and hs[k+1] and
      // faces hs[k+2].
      const Eigen::Vector2d side = p[k] - p[(k + 2) % 3];
      const double layoutLength = side.norm();
      layout.maxEdgeLengthError = std::max(layout.maxEdgeLengthError,
                                           std::abs(layoutLength - length(hs[k])) / length(hs[k]));
      const Eigen::Vector2d out = p[(k + 1) % 3] - p[k];
      const Eigen::Vector2d back = p[(k + 2) % 3] - p[k];
      const double angle = std::atan2(cross(out, back), out.dot(back));
      const int opposite = hs[(k + 2) % 3].idx();
      layout.maxLayoutAngleError =
          std::max(layout.maxLayoutAngleError, std::abs(angle - metricAngle[opposite]));
      const double distortion = std::abs(metricAngle[opposite] - inputAngle[opposite]);
      angleDistortionSum += distortion;
      layout.maxAngleDistortion = std::max(layout.maxAngleDistortion, distortion);
    }
  }
  layout.meanAreaRatio = areaRatioSum / static_cast<double>(mesh.n_faces());
  layout.meanAngleDistortion = angleDistortionSum / (3.0 * static_cast<double>(mesh.n_faces()));

  // Seam transitions from the two laid-out copies of each cut edge.
  const double scale = layout.diameter > 0.0 ? layout.diameter : 1.0;
  for (int e : layout.cutEdges) {
    const auto h0 = mesh.halfedge_handle(TriMesh::EdgeHandle(e), 0);
    const auto h1 = mesh.halfedge_handle(TriMesh::EdgeHandle(e), 1);
    const Eigen::Vector2d a0 = position(mesh.prev_halfedge_handle(h0)), b0 = position(h0);
    const Eigen::Vector2d b1 = position(mesh.prev_halfedge_handle(h1)), a1 = position(h1);
    SeamTransition seam;
    seam.edge = e;
    seam.face0 = mesh.face_handle(h0).idx();
    seam.face1 = mesh.face_handle(h1).idx();
    seam.angle = std::atan2(cross(b0 - a0, b1 - a1), (b0 - a0).dot(b1 - a1));
    if (seam.angle <= -kPi) seam.angle += 2 * kPi;
    seam.translation = a1 - rotate(a0, seam.angle);
    seam.residual = (rotate(b0, seam.angle) + seam.translation - b1).norm() / scale;
    layout.maxSeamResidual = std::max(layout.maxSeamResidual, seam.residual);
    layout.seams.push_back(seam);
  }

  if (basis.genus == 1 && basis.boundaryLoops.empty() && layout.cones.empty()) {
    layout.hasPeriods = true;
    for (int k = 0; k < 2; ++k) {
      const auto it =
          std::lower_bound(layout.cutEdges.begin(), layout.cutEdges.end(), basis.leftoverEdges[k]);
      MSPLINE_ASSERT(it != layout.cutEdges.end() && *it == basis.leftoverEdges[k],
                     "a homotopy loop's closing edge is not cut");
      layout.periods[k] = layout.seams[it - layout.cutEdges.begin()].translation;
    }
    reduceLatticeBasis(layout.periods);
    const auto base = std::find(layout.chartSourceVertex.begin(), layout.chartSourceVertex.end(),
                                basis.baseVertex);
    const Eigen::Vector2d o =
        layout.chartPositions.row(base - layout.chartSourceVertex.begin()).transpose();
    layout.fundamentalParallelogram = {
        o, o + layout.periods[0], o + layout.periods[0] + layout.periods[1], o + layout.periods[1]};
    Eigen::Matrix2d lattice;
    lattice << layout.periods[0], layout.periods[1];
    const Eigen::PartialPivLU<Eigen::Matrix2d> solver(lattice);
    for (const SeamTransition& seam : layout.seams) {
      const Eigen::Vector2d mn = solver.solve(seam.translation);
      const Eigen::Vector2d shift = lattice * mn.array().round().matrix();
      const auto h0 = mesh.halfedge_handle(TriMesh::EdgeHandle(seam.edge), 0);
      const auto h1 = mesh.halfedge_handle(TriMesh::EdgeHandle(seam.edge), 1);
      const double ra = (position(mesh.prev_halfedge_handle(h0)) + shift - position(h1)).norm();
      const double rb = (position(h0) + shift - position(mesh.prev_halfedge_handle(h1))).norm();
      layout.maxPeriodResidual = std::max(layout.maxPeriodResidual, std::max(ra, rb) / scale);
    }
  }
  return layout;
}

PolygonSoup soupWithCornerUVs(const TriMesh& mesh, const FlatLayout& layout,
                              const std::string& sourceName) {
  PolygonSoup soup = toSoup(mesh, sourceName);
  soup.cornerUVs.resize(soup.faces.size());
  for (auto f : mesh.faces())
    for (int k = 0; k < 3; ++k) {
      const auto row = layout.cornerUV.row(3 * f.idx() + k);
      soup.cornerUVs[f.idx()].push_back({row[0], row[1]});
    }
  return soup;
}

}  // namespace mspline::structure
