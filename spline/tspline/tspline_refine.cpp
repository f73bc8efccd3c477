#include "mspline/spline/tspline/tspline_refine.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>

#include <Eigen/QR>

#include "mspline/spline/tspline/tspline_cap.h"
#include "mspline/structure/core/errors.h"

namespace mspline::spline {

using structure::InputError;

namespace {

double faceTolerance(const TMeshFace& face) {
  return 1e-9 * std::max(face.width, face.height);
}

bool isCorner(const TMeshFace& face, const Eigen::Vector2d& p, double tolerance) {
  return (std::abs(p.x()) <= tolerance || std::abs(p.x() - face.width) <= tolerance) &&
         (std::abs(p.y()) <= tolerance || std::abs(p.y() - face.height) <= tolerance);
}

int vertexAt(const TMeshFace& face, const Eigen::Vector2d& p, double tolerance) {
  for (std::size_t k = 0; k < face.positions.size(); ++k)
    if ((face.positions[k] - p).cwiseAbs().maxCoeff() <= tolerance) return static_cast<int>(k);
  return -1;
}

// The boundary edge of `face` that holds p strictly inside, or -1.
int edgeHolding(const TMeshFace& face, const Eigen::Vector2d& p, double tolerance) {
  const std::size_t n = face.positions.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector2d& a = face.positions[k];
    const Eigen::Vector2d& b = face.positions[(k + 1) % n];
    for (int axis = 0; axis < 2; ++axis) {
      const int other = 1 - axis;
      if (std::abs(a[other] - p[other]) > tolerance || std::abs(b[other] - p[other]) > tolerance)
        continue;
      if (p[axis] > std::min(a[axis], b[axis]) + tolerance &&
          p[axis] < std::max(a[axis], b[axis]) - tolerance)
        return static_cast<int>(k);
    }
  }
  return -1;
}

void insertVertex(TMeshFace& face, const Eigen::Vector2d& p, int id) {
  const int k = edgeHolding(face, p, faceTolerance(face));
  MSPLINE_ASSERT(k >= 0, "a cut's endpoint lies on no side of the neighbouring face");
  face.vertices.insert(face.vertices.begin() + k + 1, id);
  face.positions.insert(face.positions.begin() + k + 1, p);
}

struct SplitDetail {
  TMesh mesh;
  /// The coordinate actually cut at (moved onto a reused vertex).
  double coordinate = 0.0;
  /// The cut's endpoints.
  std::array<int, 2> ends{};
};

SplitDetail splitFaceDetailed(const TMesh& mesh, int face, int axis, double coordinate) {
  if (face < 0 || face >= mesh.numFaces())
    throw InputError("split: face " + std::to_string(face) + " out of range (the T-mesh has " +
                     std::to_string(mesh.numFaces()) + " faces)");
  if (axis != 0 && axis != 1)
    throw InputError("split: axis " + std::to_string(axis) + " is neither 0 (x) nor 1 (y)");
  const TMeshFace& original = mesh.faces[face];
  const double size = axis == 0 ? original.width : original.height;
  const double tolerance = faceTolerance(original);
  if (!(coordinate > tolerance && coordinate < size - tolerance))
    throw InputError("split: coordinate " + std::to_string(coordinate) +
                     " is not strictly inside (0, " + std::to_string(size) + ") of face " +
                     std::to_string(face));
  const auto endpoints = [&](double c) {
    return axis == 0 ? std::array<Eigen::Vector2d, 2>{Eigen::Vector2d(c, 0.0),
                                                      Eigen::Vector2d(c, original.height)}
                     : std::array<Eigen::Vector2d, 2>{Eigen::Vector2d(original.width, c),
                                                      Eigen::Vector2d(0.0, c)};
  };
  // An existing vertex near an endpoint takes the cut onto it.
  for (const Eigen::Vector2d& end : endpoints(coordinate)) {
    const int k = vertexAt(original, end, tolerance);
    if (k >= 0) {
      coordinate = original.positions[k][axis];
      break;
    }
  }
  const std::array<Eigen::Vector2d, 2> ends = endpoints(coordinate);

  std::vector<TMeshFace> faces = mesh.faces;
  int numVertices = mesh.numVertices;
  SplitDetail detail;
  detail.coordinate = coordinate;
  for (int e = 0; e < 2; ++e) {
    const int k = vertexAt(original, ends[e], tolerance);
    if (k >= 0) {
      detail.ends[e] = original.vertices[k];
      continue;
    }
    const int id = numVertices++;
    detail.ends[e] = id;
    const int edge = edgeHolding(original, ends[e], tolerance);
    MSPLINE_ASSERT(edge >= 0, "a cut's endpoint lies on no side of its face");
    insertVertex(faces[face], ends[e], id);
    if (original.twinFace[edge] >= 0)
      insertVertex(faces[original.twinFace[edge]], mesh.acrossEdge(face, edge).apply(ends[e]), id);
  }

  // The boundary walk from (0, 0) meets ends[0] before ends[1]: the first part is the walk with
  // the stretch between them left out, the second part that stretch.
  const TMeshFace whole = faces[face];
  const int a = vertexAt(whole, ends[0], tolerance), b = vertexAt(whole, ends[1], tolerance);
  MSPLINE_ASSERT(a > 0 && b > a, "the cut's endpoints are out of order on the face boundary");
  const Eigen::Vector2d shift =
      axis == 0 ? Eigen::Vector2d(coordinate, 0.0) : Eigen::Vector2d(0.0, coordinate);
  TMeshFace first, second;
  const auto take = [&](TMeshFace& part, int k, const Eigen::Vector2d& origin) {
    part.vertices.push_back(whole.vertices[k]);
    part.positions.push_back(whole.positions[k] - origin);
  };
  for (int k = 0; k <= a; ++k) take(first, k, Eigen::Vector2d::Zero());
  for (int k = b; k < static_cast<int>(whole.vertices.size()); ++k)
    take(first, k, Eigen::Vector2d::Zero());
  if (axis == 0) {
    for (int k = a; k <= b; ++k) take(second, k, shift);
  } else {
    // The second part's frame starts at ends[1] = (0, coordinate).
    take(second, b, shift);
    for (int k = a; k < b; ++k) take(second, k, shift);
  }
  faces[face] = std::move(first);
  faces.push_back(std::move(second));
  detail.mesh = buildTMesh(numVertices, std::move(faces));
  return detail;
}

// A blending function's knots as ray distances: +s, +t, -s, -t, nearest first.
std::array<std::array<double, 2>, 4> rays(const TSplineAnchor& a) {
  return {{{a.sKnots[3], a.sKnots[4]},
           {a.tKnots[3], a.tKnots[4]},
           {-a.sKnots[1], -a.sKnots[0]},
           {-a.tKnots[1], -a.tKnots[0]}}};
}

// The refinement in progress: the T-mesh, where its faces lie in the input, and the cuts' ends.
struct Refining {
  TMesh mesh;
  std::vector<RefinedFaceOrigin> origin;
  std::vector<int> cutEnds;

  void split(int face, int axis, double coordinate) {
    SplitDetail detail = splitFaceDetailed(mesh, face, axis, coordinate);
    mesh = std::move(detail.mesh);
    RefinedFaceOrigin moved = origin[face];
    moved.offset[axis] += detail.coordinate;
    origin.push_back(moved);
    for (int end : detail.ends)
      if (std::find(cutEnds.begin(), cutEnds.end(), end) == cutEnds.end()) cutEnds.push_back(end);
  }

  // Cuts every face that has a cut's end as a T-junction inside one of its sides, on through
  // that end; returns the number of faces cut.
  int extend() {
    int cuts = 0;
    const std::vector<int> ends = cutEnds;
    for (int vertex : ends) {
      for (int f = 0; f < mesh.numFaces(); ++f) {
        const TMeshFace& face = mesh.faces[f];
        const auto it = std::find(face.vertices.begin(), face.vertices.end(), vertex);
        if (it == face.vertices.end()) continue;
        const Eigen::Vector2d p = face.positions[it - face.vertices.begin()];
        const double tolerance = faceTolerance(face);
        if (isCorner(face, p, tolerance)) continue;
        const bool onBottomOrTop =
            std::abs(p.y()) <= tolerance || std::abs(p.y() - face.height) <= tolerance;
        split(f, onBottomOrTop ? 0 : 1, onBottomOrTop ? p.x() : p.y());
        ++cuts;
        break;
      }
    }
    return cuts;
  }
};

// One least-squares round: the coefficients of the refined space and how well they reproduce the
// input surface.
struct Solution {
  Eigen::MatrixXd homogeneous;  // rows per refined function: (w c, w)
  int changed = 0, unknowns = 0, samples = 0;
  double residual = 0.0;
};

class Reexpression {
 public:
  Reexpression(const TSplineSpace& input, const Eigen::MatrixXd& homogeneous,
               const Refining& refined, const TSplineSpace& space)
      : input_(input), p_(homogeneous), refined_(refined), space_(space) {
    parts_.resize(input.mesh().faces.size());
    for (int f = 0; f < space.mesh().numFaces(); ++f) parts_[refined.origin[f].face].push_back(f);
  }

  Solution solve() const {
    const int oldCount = input_.numBasis(), newCount = space_.numBasis();
    const int inputVertices = input_.mesh().numVertices;
    Solution solution;
    solution.homogeneous = Eigen::MatrixXd::Zero(newCount, p_.cols());
    // Which input functions changed, and which refined functions are unknowns.
    std::vector<char> changed(static_cast<std::size_t>(oldCount), 0);
    std::vector<int> column(static_cast<std::size_t>(newCount), -1);
    for (int a = 0; a < oldCount; ++a) {
      const int b = space_.anchorOfVertex()[input_.anchors()[a].vertex];
      if (b >= 0 && sameFunction(a, b))
        solution.homogeneous.row(b) = p_.row(a);
      else
        changed[a] = 1, ++solution.changed;
    }
    for (int b = 0; b < newCount; ++b) {
      const int vertex = space_.anchors()[b].vertex;
      const int a = vertex < inputVertices ? input_.anchorOfVertex()[vertex] : -1;
      if (a < 0 || changed[a]) column[b] = solution.unknowns++;
    }
    if (solution.changed == 0 && solution.unknowns == 0) return solution;

    // The refined faces where a changed or unknown function lives.
    const TMesh& mesh = space_.mesh();
    std::vector<char> affected(mesh.faces.size(), 0);
    for (int f = 0; f < mesh.numFaces(); ++f) {
      for (const TSplinePiece& piece : space_.pieces(f))
        if (column[piece.anchor] >= 0) affected[f] = 1;
      for (const TSplinePiece& piece : input_.pieces(refined_.origin[f].face))
        if (changed[piece.anchor]) affected[f] = 1;
      // A cap face is one polynomial over the whole face: no knot lines, sampled whole.
      if (const TSplineCapFace* cap = space_.capFace(f))
        for (int a : cap->anchors) affected[f] |= column[a] >= 0;
      if (const TSplineCapFace* cap = input_.capFace(refined_.origin[f].face))
        for (int a : cap->anchors) affected[f] |= changed[a];
    }

    // Gauss-Legendre nodes: 4 x 4 distinct points determine a bicubic on an element.
    const std::array<double, 4> nodes{0.0694318442029737, 0.3300094782075719, 0.6699905217924281,
                                      0.9305681557970263};
    std::vector<Eigen::VectorXd> rowsA, rowsB;
    std::vector<TSplineBasisValue> basis;
    for (int f = 0; f < mesh.numFaces(); ++f) {
      if (!affected[f]) continue;
      const RefinedFaceOrigin& origin = refined_.origin[f];
      std::array<std::vector<double>, 2> lines;
      for (const TSplinePiece& piece : space_.pieces(f))
        if (column[piece.anchor] >= 0)
          addKnotLines(space_.anchors()[piece.anchor], piece.toChart, Eigen::Vector2d::Zero(),
                       lines);
      for (const TSplinePiece& piece : input_.pieces(origin.face))
        if (changed[piece.anchor])
          addKnotLines(input_.anchors()[piece.anchor], piece.toChart, origin.offset, lines);
      const TMeshFace& face = mesh.faces[f];
      const std::array<std::vector<double>, 2> cuts{elementCuts(lines[0], face.width, face),
                                                    elementCuts(lines[1], face.height, face)};
      for (std::size_t i = 0; i + 1 < cuts[0].size(); ++i)
        for (std::size_t j = 0; j + 1 < cuts[1].size(); ++j)
          for (double u : nodes)
            for (double v : nodes) {
              const Eigen::Vector2d p(cuts[0][i] + u * (cuts[0][i + 1] - cuts[0][i]),
                                      cuts[1][j] + v * (cuts[1][j + 1] - cuts[1][j]));
              Eigen::VectorXd a = Eigen::VectorXd::Zero(solution.unknowns);
              space_.basisAt(f, p, basis);
              for (const TSplineBasisValue& value : basis)
                if (column[value.anchor] >= 0) a[column[value.anchor]] += value.value;
              Eigen::VectorXd target = Eigen::VectorXd::Zero(p_.cols());
              input_.basisAt(origin.face, p + origin.offset, basis);
              for (const TSplineBasisValue& value : basis)
                if (changed[value.anchor]) target += value.value * p_.row(value.anchor).transpose();
              rowsA.push_back(std::move(a));
              rowsB.push_back(std::move(target));
            }
    }
    solution.samples = static_cast<int>(rowsA.size());
    Eigen::MatrixXd a(solution.samples, solution.unknowns), b(solution.samples, p_.cols());
    for (int r = 0; r < solution.samples; ++r) {
      a.row(r) = rowsA[r].transpose();
      b.row(r) = rowsB[r].transpose();
    }
    Eigen::MatrixXd x = Eigen::MatrixXd::Zero(solution.unknowns, p_.cols());
    if (solution.unknowns > 0 && solution.samples > 0) x = a.colPivHouseholderQr().solve(b);
    const double scale = std::max(p_.cwiseAbs().maxCoeff(), 1e-300);
    solution.residual = solution.samples > 0 ? (a * x - b).cwiseAbs().maxCoeff() / scale : 0.0;
    for (int c = 0; c < newCount; ++c)
      if (column[c] >= 0) solution.homogeneous.row(c) = x.row(column[c]);
    return solution;
  }

 private:
  // The same function in both spaces: the input function's knots, turned into the refined
  // function's chart, are its knots.
  bool sameFunction(int a, int b) const {
    const TSplineAnchor& oldAnchor = input_.anchors()[a];
    const TSplineAnchor& newAnchor = space_.anchors()[b];
    const int vertex = oldAnchor.vertex;
    const TMeshFace& chartFace = input_.mesh().faces[oldAnchor.chartFace];
    const int k =
        static_cast<int>(std::find(chartFace.vertices.begin(), chartFace.vertices.end(), vertex) -
                         chartFace.vertices.begin());
    const Eigen::Vector2d anchorInChartFace = chartFace.positions[k];
    const TMesh& mesh = space_.mesh();
    // The part of the chart face at the anchor, and the motion from it into the new chart.
    for (int f : parts_[oldAnchor.chartFace]) {
      const TMeshFace& face = mesh.faces[f];
      const Eigen::Vector2d p = anchorInChartFace - refined_.origin[f].offset;
      if (vertexAt(face, p, faceTolerance(face)) < 0) continue;
      for (const TSplinePiece& piece : space_.pieces(f)) {
        if (piece.anchor != b || piece.toChart.apply(p).norm() > faceTolerance(face)) continue;
        const auto oldRays = rays(oldAnchor), newRays = rays(newAnchor);
        const double tolerance =
            1e-9 * std::max(1.0, std::abs(oldAnchor.sKnots[0]) + std::abs(oldAnchor.sKnots[4]) +
                                     std::abs(oldAnchor.tKnots[0]) + std::abs(oldAnchor.tKnots[4]));
        for (int d = 0; d < 4; ++d) {
          const auto& mine = oldRays[d];
          const auto& theirs = newRays[(d + piece.toChart.quarterTurns) & 3];
          if (std::abs(mine[0] - theirs[0]) > tolerance ||
              std::abs(mine[1] - theirs[1]) > tolerance)
            return false;
        }
        return true;
      }
      return false;
    }
    return false;
  }

  // The knot lines of a function (with `toChart` from a frame that is `offset` away from the
  // face's frame), into lines[0] (x = const) and lines[1] (y = const) of the face.
  static void addKnotLines(const TSplineAnchor& anchor, const QuarterMotion& toChart,
                           const Eigen::Vector2d& offset,
                           std::array<std::vector<double>, 2>& lines) {
    const FaceKnots2d knots = knotsInFace(anchor, toChart);
    for (std::size_t i = 0; i < 5; ++i) {
      lines[0].push_back(knots.xKnots[i] - offset.x());
      lines[1].push_back(knots.yKnots[i] - offset.y());
    }
  }

  // 0, the lines strictly inside (0, size) merged within the face tolerance, size.
  static std::vector<double> elementCuts(std::vector<double> lines, double size,
                                         const TMeshFace& face) {
    const double tolerance = faceTolerance(face);
    std::sort(lines.begin(), lines.end());
    std::vector<double> cuts{0.0};
    for (double x : lines)
      if (x > cuts.back() + tolerance && x < size - tolerance) cuts.push_back(x);
    cuts.push_back(size);
    return cuts;
  }

  const TSplineSpace& input_;
  const Eigen::MatrixXd& p_;
  const Refining& refined_;
  const TSplineSpace& space_;
  /// Per input face, the refined faces it was cut into.
  std::vector<std::vector<int>> parts_;
};

}  // namespace

// The cells within 2 of the cone, kCapCells - 1 a sector side: split, they hold the cap's 3 x 3
// half cells, with the T-junctions at 4.
std::vector<int> withTouchedCapsSplit(const TMesh& mesh,
                                      const std::vector<TSplineCapRegion>& regions,
                                      std::vector<int> faces) {
  std::vector<char> split(mesh.faces.size(), 0);
  for (int f : faces) split[std::size_t(f)] = 1;
  std::vector<char> closed(regions.size(), 0);
  for (bool grown = true; grown;) {
    grown = false;
    for (std::size_t r = 0; r < regions.size(); ++r) {
      if (closed[r]) continue;
      bool touched = false;
      for (const auto& cells : regions[r].cells)
        for (const DevelopedFace& cell : cells) {
          const TMeshFace& face = mesh.faces[std::size_t(cell.face)];
          touched = touched || split[std::size_t(cell.face)];
          for (int twin : face.twinFace)
            touched = touched || (twin >= 0 && split[std::size_t(twin)]);
        }
      if (!touched) continue;
      closed[r] = 1;
      grown = true;
      for (const auto& cells : regions[r].cells)
        for (int b = 0; b + 1 < kCapCells; ++b)
          for (int a = 0; a + 1 < kCapCells; ++a) {
            const int f = cells[std::size_t(kCapCells * b + a)].face;
            if (split[std::size_t(f)]) continue;
            split[std::size_t(f)] = 1;
            faces.push_back(f);
          }
    }
  }
  return faces;
}

void splitIntoFour(TMesh& mesh, const std::vector<int>& faces, std::vector<FacePoint>& points) {
  // Splitting the faces one by one rebuilt the whole mesh three times per face (femur's caps:
  // 52 s for 3,200 faces). The vertices are made here in the order those splits made them, on the
  // faces' boundaries with every neighbour's insertions, and each face is cut into its four parts
  // at the end: the same mesh, rebuilt once.
  struct Cut {
    double x = 0.0, yLeft = 0.0, yRight = 0.0;
    int centre = -1;
  };
  std::vector<TMeshFace> boundaries = mesh.faces;
  std::vector<Cut> cuts(faces.size());
  std::vector<int> cutOf(mesh.faces.size(), -1);
  int numVertices = mesh.numVertices;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const int face = faces[i];
    if (face < 0 || face >= mesh.numFaces() || cutOf[std::size_t(face)] >= 0)
      throw InputError("split into four: face " + std::to_string(face) +
                       " is out of range or listed twice");
    cutOf[std::size_t(face)] = int(i);
    const TMeshFace& original = mesh.faces[std::size_t(face)];
    TMeshFace& boundary = boundaries[std::size_t(face)];
    const double tolerance = faceTolerance(original);
    // A cut's end on a side: an existing vertex, or a new one on this face's side and its
    // neighbour's.
    const auto endOnSide = [&](const Eigen::Vector2d& p) {
      if (vertexAt(boundary, p, tolerance) >= 0) return;
      const int id = numVertices++;
      insertVertex(boundary, p, id);
      const int edge = edgeHolding(original, p, tolerance);
      MSPLINE_ASSERT(edge >= 0, "a cut's endpoint lies on no side of its face");
      const int twin = original.twinFace[std::size_t(edge)];
      if (twin >= 0)
        insertVertex(boundaries[std::size_t(twin)], mesh.acrossEdge(face, edge).apply(p), id);
    };
    // A cut through the middle moves onto a vertex within the tolerance at one of its ends (the
    // horizontal cut's right half onto the centre, unless the right side has one).
    const auto vertexNear = [&](double x, double y) {
      return vertexAt(boundary, Eigen::Vector2d(x, y), tolerance);
    };
    const double w = original.width, h = original.height;
    Cut& cut = cuts[i];
    int k = vertexNear(0.5 * w, 0.0);
    if (k < 0) k = vertexNear(0.5 * w, h);
    cut.x = k >= 0 ? boundary.positions[std::size_t(k)].x() : 0.5 * w;
    endOnSide({cut.x, 0.0});
    endOnSide({cut.x, h});
    k = vertexNear(0.0, 0.5 * h);
    cut.yLeft = k >= 0 ? boundary.positions[std::size_t(k)].y() : 0.5 * h;
    cut.centre = numVertices++;
    endOnSide({0.0, cut.yLeft});
    k = vertexNear(w, 0.5 * h);
    cut.yRight = k >= 0 ? boundary.positions[std::size_t(k)].y() : cut.yLeft;
    endOnSide({w, cut.yRight});
  }

  // The quarters: the lower left keeps the face's id and frame; the lower right, upper left and
  // upper right are appended in that order.
  std::vector<TMeshFace> result = std::move(boundaries);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const TMeshFace boundary = std::move(result[std::size_t(faces[i])]);
    const Cut& cut = cuts[i];
    const double w = boundary.width, h = boundary.height;
    // Vertices moved onto within the face's tolerance can be twice that off the cut lines.
    const double tolerance = 4.0 * faceTolerance(boundary);
    std::vector<int> ids = boundary.vertices;
    std::vector<Eigen::Vector2d> positions = boundary.positions;
    ids.push_back(cut.centre);
    positions.emplace_back(cut.x, cut.yLeft);
    const auto quarter = [&](double x0, double x1, double y0, double y1) {
      // Every vertex on the rectangle's boundary, by its distance walked counter-clockwise from
      // (x0, y0).
      std::vector<std::pair<double, std::size_t>> walk;
      for (std::size_t k = 0; k < ids.size(); ++k) {
        const Eigen::Vector2d& p = positions[k];
        const bool inX = p.x() >= x0 - tolerance && p.x() <= x1 + tolerance;
        const bool inY = p.y() >= y0 - tolerance && p.y() <= y1 + tolerance;
        double along = -1.0;
        if (inX && std::abs(p.y() - y0) <= tolerance)
          along = p.x() - x0;
        else if (inY && std::abs(p.x() - x1) <= tolerance)
          along = (x1 - x0) + (p.y() - y0);
        else if (inX && std::abs(p.y() - y1) <= tolerance)
          along = (x1 - x0) + (y1 - y0) + (x1 - p.x());
        else if (inY && std::abs(p.x() - x0) <= tolerance)
          along = 2.0 * (x1 - x0) + (y1 - y0) + (y1 - p.y());
        if (along >= 0.0) walk.emplace_back(std::max(along, 0.0), k);
      }
      std::sort(walk.begin(), walk.end());
      TMeshFace part;
      for (const auto& [along, k] : walk) {
        part.vertices.push_back(ids[k]);
        part.positions.push_back(positions[k] - Eigen::Vector2d(x0, y0));
      }
      return part;
    };
    result[std::size_t(faces[i])] = quarter(0.0, cut.x, 0.0, cut.yLeft);
    result.push_back(quarter(cut.x, w, 0.0, cut.yRight));
    result.push_back(quarter(0.0, cut.x, cut.yLeft, h));
    result.push_back(quarter(cut.x, w, cut.yRight, h));
  }
  const int first = mesh.numFaces();
  for (auto& p : points) {
    const int i = p.face >= 0 && p.face < first ? cutOf[std::size_t(p.face)] : -1;
    if (i < 0) continue;
    const Cut& cut = cuts[std::size_t(i)];
    const bool right = p.position.x() >= cut.x;
    const double y = right ? cut.yRight : cut.yLeft;
    const bool top = p.position.y() >= y;
    if (right) p.position.x() -= cut.x;
    if (top) p.position.y() -= y;
    if (right || top) p.face = first + 3 * i + (top ? (right ? 2 : 1) : 0);
  }
  mesh = buildTMesh(numVertices, std::move(result));
}

int refineAroundCones(TMesh& mesh, std::vector<FacePoint>& points, int maxRounds) {
  int split = 0;
  for (int round = 0; round < maxRounds; ++round) {
    std::vector<std::vector<int>> facesAt(std::size_t(mesh.numVertices));
    for (int f = 0; f < mesh.numFaces(); ++f)
      for (int v : mesh.faces[std::size_t(f)].vertices) facesAt[std::size_t(v)].push_back(f);
    // Faces within kCapCells - 1 cells of a cone without cap (rings of faces sharing a vertex:
    // split, they are 2 kCapCells - 2 half cells, and the T-junctions at their border lie beyond
    // the kCapCells a cap needs); the cones with caps keep them, the same cells split where
    // touched (withTouchedCapsSplit).
    std::vector<char> marked(mesh.faces.size(), 0);
    std::vector<TSplineCapRegion> regions;
    std::vector<int> ring;
    FaceDeveloper developer(mesh);
    for (int v = 0; v < mesh.numVertices; ++v) {
      TSplineCapRegion region;
      if (!mesh.isExtraordinary(v)) continue;
      if (findCapRegion(mesh, v, region, developer).empty()) {
        regions.push_back(std::move(region));
        continue;
      }
      ring = facesAt[std::size_t(v)];
      for (int step = 0; step + 1 < kCapCells; ++step) {
        std::vector<int> next;
        for (int f : ring) {
          if (marked[std::size_t(f)]) continue;
          marked[std::size_t(f)] = 1;
          for (int u : mesh.faces[std::size_t(f)].vertices)
            for (int g : facesAt[std::size_t(u)])
              if (!marked[std::size_t(g)]) next.push_back(g);
        }
        ring = std::move(next);
      }
    }
    std::vector<int> faces;
    for (int f = 0; f < mesh.numFaces(); ++f)
      if (marked[std::size_t(f)]) faces.push_back(f);
    if (faces.empty()) break;
    faces = withTouchedCapsSplit(mesh, regions, std::move(faces));
    splitIntoFour(mesh, faces, points);
    split += int(faces.size());
  }
  return split;
}

TMesh splitFace(const TMesh& mesh, int face, int axis, double coordinate) {
  return splitFaceDetailed(mesh, face, axis, coordinate).mesh;
}

TSplineRefinement refine(const TSplineSpace& space, const Eigen::MatrixXd& control,
                         const Eigen::VectorXd& weights, const std::vector<FaceSplit>& splits,
                         const RefineOptions& options) {
  if (control.rows() != space.numBasis())
    throw InputError("refine: " + std::to_string(control.rows()) + " control points for " +
                     std::to_string(space.numBasis()) + " blending functions");
  if (weights.size() != 0 && weights.size() != space.numBasis())
    throw InputError("refine: " + std::to_string(weights.size()) + " weights for " +
                     std::to_string(space.numBasis()) + " blending functions");
  const Eigen::Index dim = control.cols();
  Eigen::MatrixXd homogeneous(space.numBasis(), dim + 1);
  for (int i = 0; i < space.numBasis(); ++i) {
    const double w = weights.size() ? weights[i] : 1.0;
    homogeneous.row(i) << w * control.row(i), w;
  }

  Refining refining{space.mesh(), {}, {}};
  for (int f = 0; f < space.mesh().numFaces(); ++f) refining.origin.push_back({f, {0.0, 0.0}});
  for (std::size_t s = 0; s < splits.size(); ++s) {
    try {
      refining.split(splits[s].face, splits[s].axis, splits[s].coordinate);
    } catch (const InputError& e) {
      throw InputError("refine: split " + std::to_string(s) + ": " + e.what());
    }
  }

  int extraSplits = 0, rounds = 0;
  for (;;) {
    TSplineSpace refined(refining.mesh);
    const Solution solution = Reexpression(space, homogeneous, refining, refined).solve();
    const bool converged = solution.residual <= options.tolerance;
    int cuts = 0;
    if (!converged && rounds < options.maxExtensionRounds) cuts = refining.extend();
    if (cuts == 0) {
      const int n = refined.numBasis();
      TSplineRefinement result{std::move(refined),
                               Eigen::MatrixXd::Zero(n, dim),
                               solution.homogeneous.col(dim),
                               refining.origin,
                               extraSplits,
                               rounds,
                               solution.changed,
                               solution.unknowns,
                               solution.samples,
                               solution.residual,
                               converged,
                               n > 0 ? solution.homogeneous.col(dim).minCoeff() : 0.0};
      for (int i = 0; i < n; ++i)
        if (result.weights[i] != 0.0)
          result.control.row(i) = solution.homogeneous.row(i).head(dim) / result.weights[i];
      return result;
    }
    extraSplits += cuts;
    ++rounds;
  }
}

}  // namespace mspline::spline
