#include "mspline/structure/layout/motorcycle_layout.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <queue>
#include <string>
#include <utility>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"

namespace mspline::structure {

namespace {

constexpr double kQuarter = kPi / 2.0;

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Angle in [0, 2 pi).
double wrapTurn(double angle) {
  angle = std::fmod(angle, 2.0 * kPi);
  return angle < 0.0 ? angle + 2.0 * kPi : angle;
}

struct Motion {
  Eigen::Matrix2d rotation = Eigen::Matrix2d::Identity();
  Eigen::Vector2d translation = Eigen::Vector2d::Zero();
  double angle = 0.0;
  Eigen::Vector2d apply(const Eigen::Vector2d& p) const { return rotation * p + translation; }
  Motion inverse() const {
    const Eigen::Matrix2d back = rotation.transpose();
    return {back, -(back * translation), -angle};
  }
};

// A mesh face in its own coordinates: corner k (the to-vertex of the k-th halfedge from the face's
// halfedge) at `corner[k]`, corner 0 at the origin, corner 1 on the +x axis. Local edge i runs from
// corner i to corner i + 1.
struct FaceGeometry {
  std::array<int, 3> vertex{};
  std::array<Eigen::Vector2d, 3> corner;
  std::array<int, 3> neighbour{};
  std::array<Motion, 3> across;
  /// Angle of the cross field's first axis in the face's coordinates.
  double frame = 0.0;
};

// A straight piece of a trace inside one mesh face, from a to b, at arc lengths s0 to s1.
struct Piece {
  int trace = -1;
  Eigen::Vector2d a, b;
  double s0 = 0.0, s1 = 0.0;
  // A piece along a mesh edge is stored in both faces of the edge: its copy in face twinFace at
  // twinIndex, in coordinates toTwin.apply(·).
  int twinFace = -1, twinIndex = -1;
  Motion toTwin;
};

struct Trace {
  int coneNode = -1;
  int coneIndex = 0;  // which of the cone's axis directions, counter-clockwise
  int face = -1;      // where the trace's tip is
  Eigen::Vector2d tip, direction;
  double length = 0.0;
  bool running = true;
  int endTrace = -1;  // the trace it ended on, at arc length endArc
  double endArc = 0.0;
  // It ended at the end node of this trace instead (met head-on, or crossing the node where two
  // traces met head-on): the node belongs to the trace that stopped first.
  int joinTrace = -1;
  // Its way back from the end node in quarter turns counter-clockwise from the node's reference
  // direction: the forward direction of endTrace (1 from its left, 3 from its right), or the way
  // back of the node's owner when that met a trace head-on (0).
  int endSlot = 0;
  int endNode = -1;
  // Stopped at this mesh vertex, waiting for the traces that reach it at the same arc length.
  int atVertex = -1;
  double back = 0.0;   // its way back there, as an angle around the vertex
  double start = 0.0;  // the angle around its cone at which it leaves
};

// A mesh vertex that traces reach: where the first trace went through it (going on at angle
// `forward` around the vertex), with the first trace that ended on it there; or the trace whose
// end node it is when the first traces to arrive all stopped.
struct VertexVisit {
  std::vector<int> pending;
  int passing = -1;
  double passArc = 0.0, forward = 0.0;
  int ender = -1;
  int owner = -1;
  double ownerBack = 0.0;
};

// The first crossing of the ray p + t d (0 < t <= limit) with segment [a, b]: t and the
// parameter along the segment, or t = -1. None when the sine of their angle is at most
// `parallel`.
std::pair<double, double> rayHit(const Eigen::Vector2d& p, const Eigen::Vector2d& d, double limit,
                                 const Eigen::Vector2d& a, const Eigen::Vector2d& b, double minimum,
                                 double parallel) {
  const Eigen::Vector2d e = b - a;
  const double det = cross(d, e);
  if (std::abs(det) <= parallel * e.norm()) return {-1.0, 0.0};
  const double t = cross(a - p, e) / det, w = cross(a - p, d) / det;
  if (t <= minimum || t > limit || w < -1e-12 || w > 1.0 + 1e-12) return {-1.0, 0.0};
  return {t, std::clamp(w, 0.0, 1.0)};
}

}  // namespace

struct MotorcycleLayout::Data {
  std::vector<FaceGeometry> faces;
  std::vector<std::vector<Piece>> pieces;
  std::vector<Trace> traces;
  std::vector<LayoutNode> nodes;
  std::vector<LayoutSegment> segments;
  std::vector<std::vector<int>> traceSegments;
  std::vector<LayoutRectangle> rectangles;
  std::vector<int> halfedgeRectangle, halfedgeSide;
  std::vector<double> halfedgeOffset;
  double scale = 1.0;

  // The exit of the ray from p along d (unit) in face f: distance, local edge and exit point. An
  // exit within 1e-7 of a corner is moved off it along the side, so that no walk passes through a
  // vertex (where the next face would be ambiguous).
  struct Exit {
    double t = -1.0;
    int edge = -1;
    Eigen::Vector2d point = Eigen::Vector2d::Zero();
    int corner = -1;  // the corner the exit was moved off, if any
  };
  Exit exitOf(int f, const Eigen::Vector2d& p, const Eigen::Vector2d& d) const {
    const FaceGeometry& face = faces[std::size_t(f)];
    Exit exit;
    double along = 0.0;
    for (int i = 0; i < 3; ++i) {
      const auto [t, w] = rayHit(p, d, INFINITY, face.corner[std::size_t(i)],
                                 face.corner[std::size_t((i + 1) % 3)], 1e-12 * scale, 1e-14);
      if (t >= 0.0 && (exit.edge < 0 || t < exit.t)) exit.t = t, exit.edge = i, along = w;
    }
    if (exit.edge >= 0) {
      if (along < 1e-7) exit.corner = exit.edge;
      if (along > 1.0 - 1e-7) exit.corner = (exit.edge + 1) % 3;
      along = std::clamp(along, 1e-7, 1.0 - 1e-7);
      const Eigen::Vector2d& a = face.corner[std::size_t(exit.edge)];
      exit.point = a + along * (face.corner[std::size_t((exit.edge + 1) % 3)] - a);
    }
    return exit;
  }

  // The first trace piece met along p + t d, 0 < t <= limit, in face f.
  struct Hit {
    double t = -1.0;
    int piece = -1;
    double w = 0.0;
  };
  // Where a walk met the first trace, and how far it went.
  struct WalkEnd {
    RectanglePoint point;
    double depth = 0.0;
  };
  std::optional<WalkEnd> walk(int f, Eigen::Vector2d p, Eigen::Vector2d direction) const;

  // The last piece of another trace that runs back along the line p + t d (t > 0) in face f, or
  // in a face across an edge of f that the line runs along (traces along mesh edges are nudged
  // into one face or the other): two traces on one line, which in exact arithmetic meet head-on
  // (traces from cones facing each other, or a trace aimed exactly at a cone, which sends a trace
  // back along the same line). Within 1e-6 of the surface's size and of a radian: the walk moves
  // exits off corners by 1e-7 of an edge.
  struct Facing {
    int face = -1;
    int piece = -1;
    Motion toFace;  // from the piece's face into f's coordinates
  };
  Facing headOn(int f, int self, const Eigen::Vector2d& p, const Eigen::Vector2d& d) const {
    Facing best;
    double nearest = INFINITY;
    const double tolerance = 1e-6 * scale;
    const auto consider = [&](int g, const Motion& toFace) {
      for (std::size_t k = 0; k < pieces[std::size_t(g)].size(); ++k) {
        const Piece& piece = pieces[std::size_t(g)][k];
        const Eigen::Vector2d a = toFace.apply(piece.a), b = toFace.apply(piece.b);
        const double length = (b - a).norm();
        if (piece.trace == self || length <= 0.0 ||
            piece.s1 != traces[std::size_t(piece.trace)].length)
          continue;
        const Eigen::Vector2d q = (b - a) / length;
        if (q.dot(d) >= 0.0 || std::abs(cross(q, d)) > 1e-6) continue;
        if (std::abs(cross(a - p, d)) > tolerance) continue;
        const double ahead = (b - p).dot(d);  // the end nearest to p
        if (ahead < -tolerance || ahead >= nearest) continue;
        best = {g, int(k), toFace};
        nearest = ahead;
      }
    };
    consider(f, Motion{});
    const FaceGeometry& face = faces[std::size_t(f)];
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector2d& a = face.corner[std::size_t(i)];
      const Eigen::Vector2d& b = face.corner[std::size_t((i + 1) % 3)];
      if (std::abs(cross(a - p, d)) <= tolerance && std::abs(cross(b - p, d)) <= tolerance)
        consider(face.neighbour[std::size_t(i)], face.across[std::size_t(i)].inverse());
    }
    return best;
  }

  // A trace from vertex to vertex, or leaving a vertex along an edge (turned 1e-9 off it), runs
  // along that edge: within kOnEdge of the surface's size, it is stored in the faces on both
  // sides, so that traces and walks from either side meet it before they step across the edge.
  static constexpr double kOnEdge = 1e-8;
  void addPiece(int f, int trace, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double s0,
                double s1) {
    Piece piece;
    piece.trace = trace;
    piece.a = a;
    piece.b = b;
    piece.s0 = s0;
    piece.s1 = s1;
    std::vector<Piece>& list = pieces[std::size_t(f)];
    const FaceGeometry& face = faces[std::size_t(f)];
    const double tolerance = kOnEdge * scale;
    for (int i = 0; i < 3 && (b - a).norm() > tolerance; ++i) {
      const Eigen::Vector2d& from = face.corner[std::size_t(i)];
      const Eigen::Vector2d side = (face.corner[std::size_t((i + 1) % 3)] - from).normalized();
      if (std::abs(cross(side, a - from)) > tolerance ||
          std::abs(cross(side, b - from)) > tolerance)
        continue;
      const int g = face.neighbour[std::size_t(i)];
      if (g == f) continue;
      const Motion& m = face.across[std::size_t(i)];
      Piece copy = piece;
      copy.a = m.apply(a);
      copy.b = m.apply(b);
      copy.twinFace = f;
      copy.twinIndex = int(list.size());
      copy.toTwin = m.inverse();
      piece.twinFace = g;
      piece.twinIndex = int(pieces[std::size_t(g)].size());
      piece.toTwin = m;
      pieces[std::size_t(g)].push_back(copy);
      break;
    }
    list.push_back(piece);
  }

  // Piece k of face f now ends at b, arc length s1; so does its copy across an edge.
  void trimPiece(int f, int k, const Eigen::Vector2d& b, double s1) {
    Piece& piece = pieces[std::size_t(f)][std::size_t(k)];
    piece.b = b;
    piece.s1 = s1;
    if (piece.twinFace < 0) return;
    Piece& twin = pieces[std::size_t(piece.twinFace)][std::size_t(piece.twinIndex)];
    twin.b = piece.toTwin.apply(b);
    twin.s1 = s1;
  }

  // The first trace piece met along p + t d, 0 < t <= limit, in face f. A growing trace `self`
  // (-1 for a walk) passes the end of a trace that ended on it there. Pieces up to kOnEdge past
  // the exit count: a piece along the exit edge is met in this face, not missed in both.
  Hit firstPiece(int f, const Eigen::Vector2d& p, const Eigen::Vector2d& d, double limit,
                 int self = -1) const {
    Hit hit;
    for (std::size_t k = 0; k < pieces[std::size_t(f)].size(); ++k) {
      const Piece& piece = pieces[std::size_t(f)][k];
      // Traces within 1e-6 rad of parallel do not cross: they run along each other (headOn).
      const auto [t, w] =
          rayHit(p, d, limit + kOnEdge * scale, piece.a, piece.b, 1e-10 * scale, 1e-6);
      if (t < 0.0 || (hit.t >= 0.0 && t >= hit.t)) continue;
      const Trace& other = traces[std::size_t(piece.trace)];
      if (self >= 0 && other.endTrace == self && piece.s1 == other.length &&
          (1.0 - w) * (piece.s1 - piece.s0) <= 1e-6 * scale)
        continue;
      hit = {t, int(k), w};
    }
    return hit;
  }
};

MotorcycleLayout::~MotorcycleLayout() = default;
MotorcycleLayout::MotorcycleLayout(MotorcycleLayout&&) noexcept = default;
MotorcycleLayout& MotorcycleLayout::operator=(MotorcycleLayout&&) noexcept = default;

const std::vector<LayoutNode>& MotorcycleLayout::nodes() const {
  return data_->nodes;
}
const std::vector<LayoutSegment>& MotorcycleLayout::segments() const {
  return data_->segments;
}
const std::vector<LayoutRectangle>& MotorcycleLayout::rectangles() const {
  return data_->rectangles;
}
const std::vector<int>& MotorcycleLayout::halfedgeRectangle() const {
  return data_->halfedgeRectangle;
}
const std::vector<int>& MotorcycleLayout::halfedgeSide() const {
  return data_->halfedgeSide;
}
const std::vector<double>& MotorcycleLayout::halfedgeOffset() const {
  return data_->halfedgeOffset;
}
int MotorcycleLayout::numTraces() const {
  return int(data_->traces.size());
}
double MotorcycleLayout::totalTraceLength() const {
  double total = 0.0;
  for (const Trace& t : data_->traces) total += t.length;
  return total;
}
double MotorcycleLayout::longestTrace() const {
  double longest = 0.0;
  for (const Trace& t : data_->traces) longest = std::max(longest, t.length);
  return longest;
}

MotorcycleLayout::MotorcycleLayout(const TriMesh& mesh, const Eigen::VectorXd& lengths,
                                   const MotorcycleLayoutOptions& options)
    : data_(std::make_unique<Data>()) {
  Data& d = *data_;
  if (lengths.size() != Eigen::Index(mesh.n_edges()))
    throw InputError("motorcycle layout: " + std::to_string(lengths.size()) + " lengths for " +
                     std::to_string(mesh.n_edges()) + " edges");
  for (const auto h : mesh.halfedges())
    if (mesh.is_boundary(h))
      throw InputError("motorcycle layout: the surface has a boundary (closed surfaces only)");

  // Face coordinates, and which local edge each halfedge is.
  const int faceCount = int(mesh.n_faces());
  d.faces.resize(std::size_t(faceCount));
  std::vector<int> localEdge(mesh.n_halfedges(), -1);
  double area = 0.0;
  for (const auto f : mesh.faces()) {
    FaceGeometry& face = d.faces[std::size_t(f.idx())];
    std::array<OpenMesh::SmartHalfedgeHandle, 3> h;
    h[0] = mesh.halfedge_handle(f);
    h[1] = h[0].next();
    h[2] = h[1].next();
    for (int k = 0; k < 3; ++k) {
      face.vertex[std::size_t(k)] = h[std::size_t(k)].to().idx();
      // h_{k+1} runs from corner k to corner k + 1: local edge k.
      localEdge[std::size_t(h[std::size_t((k + 1) % 3)].idx())] = k;
    }
    const double l01 = lengths[h[1].edge().idx()], l12 = lengths[h[2].edge().idx()],
                 l20 = lengths[h[0].edge().idx()];
    // The height from the area as Kahan computes it: sqrt(l20^2 - x^2) loses the height of the
    // needles the flip overlay has, and their frames turned by 2e-3 rad.
    const double x = (l01 * l01 + l20 * l20 - l12 * l12) / (2.0 * l01);
    face.corner = {Eigen::Vector2d::Zero(), Eigen::Vector2d(l01, 0.0),
                   Eigen::Vector2d(x, fourTimesArea(l01, l12, l20) / (2.0 * l01))};
    area += 0.5 * cross(face.corner[1], face.corner[2]);
  }
  d.scale = std::sqrt(area);
  for (const auto f : mesh.faces()) {
    FaceGeometry& face = d.faces[std::size_t(f.idx())];
    for (const auto h : mesh.fh_range(f)) {
      const int i = localEdge[std::size_t(h.idx())];
      const auto o = h.opp();
      const int g = o.face().idx(), j = localEdge[std::size_t(o.idx())];
      const FaceGeometry& other = d.faces[std::size_t(g)];
      // Corner i of f is corner j + 1 of g, corner i + 1 of f is corner j of g.
      const Eigen::Vector2d u = face.corner[std::size_t((i + 1) % 3)] - face.corner[std::size_t(i)];
      const Eigen::Vector2d v =
          other.corner[std::size_t(j)] - other.corner[std::size_t((j + 1) % 3)];
      Motion& m = face.across[std::size_t(i)];
      m.angle = std::atan2(cross(u, v), u.dot(v));
      m.rotation << std::cos(m.angle), -std::sin(m.angle), std::sin(m.angle), std::cos(m.angle);
      m.translation =
          other.corner[std::size_t((j + 1) % 3)] - m.rotation * face.corner[std::size_t(i)];
      face.neighbour[std::size_t(i)] = g;
    }
  }

  // The cross field: one frame carried across the surface; quarter-turn holonomy keeps its axes
  // consistent.
  {
    std::vector<char> done(std::size_t(faceCount), 0);
    std::vector<int> stack{0};
    done[0] = 1;
    d.faces[0].frame = options.frameAngle;
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      for (int i = 0; i < 3; ++i) {
        const int g = d.faces[std::size_t(f)].neighbour[std::size_t(i)];
        if (done[std::size_t(g)]) continue;
        d.faces[std::size_t(g)].frame =
            d.faces[std::size_t(f)].frame + d.faces[std::size_t(f)].across[std::size_t(i)].angle;
        done[std::size_t(g)] = 1;
        stack.push_back(g);
      }
    }
    double worst = 0.0;
    for (int f = 0; f < faceCount; ++f)
      for (int i = 0; i < 3; ++i) {
        const FaceGeometry& face = d.faces[std::size_t(f)];
        const double r = face.frame + face.across[std::size_t(i)].angle -
                         d.faces[std::size_t(face.neighbour[std::size_t(i)])].frame;
        worst = std::max(worst, std::abs(r - kQuarter * std::round(r / kQuarter)));
      }
    if (worst > options.angleTolerance)
      throw SolverError("motorcycle layout: the holonomy is not made of quarter turns (off by " +
                        std::to_string(worst) + " rad; quantize the cones and the holonomy)");
  }

  // Cones, and the traces leaving them along the axes.
  std::vector<double> angleSum(mesh.n_vertices(), 0.0);
  for (int f = 0; f < faceCount; ++f) {
    const FaceGeometry& face = d.faces[std::size_t(f)];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d a = face.corner[std::size_t((k + 1) % 3)] - face.corner[std::size_t(k)];
      const Eigen::Vector2d b = face.corner[std::size_t((k + 2) % 3)] - face.corner[std::size_t(k)];
      angleSum[std::size_t(face.vertex[std::size_t(k)])] += std::atan2(cross(a, b), a.dot(b));
    }
  }
  // Around a vertex counter-clockwise from its first outgoing halfedge: the corners of its faces,
  // where each corner's first side points, its angle, and the angles of the corners before it.
  struct Sector {
    int face, corner;
    double start, angle, before;
  };
  const auto sectorsAround = [&](int vertex) {
    std::vector<Sector> sectors;
    double around = 0.0;
    const auto first = OpenMesh::make_smart(mesh.vertex_handle(unsigned(vertex)), mesh).out();
    auto h = first;
    do {
      const int f = h.face().idx();
      const FaceGeometry& face = d.faces[std::size_t(f)];
      const int k = localEdge[std::size_t(h.idx())];  // h runs from corner k (v) to corner k + 1
      const Eigen::Vector2d a = face.corner[std::size_t((k + 1) % 3)] - face.corner[std::size_t(k)];
      const Eigen::Vector2d b = face.corner[std::size_t((k + 2) % 3)] - face.corner[std::size_t(k)];
      const double cornerAngle = std::atan2(cross(a, b), a.dot(b));
      sectors.push_back({f, k, std::atan2(a.y(), a.x()), cornerAngle, around});
      around += cornerAngle;
      h = h.prev().opp();
    } while (h != first);
    return sectors;
  };
  // The angle around `vertex` (from its first sector) of `direction` leaving it in face `face`, at
  // the face's corner `corner`.
  const auto angleAround = [&](int vertex, int face, int corner, const Eigen::Vector2d& direction) {
    const std::vector<Sector> sectors = sectorsAround(vertex);
    const auto sector = std::find_if(sectors.begin(), sectors.end(), [&](const Sector& s) {
      return s.face == face && s.corner == corner;
    });
    MSPLINE_ASSERT(sector != sectors.end(), "motorcycle layout: face " + std::to_string(face) +
                                                " is not around vertex " + std::to_string(vertex));
    const FaceGeometry& geometry = d.faces[std::size_t(face)];
    const Eigen::Vector2d side =
        geometry.corner[std::size_t((corner + 1) % 3)] - geometry.corner[std::size_t(corner)];
    return sector->before +
           std::clamp(std::atan2(cross(side, direction), side.dot(direction)), 0.0, sector->angle);
  };
  // A trace leaving the vertex at angle `at` around it starts from the sector holding that angle.
  // Counting along the summed angle gives one trace per direction even when the direction runs
  // along a mesh edge; such a trace is turned 1e-9 into the corner, so that it never runs along an
  // edge.
  const auto leave = [&](const std::vector<Sector>& sectors, double at, Trace& trace) {
    std::size_t s = 0;
    while (s + 1 < sectors.size() && sectors[s + 1].before <= at) ++s;
    const Sector& sector = sectors[s];
    const double offset = std::clamp(at - sector.before, 1e-9, sector.angle - 1e-9);
    trace.face = sector.face;
    trace.tip = d.faces[std::size_t(sector.face)].corner[std::size_t(sector.corner)];
    trace.direction =
        Eigen::Vector2d(std::cos(sector.start + offset), std::sin(sector.start + offset));
  };
  std::vector<int> vertexNode(mesh.n_vertices(), -1);
  std::vector<int> firstConeTrace;  // per node: its cone's traces follow one another from here
  for (const auto v : mesh.vertices()) {
    const double angle = angleSum[std::size_t(v.idx())];
    if (std::abs(angle - 2.0 * kPi) <= options.coneTolerance) continue;
    const int quarterTurns = int(std::lround(angle / kQuarter));
    if (quarterTurns < 1 || std::abs(angle - quarterTurns * kQuarter) > options.angleTolerance)
      throw SolverError("motorcycle layout: vertex " + std::to_string(v.idx()) +
                        " has cone angle " + std::to_string(angle) + ", not a multiple of pi/2");
    // One trace only: both sides of it bound the same rectangle, folded around the cone, and a
    // quad grid cannot have a vertex of valence one.
    if (quarterTurns == 1)
      throw SolverError("motorcycle layout: vertex " + std::to_string(v.idx()) +
                        " is a cone of angle pi/2 (valence one in a quad grid); place cones of "
                        "angle at least pi there");
    const int node = int(d.nodes.size());
    vertexNode[std::size_t(v.idx())] = node;
    d.nodes.push_back({v.idx(), quarterTurns});
    // Trace j leaves at the first axis direction past the first edge, plus j quarter turns.
    const std::vector<Sector> sectors = sectorsAround(v.idx());
    const Sector& firstSector = sectors.front();
    const double firstAxis = std::fmod(
        wrapTurn(d.faces[std::size_t(firstSector.face)].frame - firstSector.start), kQuarter);
    firstConeTrace.push_back(int(d.traces.size()));
    for (int j = 0; j < quarterTurns; ++j) {
      Trace trace;
      trace.coneNode = node;
      trace.coneIndex = j;
      trace.start = firstAxis + j * kQuarter;
      leave(sectors, trace.start, trace);
      d.traces.push_back(trace);
    }
  }
  if (d.nodes.empty())
    throw InputError("motorcycle layout: the metric has no cones (a flat torus needs no layout)");

  // Grow all traces at the same pace, a face at a time; a trace stops where it meets another.
  d.pieces.resize(std::size_t(faceCount));
  const double maxLength = options.maxTraceLength * d.scale;
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (std::size_t t = 0; t < d.traces.size(); ++t) queue.emplace(0.0, int(t));
  // Traces through a mesh vertex pass it exactly, and what happens there is decided once every
  // trace that reaches it at the same arc length has arrived: traces aimed exactly at a vertex
  // (symmetric surfaces: an octahedron's four diagonals meet at the centre of its faces) meet
  // there instead of passing each other a rounding error apart.
  std::vector<VertexVisit> visits(mesh.n_vertices());
  const double sameTime = 1e-6 * d.scale;
  const auto resolveVertex = [&](int t) {
    Trace& trace = d.traces[std::size_t(t)];
    const int v = trace.atVertex;
    VertexVisit& visit = visits[std::size_t(v)];
    const double total = angleSum[std::size_t(v)];
    // Quarter turns counter-clockwise from direction `from` to direction `to` around v.
    const auto turns = [&](double from, double to) {
      const long q = std::lround(4.0 * (to - from) / total) % 4;
      return int(q < 0 ? q + 4 : q);
    };
    std::vector<int> group, later;
    for (int m : visit.pending) {
      const Trace& other = d.traces[std::size_t(m)];
      if (!other.running || other.atVertex != v) continue;
      (std::abs(other.length - trace.length) <= sameTime ? group : later).push_back(m);
    }
    visit.pending = later;
    for (int m : group) d.traces[std::size_t(m)].atVertex = -1;
    // Ending on the trace through v: the first one to do so ends on it, the others at its node.
    const auto endOnPassing = [&](int m) {
      Trace& arriving = d.traces[std::size_t(m)];
      arriving.endSlot = turns(visit.forward, arriving.back);
      if (arriving.endSlot % 2 == 0)
        throw SolverError("motorcycle layout: trace " + std::to_string(m) + " reaches vertex " +
                          std::to_string(v) + " along the trace through it");
      if (visit.ender < 0) {
        arriving.endTrace = visit.passing;
        arriving.endArc = visit.passArc;
        visit.ender = m;
      } else {
        arriving.joinTrace = visit.ender;
      }
      arriving.running = false;
    };
    const auto joinOwner = [&](int m) {
      Trace& arriving = d.traces[std::size_t(m)];
      arriving.joinTrace = visit.owner;
      arriving.endSlot = turns(visit.ownerBack, arriving.back);
      arriving.running = false;
    };
    if (visit.passing >= 0) {
      for (int m : group) endOnPassing(m);
      return;
    }
    if (visit.owner >= 0) {
      for (int m : group) joinOwner(m);
      return;
    }
    // Alone, or with one trace at a right angle: it goes on, and the other ends on it. Otherwise
    // all stop there (a node where no angle exceeds a half turn).
    bool goesOn = true;
    for (int m : group) {
      const int turn = turns(trace.back, d.traces[std::size_t(m)].back);
      goesOn &= m == t || (group.size() == 2 && turn % 2 == 1);
    }
    if (goesOn) {
      visit.passing = t;
      visit.passArc = trace.length;
      visit.forward = std::fmod(trace.back + 0.5 * total, total);
      leave(sectorsAround(v), visit.forward, trace);
      queue.emplace(trace.length, t);
      for (int m : group)
        if (m != t) endOnPassing(m);
      return;
    }
    visit.owner = t;
    visit.ownerBack = trace.back;
    trace.running = false;
    trace.endSlot = 0;
    for (int m : group)
      if (m != t) joinOwner(m);
  };
  // The trace of the cone at corner `corner` of the tip's face that leaves back along the line of
  // `trace` and has not left yet, when the trace reaches that cone within rounding (at `reach`
  // along its direction); else -1.
  const auto coneTraceBack = [&](const Trace& trace, int corner, double reach) {
    if (corner < 0) return -1;
    const FaceGeometry& face = d.faces[std::size_t(trace.face)];
    const int v = face.vertex[std::size_t(corner)];
    const int node = vertexNode[std::size_t(v)];
    if (node < 0) return -1;
    const Eigen::Vector2d toCone = face.corner[std::size_t(corner)] - trace.tip;
    if (std::abs(cross(trace.direction, toCone)) > 1e-6 * d.scale ||
        std::abs(toCone.norm() - reach) > 1e-6 * d.scale)
      return -1;
    const double back = angleAround(v, trace.face, corner, -toCone);
    const int first = firstConeTrace[std::size_t(node)];
    for (int m = first; m < first + d.nodes[std::size_t(node)].quarterTurns; ++m) {
      const Trace& other = d.traces[std::size_t(m)];
      if (other.running && other.length == 0.0 &&
          std::abs(std::remainder(other.start - back, angleSum[std::size_t(v)])) <= 1e-6)
        return m;
    }
    return -1;
  };
  // Trace t stops head-on against `partner` (already stopped) at `end`, `meet` further on: it
  // joins the partner's node, on the side opposite the partner's way in.
  const auto meetHeadOn = [&](int t, int partnerIndex, const Eigen::Vector2d& end, double meet) {
    Trace& trace = d.traces[std::size_t(t)];
    const Trace& partner = d.traces[std::size_t(partnerIndex)];
    d.addPiece(trace.face, t, trace.tip, end, trace.length, trace.length + meet);
    trace.length += meet;
    trace.joinTrace = partner.joinTrace >= 0 ? partner.joinTrace : partnerIndex;
    trace.endSlot = (partner.endSlot + 2) % 4;
    trace.running = false;
  };
  while (!queue.empty()) {
    const int t = queue.top().second;
    queue.pop();
    Trace& trace = d.traces[std::size_t(t)];
    if (!trace.running) continue;  // stopped head-on by another trace
    if (trace.atVertex >= 0) {
      resolveVertex(t);
      continue;
    }
    const Data::Exit exit = d.exitOf(trace.face, trace.tip, trace.direction);
    if (exit.edge < 0)
      throw SolverError("motorcycle layout: trace " + std::to_string(t) + " lost its way in face " +
                        std::to_string(trace.face));
    // Aimed at a vertex within rounding: it goes there exactly, unless the vertex is a cone (whose
    // own trace comes back along the same line and meets this one head-on).
    const int corner = exit.corner;
    const int arrival =
        corner >= 0 && vertexNode[std::size_t(
                           d.faces[std::size_t(trace.face)].vertex[std::size_t(corner)])] < 0
            ? d.faces[std::size_t(trace.face)].vertex[std::size_t(corner)]
            : -1;
    Data::Hit hit = d.firstPiece(trace.face, trace.tip, trace.direction, exit.t, t);
    if (arrival >= 0 && hit.t >= exit.t - sameTime) hit = {};  // decided at the vertex
    // Head-on: where both arc lengths agree when the other still runs (they started together; its
    // piece is trimmed to that point), at its end when it has stopped; unless an ordinary crossing
    // comes clearly first.
    const Data::Facing facing = d.headOn(trace.face, t, trace.tip, trace.direction);
    if (facing.face >= 0) {
      Piece& other = d.pieces[std::size_t(facing.face)][std::size_t(facing.piece)];
      const int partnerIndex = other.trace;
      Trace& partner = d.traces[std::size_t(partnerIndex)];
      const Eigen::Vector2d a = facing.toFace.apply(other.a), b = facing.toFace.apply(other.b);
      const double toEnd = (b - trace.tip).dot(trace.direction);
      const double toStart = (a - trace.tip).dot(trace.direction);
      const double meet = partner.running ? std::clamp(0.5 * (other.s1 + toEnd - trace.length),
                                                       std::max(0.0, toEnd), toStart)
                                          : std::max(0.0, toEnd);
      if (hit.t < 0.0 || meet <= hit.t + 1e-6 * d.scale) {
        const Eigen::Vector2d end = trace.tip + meet * trace.direction;
        if (partner.running) {
          // It stops at the meeting point too; its tip's pending step is dropped.
          const Eigen::Vector2d otherEnd = facing.toFace.inverse().apply(end);
          d.trimPiece(facing.face, facing.piece, otherEnd, other.s0 + (otherEnd - other.a).norm());
          partner.length = other.s1;
          partner.running = false;
          partner.endSlot = 0;
        }
        meetHeadOn(t, partnerIndex, end, meet);
        continue;
      }
    }
    // Aimed exactly at a cone whose trace back along the same line has not left yet (a box's
    // edges: both cross the face in one step, so neither has a piece the other could meet): they
    // meet head-on where their arc lengths agree, unless a crossing comes first or there (then
    // this trace ends on it, and the cone's trace meets this one head-on when it leaves).
    if (const int partnerIndex = coneTraceBack(trace, corner, exit.t); partnerIndex >= 0) {
      const FaceGeometry& face = d.faces[std::size_t(trace.face)];
      const Eigen::Vector2d cone = face.corner[std::size_t(corner)];
      const double distance = (cone - trace.tip).norm();
      const double meet = 0.5 * (distance - trace.length);
      if (meet >= 0.0 && (hit.t < 0.0 || meet < hit.t - 1e-6 * d.scale)) {
        const Eigen::Vector2d end = trace.tip + meet * (cone - trace.tip) / distance;
        Trace& partner = d.traces[std::size_t(partnerIndex)];
        partner.length = distance - meet;
        partner.running = false;
        partner.endSlot = 0;
        d.addPiece(trace.face, partnerIndex, cone, end, 0.0, partner.length);
        meetHeadOn(t, partnerIndex, end, meet);
        continue;
      }
    }
    const Eigen::Vector2d end = hit.t >= 0.0 ? Eigen::Vector2d(trace.tip + hit.t * trace.direction)
                                : arrival >= 0
                                    ? d.faces[std::size_t(trace.face)].corner[std::size_t(corner)]
                                    : exit.point;
    if (hit.t >= 0.0) {
      Piece& other = d.pieces[std::size_t(trace.face)][std::size_t(hit.piece)];
      Trace& target = d.traces[std::size_t(other.trace)];
      const double arc = other.s0 + hit.w * (other.s1 - other.s0);
      const Eigen::Vector2d along = other.b - other.a;
      if (target.running && other.s1 == target.length &&
          arc > trace.length + hit.t + 1e-6 * d.scale) {
        // Its step crossed the whole face, but it reaches the crossing after this trace: it stops
        // on this trace there, and this one goes on (passing its end) at its next step.
        target.endTrace = t;
        target.endArc = trace.length + hit.t;
        target.endSlot = cross(trace.direction, along) < 0.0 ? 1 : 3;
        d.trimPiece(trace.face, hit.piece, end, arc);
        target.length = arc;
        target.running = false;
        queue.emplace(trace.length, t);
        continue;
      }
      trace.endTrace = other.trace;
      trace.endArc = arc;
      trace.endSlot = cross(along, trace.direction) < 0.0 ? 1 : 3;
      trace.running = false;
    }
    const double step = (end - trace.tip).norm();
    d.addPiece(trace.face, t, trace.tip, end, trace.length, trace.length + step);
    trace.length += step;
    if (!trace.running) continue;
    if (trace.length > maxLength)
      throw SolverError("motorcycle layout: trace " + std::to_string(t) + " from vertex " +
                        std::to_string(d.nodes[std::size_t(trace.coneNode)].vertex) +
                        " meets no other trace within " + std::to_string(options.maxTraceLength) +
                        " times the surface's size");
    if (arrival >= 0) {
      trace.back = angleAround(arrival, trace.face, corner, -trace.direction);
      trace.atVertex = arrival;
      visits[std::size_t(arrival)].pending.push_back(t);
      queue.emplace(trace.length, t);
      continue;
    }
    const Motion& m = d.faces[std::size_t(trace.face)].across[std::size_t(exit.edge)];
    trace.tip = m.apply(end);
    trace.direction = (m.rotation * trace.direction).normalized();
    trace.face = d.faces[std::size_t(trace.face)].neighbour[std::size_t(exit.edge)];
    queue.emplace(trace.length, t);
  }

  // A trace that ended where the trace it met stopped head-on crosses the two there: it ends at
  // their node, and so do the traces that met it head-on. Their ways back were counted from the
  // forward direction of the trace met, which is opposite to its way back.
  for (std::size_t t = 0; t < d.traces.size(); ++t) {
    Trace& trace = d.traces[t];
    if (trace.endTrace < 0) continue;
    const Trace& met = d.traces[std::size_t(trace.endTrace)];
    if (met.endTrace >= 0 || met.length - trace.endArc > 1e-6 * d.scale) continue;
    const int owner = met.joinTrace >= 0 ? met.joinTrace : trace.endTrace;
    if (owner == int(t))
      throw SolverError("motorcycle layout: trace " + std::to_string(t) +
                        " and the trace it ended on met each other's ends");
    const int shift = met.endSlot + 2;
    for (Trace& other : d.traces)
      if (other.joinTrace == int(t)) {
        other.joinTrace = owner;
        other.endSlot = (other.endSlot + shift) % 4;
      }
    trace.joinTrace = owner;
    trace.endSlot = (trace.endSlot + shift) % 4;
    trace.endTrace = -1;
  }

  // The graph: nodes at cones and trace ends, segments between consecutive nodes of a trace.
  for (Trace& trace : d.traces) {
    if (trace.joinTrace >= 0) continue;
    trace.endNode = int(d.nodes.size());
    d.nodes.push_back({-1, 4});
  }
  for (Trace& trace : d.traces)
    if (trace.joinTrace >= 0) trace.endNode = d.traces[std::size_t(trace.joinTrace)].endNode;
  std::vector<std::vector<std::pair<double, int>>> breaks(d.traces.size());
  for (std::size_t t = 0; t < d.traces.size(); ++t) {
    const Trace& trace = d.traces[t];
    breaks[t].emplace_back(0.0, trace.coneNode);
    breaks[t].emplace_back(trace.length, trace.endNode);
    if (trace.endTrace < 0) continue;
    if (trace.endArc > d.traces[std::size_t(trace.endTrace)].length)
      throw SolverError("motorcycle layout: trace " + std::to_string(t) +
                        " ended on a trace at a point that trace never reached");
    breaks[std::size_t(trace.endTrace)].emplace_back(trace.endArc, trace.endNode);
  }
  // Outgoing half-edges at each node with their angle (quarter turns, counter-clockwise).
  std::vector<std::vector<std::pair<int, int>>> outgoing(d.nodes.size());
  d.traceSegments.resize(d.traces.size());
  for (std::size_t t = 0; t < d.traces.size(); ++t) {
    auto& list = breaks[t];
    std::sort(list.begin(), list.end());
    for (std::size_t k = 0; k + 1 < list.size(); ++k) {
      if (list[k + 1].first - list[k].first <= 1e-12 * d.scale)
        throw SolverError("motorcycle layout: two nodes coincide on trace " + std::to_string(t));
      const int s = int(d.segments.size());
      d.segments.push_back(
          {int(t), list[k].first, list[k + 1].first, list[k].second, list[k + 1].second});
      d.traceSegments[t].push_back(s);
    }
  }
  for (std::size_t t = 0; t < d.traces.size(); ++t) {
    const Trace& trace = d.traces[t];
    const auto& own = d.traceSegments[t];
    outgoing[std::size_t(trace.coneNode)].emplace_back(trace.coneIndex, 2 * own.front());
    // At the end node: its way back, and the trace it ended on runs on at 0 and back at 2.
    outgoing[std::size_t(trace.endNode)].emplace_back(trace.endSlot, 2 * own.back() + 1);
    if (trace.endTrace < 0) continue;
    for (int s : d.traceSegments[std::size_t(trace.endTrace)]) {
      if (d.segments[std::size_t(s)].from == trace.endNode)
        outgoing[std::size_t(trace.endNode)].emplace_back(0, 2 * s);
      if (d.segments[std::size_t(s)].to == trace.endNode)
        outgoing[std::size_t(trace.endNode)].emplace_back(2, 2 * s + 1);
    }
  }
  std::vector<int> nextOf(2 * d.segments.size(), -1), turnAt(2 * d.segments.size(), 0);
  for (std::size_t n = 0; n < d.nodes.size(); ++n) {
    auto& list = outgoing[n];
    std::sort(list.begin(), list.end());
    const int total = d.nodes[n].quarterTurns;
    // A cone: one trace per quarter turn. Elsewhere two (traces met head-on), three (a trace
    // ended on another) or four (and one met it head-on), at distinct angles.
    bool distinct = true;
    for (std::size_t k = 1; k < list.size(); ++k) distinct &= list[k].first != list[k - 1].first;
    const bool fits =
        d.nodes[n].vertex >= 0 ? list.size() == std::size_t(total) : list.size() >= 2 && distinct;
    if (!fits)
      throw SolverError("motorcycle layout: node " + std::to_string(n) + " has " +
                        std::to_string(list.size()) + " traces leaving it");
    for (std::size_t k = 0; k < list.size(); ++k) {
      // Arriving along the reverse of list[k], the face on the left leaves along the next
      // half-edge clockwise.
      const auto& previous = list[(k + list.size() - 1) % list.size()];
      const int arriving = list[k].second ^ 1;
      nextOf[std::size_t(arriving)] = previous.second;
      int turn = list[k].first - previous.first;
      if (turn <= 0) turn += total;
      turnAt[std::size_t(arriving)] = turn;
    }
  }

  // Faces of the graph: each must be a rectangle (four corners of one quarter turn, straight
  // elsewhere).
  d.halfedgeRectangle.assign(nextOf.size(), -1);
  d.halfedgeSide.assign(nextOf.size(), -1);
  d.halfedgeOffset.assign(nextOf.size(), 0.0);
  for (std::size_t start = 0; start < nextOf.size(); ++start) {
    if (d.halfedgeRectangle[start] >= 0) continue;
    std::vector<int> cycle;
    int he = int(start);
    do {
      cycle.push_back(he);
      d.halfedgeRectangle[std::size_t(he)] = int(d.rectangles.size());
      he = nextOf[std::size_t(he)];
    } while (he != int(start) && cycle.size() <= nextOf.size());
    int corners = 0, bad = 0;
    for (int e : cycle) {
      corners += turnAt[std::size_t(e)] == 1;
      bad += turnAt[std::size_t(e)] != 1 && turnAt[std::size_t(e)] != 2;
    }
    if (corners != 4 || bad != 0)
      throw SolverError("motorcycle layout: face " + std::to_string(d.rectangles.size()) +
                        " of the trace graph is not a rectangle (" + std::to_string(corners) +
                        " corners" + (bad ? ", a reflex or full turn" : "") + ")");
    // Start right after a corner.
    std::size_t first = 0;
    while (turnAt[std::size_t(cycle[(first + cycle.size() - 1) % cycle.size()])] != 1) ++first;
    LayoutRectangle rectangle;
    int side = 0;
    double offset = 0.0;
    for (std::size_t k = 0; k < cycle.size(); ++k) {
      const int e = cycle[(first + k) % cycle.size()];
      rectangle.sides[std::size_t(side)].push_back(e);
      d.halfedgeSide[std::size_t(e)] = side;
      d.halfedgeOffset[std::size_t(e)] = offset;
      offset += d.segments[std::size_t(e / 2)].length();
      if (turnAt[std::size_t(e)] == 1) {
        rectangle.sideLength[std::size_t(side)] = offset;
        offset = 0.0;
        ++side;
      }
    }
    // Opposite sides differ by rounding, or by 1e-8 where traces met head-on; more means the
    // graph missed a crossing (traces that meet at a point where several events coincide).
    const double mismatch = std::max(std::abs(rectangle.sideLength[0] - rectangle.sideLength[2]),
                                     std::abs(rectangle.sideLength[1] - rectangle.sideLength[3]));
    if (mismatch > 1e-4 * d.scale)
      throw SolverError("motorcycle layout: face " + std::to_string(d.rectangles.size()) +
                        " of the trace graph has opposite sides " + std::to_string(mismatch) +
                        " apart (traces crossed where the graph has no node)");
    d.rectangles.push_back(rectangle);
  }
}

// Walks from p in face f along `direction` to the first trace: the rectangle point there, or
// nothing when the walk loses its way (a sliver face) or meets no trace.
std::optional<MotorcycleLayout::Data::WalkEnd> MotorcycleLayout::Data::walk(
    int f, Eigen::Vector2d p, Eigen::Vector2d direction) const {
  const Data& d = *this;
  double travelled = 0.0;
  // The distance bound ends every walk that moves; crossings without moving (through a vertex)
  // end after visiting every face.
  std::size_t standing = 0;
  for (;;) {
    const Data::Exit exit = d.exitOf(f, p, direction);
    if (exit.edge < 0) return std::nullopt;
    const Data::Hit hit = d.firstPiece(f, p, direction, exit.t);
    if (hit.t >= 0.0) {
      const Piece& piece = d.pieces[std::size_t(f)][std::size_t(hit.piece)];
      const double arc = piece.s0 + hit.w * (piece.s1 - piece.s0);
      const bool fromLeft = cross(piece.b - piece.a, direction) < 0.0;
      const auto& list = d.traceSegments[std::size_t(piece.trace)];
      // The segment of the trace holding `arc`.
      std::size_t k = 0;
      while (k + 1 < list.size() && d.segments[std::size_t(list[k])].end < arc) ++k;
      const LayoutSegment& segment = d.segments[std::size_t(list[k])];
      const int he = 2 * list[k] + (fromLeft ? 0 : 1);
      const double along =
          d.halfedgeOffset[std::size_t(he)] + (fromLeft ? arc - segment.start : segment.end - arc);
      const double depth = travelled + hit.t;
      RectanglePoint point;
      point.rectangle = d.halfedgeRectangle[std::size_t(he)];
      point.side = d.halfedgeSide[std::size_t(he)];
      point.alongSide = along;
      const LayoutRectangle& r = d.rectangles[std::size_t(point.rectangle)];
      const double w = r.width(), h = r.height();
      switch (point.side) {
        case 0:
          point.position = {along, depth};
          break;
        case 1:
          point.position = {w - depth, along};
          break;
        case 2:
          point.position = {w - along, h - depth};
          break;
        default:
          point.position = {depth, h - along};
          break;
      }
      point.position =
          point.position.cwiseMax(Eigen::Vector2d::Zero()).cwiseMin(Eigen::Vector2d(w, h));
      return WalkEnd{point, depth};
    }
    const double step = (exit.point - p).norm();
    travelled += step;
    standing = step > 0.0 ? 0 : standing + 1;
    if (travelled > 100.0 * d.scale || standing > d.faces.size()) return std::nullopt;
    const Motion& m = d.faces[std::size_t(f)].across[std::size_t(exit.edge)];
    p = m.apply(exit.point);
    direction = (m.rotation * direction).normalized();
    f = d.faces[std::size_t(f)].neighbour[std::size_t(exit.edge)];
  }
}

RectanglePoint MotorcycleLayout::locate(int face, const Eigen::Vector3d& barycentric) const {
  const Data& d = *data_;
  if (face < 0 || face >= int(d.faces.size()))
    throw InputError("motorcycle layout: face " + std::to_string(face) + " out of range");
  // A hair (1e-6 of the face) inside, walking along the four axis directions. The shortest walk
  // is kept: in exact arithmetic every walk ends on the point's rectangle, but a long one can
  // step past a trace that runs within rounding of the point (the slivers between nearly
  // coincident traces: ellipsoid.off's equator landed 20% of the diagonal away).
  const auto inside = [&](int f, Eigen::Vector3d b) {
    const FaceGeometry& g = d.faces[std::size_t(f)];
    b = b.cwiseMax(0.0);
    b = (1.0 - 1e-6) * b / b.sum() + Eigen::Vector3d::Constant(1e-6 / 3.0);
    return Eigen::Vector2d(b[0] * g.corner[0] + b[1] * g.corner[1] + b[2] * g.corner[2]);
  };
  const auto nearestWalk = [&](int f, const Eigen::Vector2d& p) {
    std::optional<Data::WalkEnd> nearest;
    const double frame = d.faces[std::size_t(f)].frame;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d axis(std::cos(frame + k * kQuarter), std::sin(frame + k * kQuarter));
      const auto end = d.walk(f, p, axis);
      if (end && (!nearest || end->depth < nearest->depth)) nearest = end;
    }
    return nearest;
  };
  // A sliver face of an overlay (1e-11 thin) can let no walk out: then the same point from the
  // faces across its edges that pass within a hair of it, and so on, a few faces at most.
  std::vector<std::pair<int, Eigen::Vector2d>> queue{{face, inside(face, barycentric)}};
  std::vector<int> visited{face};
  for (std::size_t next = 0; next < queue.size() && next < 16; ++next) {
    const auto [f, p] = queue[next];
    if (const auto end = nearestWalk(f, p)) return end->point;
    const FaceGeometry& g = d.faces[std::size_t(f)];
    double size = 0.0;
    for (int i = 0; i < 3; ++i) size = std::max(size, (g.corner[std::size_t(i)] - p).norm());
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector2d& a = g.corner[std::size_t(i)];
      const Eigen::Vector2d e = g.corner[std::size_t((i + 1) % 3)] - a;
      const int across = g.neighbour[std::size_t(i)];
      if (std::abs(cross(e, p - a)) > 1e-5 * size * e.norm() ||
          std::find(visited.begin(), visited.end(), across) != visited.end())
        continue;
      visited.push_back(across);
      // The point in the neighbour's coordinates, moved a hair into it.
      const FaceGeometry& h = d.faces[std::size_t(across)];
      const Eigen::Vector2d q = g.across[std::size_t(i)].apply(p);
      const Eigen::Vector2d e1 = h.corner[1] - h.corner[0], e2 = h.corner[2] - h.corner[0];
      const double det = cross(e1, e2);
      Eigen::Vector2d uv = Eigen::Vector2d::Constant(1.0 / 3.0);
      if (det != 0.0)
        uv = Eigen::Vector2d(cross(q - h.corner[0], e2), cross(e1, q - h.corner[0])) / det;
      queue.emplace_back(across, inside(across, Eigen::Vector3d(1.0 - uv.sum(), uv[0], uv[1])));
    }
  }
  throw SolverError("motorcycle layout: no walk from face " + std::to_string(face) +
                    " reaches a trace");
}

}  // namespace mspline::structure
