#include "mspline/structure/atlas/affine_atlas.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"

namespace mspline::structure {

namespace {

Eigen::Vector2d rotate(const Eigen::Vector2d& x, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * x.x() - s * x.y(), s * x.x() + c * x.y()};
}

// Angle in (-pi, pi].
double wrap(double angle) {
  angle = std::remainder(angle, 2.0 * kPi);
  return angle <= -kPi ? angle + 2.0 * kPi : angle;
}

// The rigid motion taking points p onto points q in the least-squares sense (2D Kabsch).
RigidMotion fitRigid(const std::vector<Eigen::Vector2d>& p, const std::vector<Eigen::Vector2d>& q) {
  Eigen::Vector2d cp = Eigen::Vector2d::Zero(), cq = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < p.size(); ++k) {
    cp += p[k];
    cq += q[k];
  }
  cp /= double(p.size());
  cq /= double(q.size());
  double dot = 0.0, crossSum = 0.0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const Eigen::Vector2d a = p[k] - cp, b = q[k] - cq;
    dot += a.dot(b);
    crossSum += a.x() * b.y() - a.y() * b.x();
  }
  RigidMotion motion;
  motion.angle = std::atan2(crossSum, dot);
  motion.translation = cq - rotate(cp, motion.angle);
  return motion;
}

// Layout position of the vertex halfedge h points to, in h's face.
Eigen::Vector2d layoutCorner(const TriMesh& mesh, const FlatLayout& layout,
                             TriMesh::HalfedgeHandle h) {
  const auto f = mesh.face_handle(h);
  auto g = mesh.halfedge_handle(f);
  int k = 0;
  while (g != h) {
    g = mesh.next_halfedge_handle(g);
    ++k;
  }
  return layout.cornerUV.row(3 * f.idx() + k).transpose();
}

// The star of v laid out: the first face where the layout has it, then face after face turning
// clockwise around v, each new neighbour at the metric length and angle from v. Directions are
// summed angles, not re-measured, so rounding does not grow around the fan.
Chart layOutStar(const TriMesh& mesh, const Eigen::VectorXd& lengths, const Eigen::VectorXd& angles,
                 const FlatLayout& layout, TriMesh::VertexHandle v) {
  Chart chart;
  chart.vertex = v.idx();
  // The fan runs clockwise from g0 (v -> t in face (v, t, s)) to the face across edge (v, t).
  TriMesh::HalfedgeHandle g0;
  for (auto h : mesh.voh_range(v)) {
    if (mesh.is_boundary(h)) {
      g0 = mesh.next_halfedge_handle(mesh.opposite_halfedge_handle(h));
      break;
    }
    if (!g0.is_valid()) g0 = h;
  }
  const Eigen::Vector2d centre = layoutCorner(mesh, layout, mesh.prev_halfedge_handle(g0));
  std::vector<Eigen::Vector2d> positions = {centre};
  chart.vertices = {v.idx()};
  const auto place = [&](TriMesh::HalfedgeHandle outgoing, double direction) {
    const int w = mesh.to_vertex_handle(outgoing).idx();
    if (std::find(chart.vertices.begin(), chart.vertices.end(), w) != chart.vertices.end()) return;
    const double l = lengths[mesh.edge_handle(outgoing).idx()];
    chart.vertices.push_back(w);
    positions.push_back(centre + l * Eigen::Vector2d(std::cos(direction), std::sin(direction)));
  };
  // The layout's summed direction, not one measured from its positions: that one would carry
  // their rounding divided by the edge length into every transition's angle.
  double direction = layout.halfedgeDirection[g0.idx()];
  auto g = g0;
  do {
    chart.faces.push_back(mesh.face_handle(g).idx());
    place(g, direction);
    // s = to(next(g)) lies counter-clockwise of t by the angle at v, which faces next(g).
    place(mesh.opposite_halfedge_handle(mesh.prev_halfedge_handle(g)),
          direction + angles[mesh.next_halfedge_handle(g).idx()]);
    const auto across = mesh.opposite_halfedge_handle(g);
    if (mesh.is_boundary(across)) break;
    g = mesh.next_halfedge_handle(across);
    // The new t lies clockwise of the old one by the angle at v in the new face.
    direction -= angles[mesh.next_halfedge_handle(g).idx()];
  } while (g != g0);
  chart.positions.resize(2, Eigen::Index(positions.size()));
  for (std::size_t k = 0; k < positions.size(); ++k)
    chart.positions.col(Eigen::Index(k)) = positions[k];
  return chart;
}

// The vertices of the faces two charts share, where their transition is defined. Other vertices
// both stars contain lie elsewhere on the surface in one of them (a short loop of edges around a
// cone or a handle), and there the charts need not agree.
std::vector<int> overlapVertices(const TriMesh& mesh, const Chart& a, const Chart& b) {
  std::vector<int> shared;
  for (int f : a.faces) {
    if (std::find(b.faces.begin(), b.faces.end(), f) == b.faces.end()) continue;
    for (const auto w : mesh.fv_range(TriMesh::FaceHandle(f)))
      if (std::find(shared.begin(), shared.end(), w.idx()) == shared.end())
        shared.push_back(w.idx());
  }
  return shared;
}

}  // namespace

Eigen::Vector2d RigidMotion::operator()(const Eigen::Vector2d& x) const {
  return rotate(x, angle) + translation;
}

RigidMotion RigidMotion::after(const RigidMotion& first) const {
  return {wrap(angle + first.angle), rotate(first.translation, angle) + translation};
}

RigidMotion RigidMotion::inverse() const {
  return {wrap(-angle), -rotate(translation, -angle)};
}

bool Chart::contains(int w) const {
  return std::find(vertices.begin(), vertices.end(), w) != vertices.end();
}

Eigen::Vector2d Chart::position(int w) const {
  const auto it = std::find(vertices.begin(), vertices.end(), w);
  if (it == vertices.end())
    throw InternalError("chart of vertex " + std::to_string(vertex) + " does not contain vertex " +
                        std::to_string(w));
  return positions.col(it - vertices.begin());
}

const char* transitionKindName(TransitionKind kind) {
  switch (kind) {
    case TransitionKind::Translation:
      return "translation";
    case TransitionKind::Rotation90:
      return "rotation90";
    default:
      return "rigid";
  }
}

int AffineAtlas::transitionIndex(int a, int b) const {
  if (a < 0 || b < 0 || a >= int(chartOfVertex.size()) || b >= int(chartOfVertex.size())) return -1;
  int ca = chartOfVertex[std::size_t(a)], cb = chartOfVertex[std::size_t(b)];
  if (ca < 0 || cb < 0) return -1;
  if (ca > cb) std::swap(ca, cb);
  const auto it = std::lower_bound(transitions.begin(), transitions.end(), std::make_pair(ca, cb),
                                   [](const Transition& t, const std::pair<int, int>& key) {
                                     return std::make_pair(t.from, t.to) < key;
                                   });
  return it != transitions.end() && it->from == ca && it->to == cb ? int(it - transitions.begin())
                                                                   : -1;
}

RigidMotion AffineAtlas::transition(int a, int b) const {
  const int index = transitionIndex(a, b);
  if (index < 0)
    throw InputError("atlas: no transition between the charts of vertices " + std::to_string(a) +
                     " and " + std::to_string(b));
  const Transition& t = transitions[std::size_t(index)];
  return t.from == chartOfVertex[std::size_t(a)] ? t.motion : t.motion.inverse();
}

AffineAtlas buildAffineAtlas(const TriMesh& mesh, const Eigen::VectorXd& flatLengths,
                             const FlatLayout& layout, const AffineAtlasOptions& options) {
  if (flatLengths.size() != Eigen::Index(mesh.n_edges()))
    throw InputError("atlas: " + std::to_string(flatLengths.size()) + " edge lengths for " +
                     std::to_string(mesh.n_edges()) + " edges");
  if (layout.cornerUV.rows() != Eigen::Index(3 * mesh.n_faces()) ||
      layout.halfedgeDirection.size() != Eigen::Index(mesh.n_halfedges()))
    throw InputError("atlas: the layout is not one of this mesh");
  AffineAtlas atlas;
  atlas.diameter = layout.diameter > 0.0 ? layout.diameter : 1.0;
  const Eigen::VectorXd angles = cornerAngles(mesh, flatLengths);
  const Eigen::VectorXd curvature = vertexCurvatures(mesh, flatLengths);

  atlas.chartOfVertex.assign(mesh.n_vertices(), -1);
  for (const auto v : mesh.vertices()) {
    if (!mesh.is_boundary(v) && std::abs(curvature[v.idx()]) > options.coneTolerance) {
      atlas.cones.push_back({v.idx(), curvature[v.idx()]});
      continue;
    }
    if (!mesh.is_boundary(v)) atlas.flatnessDefect += std::abs(curvature[v.idx()]);
    if (mesh.valence(v) == 0) continue;
    atlas.chartOfVertex[std::size_t(v.idx())] = int(atlas.charts.size());
    atlas.charts.push_back(layOutStar(mesh, flatLengths, angles, layout, v));
  }
  // Transitions fitted on the faces both stars contain (the two faces of the edge).
  std::vector<Eigen::Vector2d> p, q;
  for (const auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    int ca = atlas.chartOfVertex[std::size_t(mesh.from_vertex_handle(h).idx())];
    int cb = atlas.chartOfVertex[std::size_t(mesh.to_vertex_handle(h).idx())];
    if (ca < 0 || cb < 0) continue;
    if (ca > cb) std::swap(ca, cb);
    const Chart& a = atlas.charts[std::size_t(ca)];
    const Chart& b = atlas.charts[std::size_t(cb)];
    p.clear();
    q.clear();
    for (int w : overlapVertices(mesh, a, b)) {
      p.push_back(a.position(w));
      q.push_back(b.position(w));
    }
    atlas.transitions.push_back({ca, cb, fitRigid(p, q), 0.0});
  }
  std::sort(atlas.transitions.begin(), atlas.transitions.end(),
            [](const Transition& x, const Transition& y) {
              return std::make_pair(x.from, x.to) < std::make_pair(y.from, y.to);
            });

  measureAtlas(mesh, atlas, options);
  return atlas;
}

void measureAtlas(const TriMesh& mesh, AffineAtlas& atlas, const AffineAtlasOptions& options) {
  if (atlas.chartOfVertex.size() != mesh.n_vertices())
    throw InputError("atlas: " + std::to_string(atlas.chartOfVertex.size()) +
                     " vertices, the mesh has " + std::to_string(mesh.n_vertices()));
  atlas.uncoveredFaces = 0;
  atlas.maxTransitionResidual = atlas.maxCocycleResidual = atlas.maxKindAngleError = 0.0;
  atlas.kind = TransitionKind::Rigid;
  for (const auto f : mesh.faces()) {
    bool covered = false;
    for (const auto v : mesh.fv_range(f)) covered |= atlas.chartOfVertex[std::size_t(v.idx())] >= 0;
    atlas.uncoveredFaces += !covered;
  }

  for (Transition& t : atlas.transitions) {
    const Chart& a = atlas.charts[std::size_t(t.from)];
    const Chart& b = atlas.charts[std::size_t(t.to)];
    t.residual = 0.0;
    for (int w : overlapVertices(mesh, a, b))
      t.residual =
          std::max(t.residual, (t.motion(a.position(w)) - b.position(w)).norm() / atlas.diameter);
    atlas.maxTransitionResidual = std::max(atlas.maxTransitionResidual, t.residual);
  }
  double translationError = 0.0, quarterTurnError = 0.0;
  for (const Transition& t : atlas.transitions) {
    translationError = std::max(translationError, std::abs(wrap(t.motion.angle)));
    const double quarters = t.motion.angle / (kPi / 2.0);
    quarterTurnError =
        std::max(quarterTurnError, std::abs(quarters - std::round(quarters)) * kPi / 2.0);
  }
  const double tolerance = options.angleTolerance + atlas.flatnessDefect;
  if (translationError <= tolerance) {
    atlas.kind = TransitionKind::Translation;
    atlas.maxKindAngleError = translationError;
  } else if (quarterTurnError <= tolerance) {
    atlas.kind = TransitionKind::Rotation90;
    atlas.maxKindAngleError = quarterTurnError;
  }

  for (const auto f : mesh.faces()) {
    std::array<int, 3> v;
    int k = 0;
    for (const auto w : mesh.fv_range(f)) v[std::size_t(k++)] = w.idx();
    bool charted = true;
    for (int w : v) charted &= atlas.chartOfVertex[std::size_t(w)] >= 0;
    if (!charted) continue;
    const RigidMotion around = atlas.transition(v[2], v[0])
                                   .after(atlas.transition(v[1], v[2]))
                                   .after(atlas.transition(v[0], v[1]));
    const Chart& chart = atlas.charts[std::size_t(atlas.chartOfVertex[std::size_t(v[0])])];
    for (int w : v) {
      const Eigen::Vector2d x = chart.position(w);
      atlas.maxCocycleResidual =
          std::max(atlas.maxCocycleResidual, (around(x) - x).norm() / atlas.diameter);
    }
  }
}

Eigen::VectorXd atlasEdgeLengths(const TriMesh& mesh, const AffineAtlas& atlas) {
  if (atlas.chartOfVertex.size() != mesh.n_vertices())
    throw InputError("atlas: " + std::to_string(atlas.chartOfVertex.size()) +
                     " vertices, the mesh has " + std::to_string(mesh.n_vertices()));
  Eigen::VectorXd lengths(Eigen::Index(mesh.n_edges()));
  for (const auto e : mesh.edges()) {
    const auto h = mesh.halfedge_handle(e, 0);
    const int a = mesh.from_vertex_handle(h).idx(), b = mesh.to_vertex_handle(h).idx();
    std::vector<int> holders = {a, b};
    for (int side = 0; side < 2; ++side) {
      const auto g = mesh.halfedge_handle(e, side);
      if (!mesh.is_boundary(g))
        holders.push_back(mesh.to_vertex_handle(mesh.next_halfedge_handle(g)).idx());
    }
    int chart = -1;
    for (int w : holders)
      if (chart < 0) chart = atlas.chartOfVertex[std::size_t(w)];
    if (chart < 0) throw InputError("atlas: edge " + std::to_string(e.idx()) + " lies in no chart");
    const Chart& c = atlas.charts[std::size_t(chart)];
    lengths[e.idx()] = (c.position(a) - c.position(b)).norm();
  }
  return lengths;
}

std::vector<ChartPoint> chartsContaining(const TriMesh& mesh, const AffineAtlas& atlas, int face,
                                         const Eigen::Vector3d& barycentric) {
  if (face < 0 || face >= int(mesh.n_faces()))
    throw InputError("atlas: face " + std::to_string(face) + " does not exist");
  std::array<int, 3> v;
  int k = 0;
  for (const auto w : mesh.fv_range(TriMesh::FaceHandle(face))) v[std::size_t(k++)] = w.idx();
  std::vector<ChartPoint> points;
  for (int w : v) {
    const int c = atlas.chartOfVertex[std::size_t(w)];
    if (c < 0) continue;
    const Chart& chart = atlas.charts[std::size_t(c)];
    Eigen::Vector2d x = Eigen::Vector2d::Zero();
    for (int j = 0; j < 3; ++j) x += barycentric[j] * chart.position(v[std::size_t(j)]);
    points.push_back({c, x});
  }
  return points;
}

SurfacePoint locateInChart(const TriMesh& mesh, const AffineAtlas& atlas, int chart,
                           const Eigen::Vector2d& x, double tolerance) {
  if (chart < 0 || chart >= int(atlas.charts.size()))
    throw InputError("atlas: chart " + std::to_string(chart) + " does not exist");
  const Chart& c = atlas.charts[std::size_t(chart)];
  for (int f : c.faces) {
    std::array<Eigen::Vector2d, 3> p;
    int k = 0;
    for (const auto w : mesh.fv_range(TriMesh::FaceHandle(f)))
      p[std::size_t(k++)] = c.position(w.idx());
    const Eigen::Vector2d e1 = p[1] - p[0], e2 = p[2] - p[0], d = x - p[0];
    const double area = e1.x() * e2.y() - e1.y() * e2.x();
    const double b1 = (d.x() * e2.y() - d.y() * e2.x()) / area;
    const double b2 = (e1.x() * d.y() - e1.y() * d.x()) / area;
    const Eigen::Vector3d b(1.0 - b1 - b2, b1, b2);
    if (b.minCoeff() >= -tolerance) return {f, b};
  }
  return {};
}

RigidMotion holonomy(const AffineAtlas& atlas, const std::vector<int>& loop) {
  if (loop.size() < 2) throw InputError("atlas: a loop needs at least two vertices");
  RigidMotion total;
  for (std::size_t k = 0; k < loop.size(); ++k)
    total = atlas.transition(loop[k], loop[(k + 1) % loop.size()]).after(total);
  return total;
}

bool identicalAtlases(const AffineAtlas& a, const AffineAtlas& b) {
  bool identical =
      a.charts.size() == b.charts.size() && a.transitions.size() == b.transitions.size();
  for (std::size_t c = 0; identical && c < a.charts.size(); ++c)
    identical = a.charts[c].vertices == b.charts[c].vertices &&
                a.charts[c].positions == b.charts[c].positions;
  for (std::size_t t = 0; identical && t < a.transitions.size(); ++t)
    identical = a.transitions[t].motion.angle == b.transitions[t].motion.angle &&
                a.transitions[t].motion.translation == b.transitions[t].motion.translation;
  return identical;
}

}  // namespace mspline::structure
