#include "mspline/spline/tspline/tspline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Geometry>

#include "mspline/spline/core/cubic_bspline.h"
#include "mspline/spline/tspline/tspline_cap.h"
#include "mspline/structure/core/errors.h"

namespace mspline::spline {

using structure::InputError;

namespace {

double meshScale(const TMesh& mesh) {
  double scale = 0.0;
  for (const auto& f : mesh.faces) scale = std::max({scale, f.width, f.height});
  return scale;
}

// Chart-space rectangle of a developed face.
void developedBox(const TMeshFace& face, const QuarterMotion& m, Eigen::Vector2d& lo,
                  Eigen::Vector2d& hi) {
  const Eigen::Vector2d a = m.apply({0.0, 0.0}), b = m.apply({face.width, face.height});
  lo = a.cwiseMin(b);
  hi = a.cwiseMax(b);
}

Eigen::Matrix2d rotationMatrix(int quarterTurns) {
  const QuarterMotion m{quarterTurns, Eigen::Vector2d::Zero()};
  Eigen::Matrix2d r;
  r.col(0) = m.rotate({1.0, 0.0});
  r.col(1) = m.rotate({0.0, 1.0});
  return r;
}

}  // namespace

// developFaces with what every development of one mesh shares computed once: the tolerances, the
// frame change across every side, and the scratch space that tells placements apart (a
// construction runs five developments per anchor, each reaching a few dozen faces at most).
class FaceDeveloper::Impl {
 public:
  explicit Impl(const TMesh& mesh) : mesh_(mesh) {
    const double scale = std::max(1.0, meshScale(mesh));
    tolerance_ = 1e-9 * scale;
    grid_ = 1e-6 * scale;
    firstSide_.reserve(mesh.faces.size());
    for (int f = 0; f < mesh.numFaces(); ++f) {
      firstSide_.push_back(static_cast<int>(fromTwin_.size()));
      const TMeshFace& face = mesh.faces[f];
      for (std::size_t k = 0; k < face.vertices.size(); ++k)
        fromTwin_.push_back(face.twinFace[k] < 0
                                ? QuarterMotion{}
                                : mesh.acrossEdge(f, static_cast<int>(k)).inverse());
    }
    lastSeen_.assign(mesh.faces.size(), -1);
    mark_.assign(mesh.faces.size(), 0);
  }

  double tolerance() const { return tolerance_; }

  // developFaces into `found`: breadth first, each placement in the order it is first reached.
  void develop(int start, const QuarterMotion& startToChart, const Eigen::Vector2d& lo,
               const Eigen::Vector2d& hi, bool openBox, std::vector<DevelopedFace>& found) {
    found.clear();
    seen_.clear();
    ++search_;
    const auto meets = [&](const DevelopedFace& d) {
      Eigen::Vector2d flo, fhi;
      developedBox(mesh_.faces[d.face], d.toChart, flo, fhi);
      if (openBox)
        return flo.x() < hi.x() - tolerance_ && flo.y() < hi.y() - tolerance_ &&
               fhi.x() > lo.x() + tolerance_ && fhi.y() > lo.y() + tolerance_;
      return flo.x() <= hi.x() + tolerance_ && flo.y() <= hi.y() + tolerance_ &&
             fhi.x() >= lo.x() - tolerance_ && fhi.y() >= lo.y() - tolerance_;
    };
    const DevelopedFace first{start, startToChart};
    if (!meets(first)) return;
    record(first);
    found.push_back(first);
    // `found` is the queue: placements are appended when reached and expanded in that order.
    for (std::size_t i = 0; i < found.size(); ++i) {
      const DevelopedFace d = found[i];
      const TMeshFace& face = mesh_.faces[d.face];
      const QuarterMotion* fromTwin = &fromTwin_[firstSide_[d.face]];
      for (std::size_t k = 0; k < face.vertices.size(); ++k) {
        if (face.twinFace[k] < 0) continue;
        const DevelopedFace next{face.twinFace[k], fromTwin[k].then(d.toChart)};
        if (!meets(next) || !record(next)) continue;
        found.push_back(next);
      }
    }
  }

 private:
  // A recorded placement of a face: its turn and its translation rounded to the grid.
  struct Placement {
    int quarterTurns;
    long long x, y;
    int previous;  // the placement of the same face recorded before it in this search, or -1
  };

  // Records d unless a placement equal to it is recorded already; whether it was new.
  bool record(const DevelopedFace& d) {
    const Placement p{d.toChart.quarterTurns, std::llround(d.toChart.translation.x() / grid_),
                      std::llround(d.toChart.translation.y() / grid_),
                      mark_[d.face] == search_ ? lastSeen_[d.face] : -1};
    for (int s = p.previous; s >= 0; s = seen_[s].previous)
      if (seen_[s].quarterTurns == p.quarterTurns && seen_[s].x == p.x && seen_[s].y == p.y)
        return false;
    mark_[d.face] = search_;
    lastSeen_[d.face] = static_cast<int>(seen_.size());
    seen_.push_back(p);
    return true;
  }

  const TMesh& mesh_;
  double tolerance_ = 0.0, grid_ = 0.0;
  std::vector<int> firstSide_;            // per face: the index of its side 0 in fromTwin_
  std::vector<QuarterMotion> fromTwin_;   // per face side: the twin's frame into the face's
  std::vector<Placement> seen_;           // the placements of the current search
  std::vector<int> lastSeen_;             // per face: its last entry of seen_ (if marked)
  std::vector<unsigned long long> mark_;  // per face: the search that set lastSeen_
  unsigned long long search_ = 0;
};

namespace {

// The knots a ray meets: distances (> 0) along +x from the origin of the frame given by `toRay`,
// of edges of the developed faces that cross or touch the line y = 0 perpendicularly, and how far
// along the line the developed faces reach without gap.
struct RayHits {
  std::vector<double> knots;
  double covered = 0.0;
  std::vector<std::pair<double, double>> spans;  // scratch
};

void castRay(const TMesh& mesh, const std::vector<DevelopedFace>& faces, const QuarterMotion& toRay,
             double tolerance, RayHits& hits) {
  hits.knots.clear();
  hits.spans.clear();
  hits.covered = 0.0;
  for (const DevelopedFace& d : faces) {
    const TMeshFace& face = mesh.faces[d.face];
    const QuarterMotion m = d.toChart.then(toRay);
    Eigen::Vector2d lo, hi;
    developedBox(face, m, lo, hi);
    if (lo.y() > tolerance || hi.y() < -tolerance || hi.x() <= tolerance) continue;
    hits.spans.emplace_back(lo.x(), hi.x());
    const std::size_t n = face.positions.size();
    for (std::size_t k = 0; k < n; ++k) {
      const Eigen::Vector2d a = m.apply(face.positions[k]),
                            b = m.apply(face.positions[(k + 1) % n]);
      if (std::abs(a.x() - b.x()) > tolerance) continue;
      if (std::min(a.y(), b.y()) > tolerance || std::max(a.y(), b.y()) < -tolerance) continue;
      if (a.x() > tolerance) hits.knots.push_back(a.x());
    }
  }
  std::sort(hits.knots.begin(), hits.knots.end());
  // Knots closer than the tolerance are one: keep the first of each run, in place.
  std::size_t distinct = 0;
  for (double k : hits.knots)
    if (distinct == 0 || k > hits.knots[distinct - 1] + tolerance) hits.knots[distinct++] = k;
  hits.knots.resize(distinct);
  std::sort(hits.spans.begin(), hits.spans.end());
  for (const auto& [lo, hi] : hits.spans)
    if (lo <= hits.covered + tolerance) hits.covered = std::max(hits.covered, hi);
}

}  // namespace

std::vector<DevelopedFace> developFaces(const TMesh& mesh, int start,
                                        const QuarterMotion& startToChart,
                                        const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                                        bool openBox) {
  return FaceDeveloper(mesh).develop(start, startToChart, lo, hi, openBox);
}

FaceDeveloper::FaceDeveloper(const TMesh& mesh) : impl_(std::make_unique<Impl>(mesh)) {}
FaceDeveloper::~FaceDeveloper() = default;

std::vector<DevelopedFace> FaceDeveloper::develop(int start, const QuarterMotion& startToChart,
                                                  const Eigen::Vector2d& lo,
                                                  const Eigen::Vector2d& hi, bool openBox) {
  std::vector<DevelopedFace> found;
  impl_->develop(start, startToChart, lo, hi, openBox, found);
  return found;
}

TSplineSpace::TSplineSpace(TMesh mesh) : mesh_(std::move(mesh)) {
  const int numVertices = mesh_.numVertices;
  const double scale = std::max(1.0, meshScale(mesh_));
  FaceDeveloper::Impl developer(mesh_);
  const double tolerance = developer.tolerance();
  double extent = 0.0;  // no ray needs to go further than all faces laid end to end
  for (const auto& f : mesh_.faces) extent += f.width + f.height;

  // A face each vertex is a corner of, and its position there.
  std::vector<std::pair<int, Eigen::Vector2d>> cornerFace(static_cast<std::size_t>(numVertices),
                                                          {-1, Eigen::Vector2d::Zero()});
  for (int f = 0; f < mesh_.numFaces(); ++f) {
    const TMeshFace& face = mesh_.faces[f];
    for (std::size_t k = 0; k < face.vertices.size(); ++k) {
      const Eigen::Vector2d& p = face.positions[k];
      const bool corner =
          (std::abs(p.x()) <= tolerance || std::abs(p.x() - face.width) <= tolerance) &&
          (std::abs(p.y()) <= tolerance || std::abs(p.y() - face.height) <= tolerance);
      if (corner && cornerFace[face.vertices[k]].first < 0) cornerFace[face.vertices[k]] = {f, p};
    }
  }

  // Caps: the vertices anchoring uniform B-splines around a cone (its region), and the faces
  // around it (one patch each; marked here, their entries of capFaces_ set below).
  const std::vector<TSplineCapRegion> regions = capRegions(mesh_);
  std::vector<int> capRegionOf(static_cast<std::size_t>(numVertices), -1);
  capFaceOf_.assign(mesh_.faces.size(), -1);
  for (std::size_t r = 0; r < regions.size(); ++r) {
    const TSplineCapRegion& region = regions[r];
    capRegionOf[std::size_t(region.vertex)] = int(r);
    for (int k = 0; k < region.valence; ++k) {
      capRegionOf[std::size_t(region.vertexAt(k, 1, 0))] = int(r);
      capRegionOf[std::size_t(region.vertexAt(k, 1, 1))] = int(r);
      capFaceOf_[std::size_t(region.cells[std::size_t(k)][0].face)] = 0;
    }
  }

  anchorOfVertex_.assign(static_cast<std::size_t>(numVertices), -1);
  pieces_.resize(mesh_.faces.size());
  std::vector<DevelopedFace> faces, support;  // reused from anchor to anchor
  RayHits hits;
  for (int v = 0; v < numVertices; ++v) {
    if (cornerFace[v].first < 0) {
      missing_.push_back({v, "corner of no face"});
      continue;
    }
    TSplineAnchor anchor;
    anchor.vertex = v;
    anchor.chartFace = cornerFace[v].first;
    const QuarterMotion toChart{0, -cornerFace[v].second};
    if (capRegionOf[std::size_t(v)] >= 0) {
      // Uniform knots; the pieces follow from the region below.
      const double d = regions[std::size_t(capRegionOf[std::size_t(v)])].cellSize;
      anchor.sKnots = anchor.tKnots = {-2.0 * d, -d, 0.0, d, 2.0 * d};
      anchorOfVertex_[v] = static_cast<int>(anchors_.size());
      anchors_.push_back(anchor);
      continue;
    }
    // Rays +x, +y, -x, -y: the ray frame turns the chart so that the ray runs along +x.
    std::array<std::array<double, 2>, 4> rayKnots{};
    std::array<int, 4> numKnots{};
    std::string failure;
    for (int direction = 0; direction < 4 && failure.empty(); ++direction) {
      const QuarterMotion toRay{(4 - direction) & 3, Eigen::Vector2d::Zero()};
      const QuarterMotion fromRay = toRay.inverse();
      for (double reach = 2.0 * scale;; reach *= 2.0) {
        const Eigen::Vector2d end = fromRay.rotate({reach, 0.0});
        developer.develop(anchor.chartFace, toChart, end.cwiseMin(Eigen::Vector2d::Zero()),
                          end.cwiseMax(Eigen::Vector2d::Zero()), false, faces);
        castRay(mesh_, faces, toRay, tolerance, hits);
        if (hits.knots.size() >= 2 || hits.covered < reach - tolerance) {
          numKnots[direction] = static_cast<int>(std::min<std::size_t>(hits.knots.size(), 2));
          for (int i = 0; i < numKnots[direction]; ++i) rayKnots[direction][i] = hits.knots[i];
          break;
        }
        if (reach > 2.0 * extent) {
          failure = "a ray from it meets no edge";
          break;
        }
      }
    }
    if (!failure.empty()) {
      missing_.push_back({v, failure});
      continue;
    }
    // Beyond the boundary, repeat the last spacing seen (on this ray, else on the opposite one).
    for (int direction = 0; direction < 4; ++direction) {
      if (numKnots[direction] == 2) continue;
      ++anchor.paddedRays;
      std::array<double, 2>& knots = rayKnots[direction];
      const int opposite = (direction + 2) & 3;
      double spacing = numKnots[direction] > 0  ? knots[0]
                       : numKnots[opposite] > 0 ? rayKnots[opposite][0]
                                                : 0.0;
      if (spacing <= tolerance) spacing = scale;
      for (int& n = numKnots[direction]; n < 2; ++n)
        knots[n] = (n > 0 ? knots[n - 1] : 0.0) + spacing;
    }
    anchor.sKnots = {-rayKnots[2][1], -rayKnots[2][0], 0.0, rayKnots[0][0], rayKnots[0][1]};
    anchor.tKnots = {-rayKnots[3][1], -rayKnots[3][0], 0.0, rayKnots[1][0], rayKnots[1][1]};

    // The support, developed: it must not overlap itself.
    const Eigen::Vector2d lo(anchor.sKnots[0], anchor.tKnots[0]),
        hi(anchor.sKnots[4], anchor.tKnots[4]);
    developer.develop(anchor.chartFace, toChart, lo, hi, true, faces);
    double coveredArea = 0.0;
    support.clear();
    for (const DevelopedFace& d : faces) {
      const TMeshFace& face = mesh_.faces[d.face];
      Eigen::Vector2d flo, fhi;
      developedBox(face, d.toChart, flo, fhi);
      const Eigen::Vector2d overlap = fhi.cwiseMin(hi) - flo.cwiseMax(lo);
      if (overlap.x() <= tolerance || overlap.y() <= tolerance) continue;
      coveredArea += overlap.x() * overlap.y();
      if (capFaceOf_[std::size_t(d.face)] < 0) support.push_back(d);
    }
    if (failure.empty() && coveredArea > (hi - lo).prod() * (1.0 + 1e-9))
      failure = "its support overlaps itself when developed";
    if (!failure.empty()) {
      missing_.push_back({v, failure});
      continue;
    }
    anchorOfVertex_[v] = static_cast<int>(anchors_.size());
    for (const DevelopedFace& d : support)
      pieces_[d.face].push_back({anchorOfVertex_[v], d.toChart});
    anchors_.push_back(anchor);
  }

  for (std::size_t r = 0; r < regions.size(); ++r) {
    const TSplineCapRegion& region = regions[r];
    const double d = region.cellSize;
    for (int k = 0; k < region.valence; ++k) {
      // The cap's functions on the faces off the cone: the face's 4 x 4 block of anchors never
      // has the cone inside, so the sector frame develops it without winding. Only the cone and
      // its one ring (indices -1..1) anchor the cap's functions.
      for (int b = 0; b < kCapCells; ++b)
        for (int a = 0; a < kCapCells; ++a) {
          if (a == 0 && b == 0) continue;
          const DevelopedFace& cell = region.cells[std::size_t(k)][std::size_t(kCapCells * b + a)];
          for (int j = b - 1; j <= std::min(b + 2, 1); ++j)
            for (int i = a - 1; i <= std::min(a + 2, 1); ++i) {
              const int u = region.vertexAt(k, i, j);
              if (capRegionOf[std::size_t(u)] != int(r)) continue;
              pieces_[std::size_t(cell.face)].push_back(
                  {anchorOfVertex_[std::size_t(u)],
                   {cell.toChart.quarterTurns,
                    cell.toChart.translation - d * Eigen::Vector2d(i, j)}});
            }
        }
      const TSplineCapPatch patch = capPatch(region, k);
      TSplineCapFace capFace;
      capFace.face = patch.face;
      capFace.cone = region.vertex;
      capFace.bezier = patch.coefficients;
      for (const int u : patch.vertices) {
        if (anchorOfVertex_[std::size_t(u)] < 0)
          throw structure::SolverError("T-spline: vertex " + std::to_string(u) + " of the cap at " +
                                       std::to_string(region.vertex) + " has no blending function");
        capFace.anchors.push_back(anchorOfVertex_[std::size_t(u)]);
      }
      capFaceOf_[std::size_t(patch.face)] = int(capFaces_.size());
      capFaces_.push_back(std::move(capFace));
    }
  }
}

void TSplineSpace::basisAt(int face, const Eigen::Vector2d& p, std::vector<TSplineBasisValue>& out,
                           int derivatives) const {
  out.clear();
  if (const TSplineCapFace* cap = capFace(face)) {
    const TMeshFace& f = mesh_.faces[std::size_t(face)];
    double bx[4], dx[4], ddx[4], by[4], dy[4], ddy[4];
    cubicBernstein(p.x() / f.width, bx, dx, ddx);
    cubicBernstein(p.y() / f.height, by, dy, ddy);
    Eigen::Matrix<double, 16, 6> bernstein;  // value, d/dx, d/dy, d2/dx2, d2/dxdy, d2/dy2
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i)
        bernstein.row(4 * j + i) << bx[i] * by[j], dx[i] * by[j] / f.width,
            bx[i] * dy[j] / f.height, ddx[i] * by[j] / (f.width * f.width),
            dx[i] * dy[j] / (f.width * f.height), bx[i] * ddy[j] / (f.height * f.height);
    const Eigen::Matrix<double, Eigen::Dynamic, 6> values = cap->bezier.transpose() * bernstein;
    for (std::size_t m = 0; m < cap->anchors.size(); ++m) {
      const Eigen::Index r = Eigen::Index(m);
      TSplineBasisValue value{cap->anchors[m], values(r, 0)};
      if (derivatives) value.ds = values(r, 1), value.dt = values(r, 2);
      if (derivatives > 1)
        value.dss = values(r, 3), value.dst = values(r, 4), value.dtt = values(r, 5);
      out.push_back(value);
    }
    return;
  }
  for (const TSplinePiece& piece : pieces_.at(face)) {
    const TSplineAnchor& a = anchors_[piece.anchor];
    const Eigen::Vector2d q = piece.toChart.apply(p);
    double ds = 0, dss = 0, dt = 0, dtt = 0;
    const double ns = cubicBSpline(a.sKnots.data(), q.x(), derivatives ? &ds : nullptr,
                                   derivatives > 1 ? &dss : nullptr);
    const double nt = cubicBSpline(a.tKnots.data(), q.y(), derivatives ? &dt : nullptr,
                                   derivatives > 1 ? &dtt : nullptr);
    if (ns == 0.0 && nt == 0.0 && ds == 0.0 && dt == 0.0) continue;
    TSplineBasisValue value;
    value.anchor = piece.anchor;
    value.value = ns * nt;
    if (derivatives) {
      // Chart derivatives back to the face frame: gradient R^T g, Hessian R^T H R.
      const Eigen::Matrix2d r = rotationMatrix(piece.toChart.quarterTurns);
      const Eigen::Vector2d g = r.transpose() * Eigen::Vector2d(ds * nt, ns * dt);
      value.ds = g.x();
      value.dt = g.y();
      if (derivatives > 1) {
        Eigen::Matrix2d h;
        h << dss * nt, ds * dt, ds * dt, ns * dtt;
        const Eigen::Matrix2d hp = r.transpose() * h * r;
        value.dss = hp(0, 0);
        value.dst = hp(0, 1);
        value.dtt = hp(1, 1);
      }
    }
    out.push_back(value);
  }
}

namespace {

TSplinePoint rationalPoint(const Eigen::MatrixXd& control, const Eigen::VectorXd& weights,
                           const std::vector<TSplineBasisValue>& basis, int derivatives) {
  const Eigen::Index dim = control.cols();
  Eigen::VectorXd n = Eigen::VectorXd::Zero(dim), ns = n, nt = n, nss = n, nst = n, ntt = n;
  double d = 0, ds = 0, dt = 0, dss = 0, dst = 0, dtt = 0;
  for (const TSplineBasisValue& b : basis) {
    const double w = weights.size() ? weights[b.anchor] : 1.0;
    const Eigen::VectorXd c = control.row(b.anchor).transpose() * w;
    n += b.value * c, d += b.value * w;
    if (derivatives) ns += b.ds * c, nt += b.dt * c, ds += b.ds * w, dt += b.dt * w;
    if (derivatives > 1) {
      nss += b.dss * c, nst += b.dst * c, ntt += b.dtt * c;
      dss += b.dss * w, dst += b.dst * w, dtt += b.dtt * w;
    }
  }
  TSplinePoint point;
  point.denominator = d;
  if (!(d > 0.0)) {
    point.position = Eigen::VectorXd::Constant(dim, std::numeric_limits<double>::quiet_NaN());
    point.ds = point.dt = point.dss = point.dst = point.dtt = point.position;
    return point;
  }
  // Quotient rule for s = n / d.
  point.position = n / d;
  const Eigen::VectorXd& s = point.position;
  point.ds = (ns - ds * s) / d;
  point.dt = (nt - dt * s) / d;
  point.dss = (nss - 2.0 * ds * point.ds - dss * s) / d;
  point.dst = (nst - ds * point.dt - dt * point.ds - dst * s) / d;
  point.dtt = (ntt - 2.0 * dt * point.dt - dtt * s) / d;
  if (derivatives && dim == 3) {
    const Eigen::Vector3d n3 = Eigen::Vector3d(point.ds).cross(Eigen::Vector3d(point.dt));
    point.normal = n3 / n3.norm();
  }
  return point;
}

void checkControl(const TSplineSpace& space, const Eigen::MatrixXd& control,
                  const Eigen::VectorXd& weights, int face) {
  if (control.rows() != space.numBasis())
    throw InputError("T-spline: " + std::to_string(control.rows()) + " control points for " +
                     std::to_string(space.numBasis()) + " blending functions");
  if (weights.size() != 0 && weights.size() != space.numBasis())
    throw InputError("T-spline: weights do not match the blending functions");
  if (face < 0 || face >= space.mesh().numFaces())
    throw InputError("T-spline: face " + std::to_string(face) + " out of range");
}

}  // namespace

TSplinePoint TSplineSpace::evaluate(const Eigen::MatrixXd& control, const Eigen::VectorXd& weights,
                                    int face, const Eigen::Vector2d& p, int derivatives) const {
  checkControl(*this, control, weights, face);
  std::vector<TSplineBasisValue> basis;
  basisAt(face, p, basis, derivatives);
  return rationalPoint(control, weights, basis, derivatives);
}

FaceKnots2d knotsInFace(const TSplineAnchor& anchor, const QuarterMotion& toChart) {
  // A chart axis maps to a face axis, maybe reversed (then the knots come out descending).
  const QuarterMotion back = toChart.inverse();
  const bool sAlongX = std::abs(back.rotate({1.0, 0.0}).x()) > 0.5;
  FaceKnots2d knots;
  for (std::size_t i = 0; i < 5; ++i) {
    const Eigen::Vector2d sLine = back.apply({anchor.sKnots[i], 0.0});
    const Eigen::Vector2d tLine = back.apply({0.0, anchor.tKnots[i]});
    knots.xKnots[i] = sAlongX ? sLine.x() : tLine.x();
    knots.yKnots[i] = sAlongX ? tLine.y() : sLine.y();
  }
  std::sort(knots.xKnots.begin(), knots.xKnots.end());
  std::sort(knots.yKnots.begin(), knots.yKnots.end());
  return knots;
}

TSplinePoint TSplineSpace::evaluateMovingKnots(const Eigen::MatrixXd& control,
                                               const Eigen::VectorXd& weights, int face,
                                               const Eigen::Vector2d& p) const {
  checkControl(*this, control, weights, face);
  std::vector<TSplineBasisValue> basis;
  if (capFace(face)) basisAt(face, p, basis);  // a patch: no knots to move
  for (const TSplinePiece& piece : pieces_[face]) {
    const FaceKnots2d knots = knotsInFace(anchors_[piece.anchor], piece.toChart);
    const double value =
        cubicBSpline(knots.xKnots.data(), p.x()) * cubicBSpline(knots.yKnots.data(), p.y());
    if (value != 0.0) basis.push_back({piece.anchor, value});
  }
  return rationalPoint(control, weights, basis, 0);
}

}  // namespace mspline::spline
