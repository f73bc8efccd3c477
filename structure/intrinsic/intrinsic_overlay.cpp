#include "mspline/structure/intrinsic/intrinsic_overlay.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>

#include <Eigen/Dense>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"

namespace mspline::structure {

namespace {

using Vec2 = Eigen::Vector2d;

double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Barycentric coordinates (1 - beta, beta) on an edge of an ideal triangle become proportional to
// (exp(-du0) (1 - beta), exp(-du1) beta) when the decoration changes by du0, du1 at its ends.
double rescale(double beta, double du0, double du1) {
  if (beta <= 0.0) return 0.0;
  if (beta >= 1.0) return 1.0;
  return 1.0 / (1.0 + std::exp(du1 - du0) * (1.0 - beta) / beta);
}

// Where an input edge crosses an intrinsic edge.
struct Crossing {
  int inputEdge = -1;
  // -1 once the intrinsic edge has been flipped away.
  int intrinsicEdge = -1;
  // Barycentric weight of the intrinsic edge's second vertex (edgeVertices), in the input's
  // decoration u = 0.
  double alongIntrinsic = 0.0;
  // Barycentric weight of the input edge's to-vertex (of its halfedge 0): at u = 0 the fraction
  // of its Euclidean length.
  double alongInput = 0.0;
  // Its place in edgeCrossings_ of its intrinsic edge.
  int rankOnEdge = -1;
};

// End of a segment inside a face: the corner at tip(slot) when crossing < 0, otherwise a crossing
// on the side of halfedge slot `slot`.
struct End {
  int slot = -1;
  int crossing = -1;
};

// A piece of an input edge inside an intrinsic face.
struct Segment {
  int inputEdge = -1;
  End a, b;
};

class FlipReplay {
 public:
  explicit FlipReplay(const TriMesh& input)
      : input_(input),
        tri_(input),
        edgeCrossings_(input.n_edges()),
        faceSegments_(input.n_faces()),
        coincidentInput_(input.n_edges()) {
    for (std::size_t e = 0; e < coincidentInput_.size(); ++e) coincidentInput_[e] = int(e);
  }

  void flip(int e);
  IntrinsicOverlay overlay(const Eigen::VectorXd& u, const Eigen::VectorXd& lengths) const;

 private:
  // Weight of tip(slot) for crossing c on the side of slot.
  double towardTip(int slot, int c) const {
    const double beta = crossings_[std::size_t(c)].alongIntrinsic;
    return tri_.halfedge(tri_.edge(slot)) == slot ? beta : 1.0 - beta;
  }
  // Place of crossing c among the crossings on the side of slot, counted from tail(slot).
  int rankOnSide(int slot, int c) const {
    const std::vector<int>& onEdge = edgeCrossings_[std::size_t(tri_.edge(slot))];
    const int rank = crossings_[std::size_t(c)].rankOnEdge;
    if (rank < 0 || rank >= int(onEdge.size()) || onEdge[std::size_t(rank)] != c)
      throw InternalError("overlay: a segment ends off its face");
    return tri_.halfedge(tri_.edge(slot)) == slot ? rank : int(onEdge.size()) - 1 - rank;
  }
  // alongInput at a segment end (0 or 1 at a corner: the input edge's endpoints).
  double inputWeight(const End& end, int inputEdge) const {
    if (end.crossing >= 0) return crossings_[std::size_t(end.crossing)].alongInput;
    const auto h = input_.halfedge_handle(input_.edge_handle(inputEdge), 0);
    return tri_.tip(end.slot) == input_.to_vertex_handle(h).idx() ? 1.0 : 0.0;
  }

  const TriMesh& input_;
  IntrinsicTriangulation tri_;
  std::vector<Crossing> crossings_;
  // The crossings on each intrinsic edge, in their order from tail to tip of halfedge(edge).
  std::vector<std::vector<int>> edgeCrossings_;
  std::vector<std::vector<Segment>> faceSegments_;
  // The input edge an intrinsic edge coincides with, or -1.
  std::vector<int> coincidentInput_;
};

void FlipReplay::flip(int e) {
  const int a0 = tri_.halfedge(e);
  const int b0 = tri_.twin(a0);
  if (b0 < 0 || a0 / 3 == b0 / 3)
    throw InternalError("overlay: edge " + std::to_string(e) + " cannot be flipped");
  const int a1 = tri_.next(a0), a2 = tri_.prev(a0), b1 = tri_.next(b0), b2 = tri_.prev(b0);
  const int faceA = a0 / 3, faceB = b0 / 3;
  // Quad corners 0 = i, 1 = j, 2 = k, 3 = l; A = (i, j, k), B = (j, i, l), as in
  // IntrinsicTriangulation::flip.
  const auto corner = [&](int slot) {
    if (slot == a2 || slot == b0) return 0;
    if (slot == a0 || slot == b2) return 1;
    return slot == a1 ? 2 : 3;
  };
  // A local decoration du (per corner, relative to u = 0) that makes A equilateral and inscribed
  // in the unit circle; B then lies on the circle too, with l where the ideal gluing along ij
  // puts it (the ratio of its distances to i and j is the ratio of lengths at du).
  const Eigen::VectorXd& lambda = tri_.logLengths0();
  const double half = 0.5 * std::log(3.0);
  const double sij = half - lambda[e], sjk = half - lambda[tri_.edge(a1)],
               ski = half - lambda[tri_.edge(a2)];
  std::array<double, 4> du = {sij + ski - sjk, sij + sjk - ski, sjk + ski - sij, 0.0};
  const double lil = lambda[tri_.edge(b1)], llj = lambda[tri_.edge(b2)];
  const double rho = std::exp(lil - llj + 0.5 * (du[0] - du[1]));
  const double phi = std::atan2(rho * std::sqrt(3.0), 2.0 + rho);
  const double theta = 7.0 * kPi / 6.0 + 2.0 * phi;
  const std::array<Vec2, 4> p = {Vec2(-0.5 * std::sqrt(3.0), -0.5),
                                 Vec2(0.5 * std::sqrt(3.0), -0.5), Vec2(0.0, 1.0),
                                 Vec2(std::cos(theta), std::sin(theta))};
  du[3] = 2.0 * (std::log(2.0 * std::sin(phi)) - lil) - du[0];

  const auto position = [&](const End& end) -> Vec2 {
    if (end.crossing < 0) return p[std::size_t(corner(end.slot))];
    const int tail = corner(tri_.prev(end.slot)), tip = corner(end.slot);
    const double mu =
        rescale(towardTip(end.slot, end.crossing), du[std::size_t(tail)], du[std::size_t(tip)]);
    return (1.0 - mu) * p[std::size_t(tail)] + mu * p[std::size_t(tip)];
  };

  // The straight pieces of input edges through the quadrilateral: segments of A and B, joined at
  // their crossings with the diagonal.
  std::vector<Segment> pieces;
  std::unordered_map<int, End> beyondDiagonal;  // diagonal crossing -> other end of its B segment
  for (const Segment& s : faceSegments_[std::size_t(faceB)]) {
    if (s.a.crossing >= 0 && s.a.slot == b0)
      beyondDiagonal[s.a.crossing] = s.b;
    else if (s.b.crossing >= 0 && s.b.slot == b0)
      beyondDiagonal[s.b.crossing] = s.a;
    else
      pieces.push_back(s);
  }
  for (const Segment& s : faceSegments_[std::size_t(faceA)]) {
    const bool atA = s.a.crossing >= 0 && s.a.slot == a0;
    const bool atB = s.b.crossing >= 0 && s.b.slot == a0;
    if (!atA && !atB) {
      pieces.push_back(s);
      continue;
    }
    const int c = atA ? s.a.crossing : s.b.crossing;
    const auto it = beyondDiagonal.find(c);
    if (it == beyondDiagonal.end())
      throw InternalError("overlay: a diagonal crossing has no continuation");
    pieces.push_back({s.inputEdge, atA ? s.b : s.a, it->second});
    beyondDiagonal.erase(it);
  }
  if (!beyondDiagonal.empty()) throw InternalError("overlay: a diagonal crossing has no segment");
  if (coincidentInput_[std::size_t(e)] >= 0)
    pieces.push_back({coincidentInput_[std::size_t(e)], End{a2, -1}, End{a0, -1}});
  for (int c : edgeCrossings_[std::size_t(e)]) {
    crossings_[std::size_t(c)].intrinsicEdge = -1;
    crossings_[std::size_t(c)].rankOnEdge = -1;
  }
  edgeCrossings_[std::size_t(e)].clear();
  coincidentInput_[std::size_t(e)] = -1;
  faceSegments_[std::size_t(faceA)].clear();
  faceSegments_[std::size_t(faceB)].clear();

  // After the flip A = (l -> k, k -> i, i -> l) in slots a0, a1, a2 and B = (k -> l, l -> j,
  // j -> k) in b0, b1, b2: the sides move with their contents.
  const auto newSide = [&](int slot) {
    if (slot == a1) return b2;
    if (slot == a2) return a1;
    return slot == b1 ? a2 : b1;
  };
  const auto newEnd = [&](const End& end, bool inA) -> End {
    if (end.crossing >= 0) return {newSide(end.slot), end.crossing};
    switch (corner(end.slot)) {
      case 0:
        return {a1, -1};
      case 1:
        return {b1, -1};
      case 2:
        return {inA ? a0 : b2, -1};
      default:
        return {inA ? a2 : b0, -1};
    }
  };
  // Which face of the flipped quadrilateral holds a piece, and whether it crosses the new diagonal
  // k l, is decided by where its ends lie (input edges do not cross one another): +1 on i's side
  // (the new A), -1 on j's side (the new B), 0 at k or l. Positions serve only to place crossings.
  const auto sideOf = [&](const End& end) {
    if (end.crossing < 0) {
      const int c = corner(end.slot);
      return c == 0 ? 1 : c == 1 ? -1 : 0;
    }
    if (end.slot == a2 || end.slot == b1) return 1;
    if (end.slot == a1 || end.slot == b2) return -1;
    throw InternalError("overlay: a segment ends on the flipped edge");
  };
  // Order of an end along the boundary path k -> i -> l (side +1) or k -> j -> l (side -1): pieces
  // that do not cross one another cross k l in the order of their ends on both paths.
  const auto along = [&](const End& end) -> std::pair<int, int> {
    if (end.crossing < 0) return {1, 0};
    const int rank = rankOnSide(end.slot, end.crossing);
    if (end.slot == a2) return {0, rank};
    if (end.slot == b1) return {2, rank};
    return {end.slot == a1 ? 0 : 2, -rank};
  };
  struct DiagonalCrossing {
    std::pair<int, int> onSideI, onSideJ;
    double s;  // where it crosses, l = 0 to k = 1, from the positions
    int id;
  };
  std::vector<DiagonalCrossing> onDiagonal;

  const Vec2& k = p[2];
  const Vec2& l = p[3];
  const Vec2 diagonal = k - l;
  const double sideOfI = cross(diagonal, p[0] - l) > 0.0 ? 1.0 : -1.0;
  for (Segment piece : pieces) {
    // Orient the piece along its input edge.
    double wa = inputWeight(piece.a, piece.inputEdge), wb = inputWeight(piece.b, piece.inputEdge);
    if (wa > wb) {
      std::swap(piece.a, piece.b);
      std::swap(wa, wb);
    }
    const int sa = sideOf(piece.a), sb = sideOf(piece.b);
    if (sa == 0 && sb == 0) {
      coincidentInput_[std::size_t(e)] = piece.inputEdge;
      continue;
    }
    if (sa * sb >= 0) {
      const bool inA = sa + sb > 0;
      faceSegments_[std::size_t(inA ? faceA : faceB)].push_back(
          {piece.inputEdge, newEnd(piece.a, inA), newEnd(piece.b, inA)});
      continue;
    }
    // The piece crosses the new diagonal at x = pa + t (pb - pa) = l + s (k - l); distances to
    // the diagonal that rounding puts on the wrong side count as 0.
    const Vec2 pa = position(piece.a), pb = position(piece.b);
    const double da = std::max(0.0, sa * sideOfI * cross(diagonal, pa - l));
    const double db = std::max(0.0, sb * sideOfI * cross(diagonal, pb - l));
    const double t = da + db > 0.0 ? da / (da + db) : 0.5;
    const Vec2 d = pb - pa;
    const Vec2 x = pa + t * d;
    const double s = std::clamp((x - l).dot(diagonal) / diagonal.squaredNorm(), 0.0, 1.0);
    // Weight of the input edge's end along the chord between the two points where the piece's
    // line meets the circle (its ideal endpoints), then calibrated at a point of known weight:
    // the two parametrizations of one geodesic differ by a rescaling of the ends.
    const double qa = d.squaredNorm(), qb = pa.dot(d), qc = pa.squaredNorm() - 1.0;
    double tLow, tHigh;
    const bool cornerA = piece.a.crossing < 0, cornerB = piece.b.crossing < 0;
    if (cornerA && cornerB) {
      tLow = 0.0;
      tHigh = 1.0;
    } else if (cornerA) {
      tLow = 0.0;
      tHigh = -2.0 * qb / qa;
    } else if (cornerB) {
      tHigh = 1.0;
      tLow = -2.0 * qb / qa - 1.0;
    } else {
      const double root = std::sqrt(std::max(0.0, qb * qb - qa * qc));
      const double q = -(qb + std::copysign(root, qb));
      const double r0 = q / qa, r1 = q != 0.0 ? qc / q : -r0;
      tLow = std::min(r0, r1);
      tHigh = std::max(r0, r1);
    }
    const auto chordWeight = [&](double at) { return (at - tLow) / (tHigh - tLow); };
    double logRatio;  // log of w_b / w_a in alongInput = w_b m / (w_a (1 - m) + w_b m)
    if (cornerA && cornerB) {
      logRatio = du[std::size_t(corner(piece.b.slot))] - du[std::size_t(corner(piece.a.slot))];
    } else {
      const double ma = chordWeight(0.0), mb = chordWeight(1.0);
      const bool useA = !cornerA && (cornerB || std::abs(ma - 0.5) <= std::abs(mb - 0.5));
      const double m = useA ? ma : mb, w = useA ? wa : wb;
      logRatio = std::log(w / (1.0 - w)) + std::log((1.0 - m) / m);
    }
    const double m = chordWeight(t);
    double alongInput = 1.0 / (1.0 + std::exp(-logRatio) * (1.0 - m) / m);
    // Near-degenerate pieces (ends almost at one point, or almost on the circle): between the
    // piece's ends, where the input edge must cross.
    if (!std::isfinite(alongInput)) alongInput = wa + t * (wb - wa);
    alongInput = std::clamp(alongInput, wa, wb);
    const int id = int(crossings_.size());
    crossings_.push_back({piece.inputEdge, e, 0.0, alongInput});
    const bool aInA = sa > 0;
    onDiagonal.push_back({along(aInA ? piece.a : piece.b), along(aInA ? piece.b : piece.a), s, id});
    faceSegments_[std::size_t(aInA ? faceA : faceB)].push_back(
        {piece.inputEdge, newEnd(piece.a, aInA), End{aInA ? a0 : b0, id}});
    faceSegments_[std::size_t(aInA ? faceB : faceA)].push_back(
        {piece.inputEdge, End{aInA ? b0 : a0, id}, newEnd(piece.b, !aInA)});
  }
  // The new edge runs l -> k (IntrinsicTriangulation::flip keeps halfedge(e) = a0): its crossings
  // in their order from l, which is the reverse of their order from k on both paths, and the
  // positions, sorted, handed out in that order so that rounding cannot reorder them.
  std::sort(onDiagonal.begin(), onDiagonal.end(),
            [](const DiagonalCrossing& x, const DiagonalCrossing& y) {
              return std::tie(y.onSideI, y.onSideJ) < std::tie(x.onSideI, x.onSideJ);
            });
  std::vector<double> positions;
  for (const DiagonalCrossing& c : onDiagonal) positions.push_back(c.s);
  std::sort(positions.begin(), positions.end());
  for (std::size_t n = 0; n < onDiagonal.size(); ++n) {
    const int id = onDiagonal[n].id;
    crossings_[std::size_t(id)].alongIntrinsic = rescale(positions[n], -du[3], -du[2]);
    crossings_[std::size_t(id)].rankOnEdge = int(edgeCrossings_[std::size_t(e)].size());
    edgeCrossings_[std::size_t(e)].push_back(id);
  }
  tri_.flip(e);
}

IntrinsicOverlay FlipReplay::overlay(const Eigen::VectorXd& u,
                                     const Eigen::VectorXd& lengths) const {
  const int vertices = int(input_.n_vertices());
  IntrinsicOverlay out;
  out.flips = tri_.flipCount();
  for (const auto v : input_.vertices()) out.mesh.add_vertex(input_.point(v));
  std::vector<int> crossingVertex(crossings_.size(), -1);
  for (std::size_t c = 0; c < crossings_.size(); ++c) {
    const Crossing& x = crossings_[c];
    if (x.intrinsicEdge < 0) continue;
    const auto h = input_.halfedge_handle(input_.edge_handle(x.inputEdge), 0);
    const auto from = input_.point(input_.from_vertex_handle(h));
    const auto to = input_.point(input_.to_vertex_handle(h));
    crossingVertex[c] = out.mesh.add_vertex(from + x.alongInput * (to - from)).idx();
    out.crossingInputEdge.push_back(x.inputEdge);
  }

  struct Node {
    int slot;      // corner at tip(slot), or the side a crossing lies on
    int crossing;  // -1 for a corner
    Vec2 uv;
    int vertex;                // overlay vertex
    std::vector<int> targets;  // ccw: next on the boundary, chords, previous on the boundary
  };
  std::vector<std::array<Vec2, 3>> faceUV;
  std::vector<std::array<int, 3>> faceVertices;
  for (int f = 0; f < tri_.faceCount(); ++f) {
    // The triangle at u, corner tip(3f + 2) at the origin and side 3f along the x axis.
    const double l0 = lengths[tri_.edge(3 * f)], l1 = lengths[tri_.edge(3 * f + 1)],
                 l2 = lengths[tri_.edge(3 * f + 2)];
    const double x = (l0 * l0 + l2 * l2 - l1 * l1) / (2.0 * l0);
    const std::array<Vec2, 3> cornerUV = {
        Vec2(l0, 0.0), Vec2(x, std::sqrt(std::max(0.0, l2 * l2 - x * x))), Vec2(0.0, 0.0)};
    std::vector<Node> nodes;
    std::unordered_map<int, int> crossingNode;
    std::array<int, 3> cornerNode{};
    for (int side = 0; side < 3; ++side) {
      const int s = 3 * f + side;
      const int before = (side + 2) % 3;
      cornerNode[std::size_t(before)] = int(nodes.size());
      nodes.push_back(
          {3 * f + before, -1, cornerUV[std::size_t(before)], tri_.tip(3 * f + before), {}});
      // From tail(s) to tip(s).
      std::vector<int> along = edgeCrossings_[std::size_t(tri_.edge(s))];
      if (tri_.halfedge(tri_.edge(s)) != s) std::reverse(along.begin(), along.end());
      for (int c : along) {
        const double mu = rescale(towardTip(s, c), u[tri_.tail(s)], u[tri_.tip(s)]);
        crossingNode[c * 3 + side] = int(nodes.size());
        nodes.push_back(
            {s,
             c,
             (1.0 - mu) * cornerUV[std::size_t(before)] + mu * cornerUV[std::size_t(side)],
             crossingVertex[std::size_t(c)],
             {}});
      }
    }
    const int n = int(nodes.size());
    const auto nodeOf = [&](const End& end) {
      if (end.crossing < 0) return cornerNode[std::size_t(end.slot % 3)];
      const auto it = crossingNode.find(end.crossing * 3 + end.slot % 3);
      if (it == crossingNode.end()) throw InternalError("overlay: a segment ends off its face");
      return it->second;
    };
    std::vector<std::vector<int>> chords(nodes.size());
    for (const Segment& segment : faceSegments_[std::size_t(f)]) {
      const int na = nodeOf(segment.a), nb = nodeOf(segment.b);
      chords[std::size_t(na)].push_back(nb);
      chords[std::size_t(nb)].push_back(na);
    }
    for (int a = 0; a < n; ++a) {
      auto& chord = chords[std::size_t(a)];
      // Chords from a corner end on the opposite side, in ccw order along it.
      std::sort(chord.begin(), chord.end());
      if (nodes[std::size_t(a)].crossing >= 0 && chord.size() > 1)
        throw InternalError("overlay: two input edges through one crossing");
      auto& targets = nodes[std::size_t(a)].targets;
      targets.push_back((a + 1) % n);
      targets.insert(targets.end(), chord.begin(), chord.end());
      targets.push_back((a + n - 1) % n);
    }
    // Trace the cells, interior on the left: arriving at b from a, leave along the edge just
    // clockwise of b -> a.
    std::vector<std::vector<char>> used(nodes.size());
    for (int a = 0; a < n; ++a)
      used[std::size_t(a)].assign(nodes[std::size_t(a)].targets.size(), 0);
    for (int a = 0; a < n; ++a) {
      for (std::size_t start = 0; start + 1 < nodes[std::size_t(a)].targets.size(); ++start) {
        if (used[std::size_t(a)][start]) continue;
        std::vector<int> cell;
        int from = a;
        std::size_t slot = start;
        while (!used[std::size_t(from)][slot]) {
          used[std::size_t(from)][slot] = 1;
          cell.push_back(from);
          const int to = nodes[std::size_t(from)].targets[slot];
          const auto& back = nodes[std::size_t(to)].targets;
          const auto found = std::find(back.begin(), back.end(), from);
          if (found == back.begin() || found == back.end())
            throw InternalError("overlay: inconsistent cell boundary");
          slot = std::size_t(found - back.begin()) - 1;
          from = to;
        }
        if (from != a || slot != start || cell.size() < 3)
          throw InternalError("overlay: a cell does not close");
        for (std::size_t q = 1; q + 1 < cell.size(); ++q) {
          const std::array<int, 3> corners = {cell[0], cell[q], cell[q + 1]};
          std::array<Vec2, 3> uv;
          std::array<int, 3> vs;
          for (int r = 0; r < 3; ++r) {
            uv[std::size_t(r)] = nodes[std::size_t(corners[std::size_t(r)])].uv;
            vs[std::size_t(r)] = nodes[std::size_t(corners[std::size_t(r)])].vertex;
          }
          out.degenerateCells += !(cross(uv[1] - uv[0], uv[2] - uv[0]) > 0.0);
          faceUV.push_back(uv);
          faceVertices.push_back(vs);
          out.intrinsicFace.push_back(f);
        }
      }
    }
  }

  // The input face of each cell: the one incident to all its vertices and crossing edges.
  const auto incident = [&](int overlayVertex, OpenMesh::FaceHandle face) {
    if (overlayVertex < vertices) {
      for (const auto v : input_.fv_range(face))
        if (v.idx() == overlayVertex) return true;
      return false;
    }
    const int edge = out.crossingInputEdge[std::size_t(overlayVertex - vertices)];
    for (const auto e : input_.fe_range(face))
      if (e.idx() == edge) return true;
    return false;
  };
  out.edgeLengths = Eigen::VectorXd::Constant(Eigen::Index(3 * faceVertices.size()), -1.0);
  for (std::size_t t = 0; t < faceVertices.size(); ++t) {
    const auto& vs = faceVertices[t];
    std::vector<OpenMesh::FaceHandle> candidates;
    const int anchor = *std::max_element(vs.begin(), vs.end());
    if (anchor >= vertices) {
      const auto e = input_.edge_handle(out.crossingInputEdge[std::size_t(anchor - vertices)]);
      for (int side = 0; side < 2; ++side) {
        const auto face = input_.face_handle(input_.halfedge_handle(e, side));
        if (face.is_valid()) candidates.push_back(face);
      }
    } else {
      for (const auto face : input_.vf_range(OpenMesh::VertexHandle(anchor)))
        candidates.push_back(face);
    }
    candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                    [&](OpenMesh::FaceHandle face) {
                                      for (int v : vs)
                                        if (!incident(v, face)) return true;
                                      return false;
                                    }),
                     candidates.end());
    if (candidates.size() != 1)
      throw InternalError("overlay: a cell lies in " + std::to_string(candidates.size()) +
                          " input faces");
    out.inputFace.push_back(candidates.front().idx());
    const auto face =
        out.mesh.add_face(OpenMesh::VertexHandle(vs[0]), OpenMesh::VertexHandle(vs[1]),
                          OpenMesh::VertexHandle(vs[2]));
    if (!face.is_valid()) throw InternalError("overlay: the common subdivision is not a manifold");
    for (int r = 0; r < 3; ++r) {
      const auto h = out.mesh.find_halfedge(OpenMesh::VertexHandle(vs[std::size_t(r)]),
                                            OpenMesh::VertexHandle(vs[std::size_t((r + 1) % 3)]));
      const Eigen::Index edge = out.mesh.edge_handle(h).idx();
      const double length =
          (faceUV[t][std::size_t((r + 1) % 3)] - faceUV[t][std::size_t(r)]).norm();
      double& stored = out.edgeLengths[edge];
      if (stored < 0.0)
        stored = length;
      else
        out.maxLengthMismatch =
            std::max(out.maxLengthMismatch, std::abs(stored - length) / std::max(stored, length));
    }
  }
  out.edgeLengths.conservativeResize(Eigen::Index(out.mesh.n_edges()));
  return out;
}

}  // namespace

IntrinsicOverlay intrinsicOverlay(const TriMesh& input, const std::vector<int>& flips,
                                  const Eigen::VectorXd& u, const Eigen::VectorXd& lengths) {
  if (u.size() != Eigen::Index(input.n_vertices()))
    throw InputError("overlay: " + std::to_string(u.size()) + " scale factors for " +
                     std::to_string(input.n_vertices()) + " vertices");
  if (lengths.size() != Eigen::Index(input.n_edges()))
    throw InputError("overlay: " + std::to_string(lengths.size()) + " intrinsic edge lengths for " +
                     std::to_string(input.n_edges()) + " edges");
  FlipReplay replay(input);
  for (int e : flips) {
    if (e < 0 || e >= int(input.n_edges()))
      throw InputError("overlay: flip of edge " + std::to_string(e) + ", which does not exist");
    replay.flip(e);
  }
  return replay.overlay(u, lengths);
}

std::vector<SurfacePoint> pointsOnOverlay(const TriMesh& input, const IntrinsicOverlay& overlay,
                                          const std::vector<SurfacePoint>& points) {
  std::vector<std::vector<int>> pieces(input.n_faces());
  for (std::size_t g = 0; g < overlay.inputFace.size(); ++g)
    pieces[overlay.inputFace[g]].push_back(static_cast<int>(g));
  std::vector<SurfacePoint> mapped;
  for (const SurfacePoint& point : points) {
    const Eigen::Vector3d x = surfacePosition(input, point);
    SurfacePoint best;
    double bestWorst = -std::numeric_limits<double>::infinity();
    for (int g : pieces[point.face]) {
      const Eigen::Vector3d q0 = surfacePosition(overlay.mesh, {g, Eigen::Vector3d(1, 0, 0)});
      const Eigen::Vector3d e1 = surfacePosition(overlay.mesh, {g, Eigen::Vector3d(0, 1, 0)}) - q0;
      const Eigen::Vector3d e2 = surfacePosition(overlay.mesh, {g, Eigen::Vector3d(0, 0, 1)}) - q0;
      Eigen::Matrix2d gram;
      gram << e1.dot(e1), e1.dot(e2), e1.dot(e2), e2.dot(e2);
      const Eigen::Vector2d beta = gram.inverse() * Eigen::Vector2d(e1.dot(x - q0), e2.dot(x - q0));
      const Eigen::Vector3d b(1.0 - beta.sum(), beta.x(), beta.y());
      if (b.minCoeff() > bestWorst) {
        bestWorst = b.minCoeff();
        best = {g, b};
      }
    }
    best.barycentric = best.barycentric.cwiseMax(0.0);
    best.barycentric /= best.barycentric.sum();
    mapped.push_back(best);
  }
  return mapped;
}

}  // namespace mspline::structure
