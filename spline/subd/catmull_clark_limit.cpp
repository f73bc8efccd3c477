#include "mspline/spline/subd/catmull_clark_limit.h"

#include <algorithm>
#include <limits>
#include <set>
#include <string>

#include <opensubdiv/far/primvarRefiner.h>

#include "mspline/spline/subd/osd_patches.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/polygon_soup.h"
#include "mspline/structure/mesh/validate.h"

namespace mspline::spline {

namespace Far = OpenSubdiv::Far;
using structure::InputError;

namespace {

const char* const kSource = "Catmull-Clark control net";

// A refined or local point, in the form PrimvarRefiner and StencilTable interpolate.
struct Point {
  double x[3];
  void Clear(void* = nullptr) { x[0] = x[1] = x[2] = 0.0; }
  void AddWithWeight(const Point& p, double w) {
    x[0] += w * p.x[0];
    x[1] += w * p.x[1];
    x[2] += w * p.x[2];
  }
};

void checkPoints(const Eigen::MatrixXd& points, Eigen::Index expectedRows) {
  if (points.cols() != 3)
    throw InputError(std::string(kSource) + ": control points must be n x 3, got " +
                     std::to_string(points.rows()) + " x " + std::to_string(points.cols()));
  if (expectedRows >= 0 && points.rows() != expectedRows)
    throw InputError(std::string(kSource) + ": " + std::to_string(points.rows()) +
                     " control points given where the net has " + std::to_string(expectedRows));
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    if (!points.row(i).allFinite())
      throw InputError(std::string(kSource) + ": control point " + std::to_string(i) +
                       " has a non-finite coordinate (NaN or infinity)");
}

// Everything OpenSubdiv would silently accept but tag as non-manifold, or crash on. Zero-area
// faces, unreferenced points and several components are fine for subdivision.
void checkNet(const Eigen::MatrixXd& points, const std::vector<std::vector<int>>& faces) {
  structure::PolygonSoup soup;
  soup.sourceName = kSource;
  soup.positions.resize(static_cast<std::size_t>(points.rows()));
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    soup.positions[static_cast<std::size_t>(i)] = {points(i, 0), points(i, 1), points(i, 2)};
  soup.faces.reserve(faces.size());
  for (const auto& face : faces) soup.faces.emplace_back(face.begin(), face.end());

  static const std::set<std::string> fatal = {"empty_mesh",
                                              "face_index_out_of_range",
                                              "too_few_face_vertices",
                                              "non_manifold_edge",
                                              "non_manifold_vertex",
                                              "duplicate_face",
                                              "inconsistent_orientation"};
  const structure::ValidationReport report = structure::validate(soup);
  std::string message;
  for (const auto& problem : report.problems)
    if (fatal.count(problem.kind)) message += (message.empty() ? "" : "; also: ") + problem.message;
  if (!message.empty()) throw InputError(message);

  for (std::size_t f = 0; f < faces.size(); ++f) {
    std::vector<int> sorted = faces[f];
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
      throw InputError(std::string(kSource) + ": face " + std::to_string(f) + " repeats a vertex");
  }
}

}  // namespace

struct CatmullClarkLimit::Tables {
  CatmullClarkOptions options;
  int numControlPoints = 0;
  OsdPatches osd;
  /// Refined vertices of every level (the control points first), then the local points.
  std::vector<Point> points;
  FaceCounts counts;

  void computePoints(const Eigen::MatrixXd& controlPoints) {
    for (int i = 0; i < numControlPoints; ++i)
      for (int c = 0; c < 3; ++c) points[std::size_t(i)].x[c] = controlPoints(i, c);
    Far::PrimvarRefinerReal<double> primvar(*osd.refiner);
    Point* src = points.data();
    for (int level = 1; level < osd.refiner->GetNumLevels(); ++level) {
      Point* dst = src + osd.refiner->GetLevel(level - 1).GetNumVertices();
      primvar.Interpolate(level, src, dst);
      src = dst;
    }
    // The double-precision stencils: ComputeLocalPointValues would read float ones.
    if (osd.patchTable->GetNumLocalPoints() > 0)
      osd.patchTable->GetLocalPointStencilTable<double>()->UpdateValues(
          points.data(), points.data() + osd.refiner->GetNumVerticesTotal());
  }

  void countFaces() {
    const int numFaces = static_cast<int>(osd.firstPatchFace.size()) - 1;
    std::vector<int> baseOf(static_cast<std::size_t>(osd.firstPatchFace.back()));
    for (int f = 0; f < numFaces; ++f)
      std::fill(baseOf.begin() + osd.firstPatchFace[f], baseOf.begin() + osd.firstPatchFace[f + 1],
                f);
    std::vector<char> hasPatch(std::size_t(numFaces), 0), irregular(std::size_t(numFaces), 0);
    for (int array = 0; array < osd.patchTable->GetNumPatchArrays(); ++array) {
      const bool regularType =
          osd.patchTable->GetPatchArrayDescriptor(array).GetType() == Far::PatchDescriptor::REGULAR;
      for (int patch = 0; patch < osd.patchTable->GetNumPatches(array); ++patch) {
        const Far::PatchParam param = osd.patchTable->GetPatchParam(array, patch);
        const int base = baseOf[std::size_t(param.GetFaceId())];
        hasPatch[std::size_t(base)] = 1;
        if (!regularType || param.GetDepth() != 0) irregular[std::size_t(base)] = 1;
      }
    }
    counts = {};
    for (int f = 0; f < numFaces; ++f) {
      if (!hasPatch[std::size_t(f)])
        ++counts.withoutSurface;
      else if (irregular[std::size_t(f)])
        ++counts.irregular;
      else
        ++counts.regular;
    }
  }

  void checkParameter(int face, double u, double v) const {
    if (face < 0 || face >= osd.firstPatchFace.back())
      throw InputError(std::string(kSource) + ": patch face " + std::to_string(face) +
                       " out of range (the net has " + std::to_string(osd.firstPatchFace.back()) +
                       " patch faces)");
    if (!(u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0))
      throw InputError(std::string(kSource) + ": parameter (" + std::to_string(u) + ", " +
                       std::to_string(v) + ") of patch face " + std::to_string(face) +
                       " is outside [0,1]^2");
  }
};

CatmullClarkLimit::CatmullClarkLimit(const Eigen::MatrixXd& controlPoints,
                                     const std::vector<std::vector<int>>& faces,
                                     const CatmullClarkOptions& options)
    : tables_(std::make_unique<Tables>()) {
  checkIsolationLevel(options, kSource);
  checkPoints(controlPoints, -1);
  checkNet(controlPoints, faces);
  Tables& t = *tables_;
  t.options = options;
  t.numControlPoints = static_cast<int>(controlPoints.rows());

  t.osd = buildOsdPatches(t.numControlPoints, faces, options, kSource);

  t.points.resize(
      std::size_t(t.osd.refiner->GetNumVerticesTotal() + t.osd.patchTable->GetNumLocalPoints()));
  t.computePoints(controlPoints);
  t.countFaces();
}

CatmullClarkLimit::~CatmullClarkLimit() = default;
CatmullClarkLimit::CatmullClarkLimit(CatmullClarkLimit&&) noexcept = default;
CatmullClarkLimit& CatmullClarkLimit::operator=(CatmullClarkLimit&&) noexcept = default;

void CatmullClarkLimit::updateControlPoints(const Eigen::MatrixXd& controlPoints) {
  checkPoints(controlPoints, tables_->numControlPoints);
  tables_->computePoints(controlPoints);
}

std::optional<LimitPoint> CatmullClarkLimit::evaluate(int face, double u, double v,
                                                      bool secondDerivatives) const {
  const Tables& t = *tables_;
  t.checkParameter(face, u, v);
  const Far::PatchTable::PatchHandle* handle = t.osd.patchMap->FindPatch(face, u, v);
  if (!handle) return std::nullopt;
  double w[6][kMaxOsdPatchVertices];
  const Far::ConstIndexArray cvs =
      osdPatchWeights(*t.osd.patchTable, *handle, u, v, w, secondDerivatives);
  Eigen::Vector3d sum[6];
  const int outputs = secondDerivatives ? 6 : 3;
  for (int k = 0; k < outputs; ++k) sum[k].setZero();
  for (int i = 0; i < cvs.size(); ++i) {
    const Eigen::Map<const Eigen::Vector3d> p(t.points[std::size_t(cvs[i])].x);
    for (int k = 0; k < outputs; ++k) sum[k] += w[k][i] * p;
  }
  LimitPoint result;
  result.position = sum[0];
  result.du = sum[1];
  result.dv = sum[2];
  if (secondDerivatives) {
    result.duu = sum[3];
    result.duv = sum[4];
    result.dvv = sum[5];
  }
  return result;
}

std::size_t CatmullClarkLimit::evaluate(const std::vector<FaceParameter>& points,
                                        LimitPoints& out) const {
  const Tables& t = *tables_;
  for (const auto& p : points) t.checkParameter(p.face, p.u, p.v);
  const Eigen::Index n = static_cast<Eigen::Index>(points.size());
  out.position.resize(n, 3);
  out.du.resize(n, 3);
  out.dv.resize(n, 3);
  out.onSurface.assign(points.size(), 0);
  std::size_t found = 0;
  double w[6][kMaxOsdPatchVertices];
  for (Eigen::Index k = 0; k < n; ++k) {
    const FaceParameter& p = points[std::size_t(k)];
    const Far::PatchTable::PatchHandle* handle = t.osd.patchMap->FindPatch(p.face, p.u, p.v);
    if (!handle) {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      out.position.row(k).setConstant(nan);
      out.du.row(k).setConstant(nan);
      out.dv.row(k).setConstant(nan);
      continue;
    }
    const Far::ConstIndexArray cvs =
        osdPatchWeights(*t.osd.patchTable, *handle, p.u, p.v, w, false);
    Eigen::Vector3d position = Eigen::Vector3d::Zero(), du = position, dv = position;
    for (int i = 0; i < cvs.size(); ++i) {
      const Eigen::Map<const Eigen::Vector3d> q(t.points[std::size_t(cvs[i])].x);
      position += w[0][i] * q;
      du += w[1][i] * q;
      dv += w[2][i] * q;
    }
    out.position.row(k) = position;
    out.du.row(k) = du;
    out.dv.row(k) = dv;
    out.onSurface[std::size_t(k)] = 1;
    ++found;
  }
  return found;
}

int CatmullClarkLimit::numControlPoints() const {
  return tables_->numControlPoints;
}

int CatmullClarkLimit::numBaseFaces() const {
  return static_cast<int>(tables_->osd.firstPatchFace.size()) - 1;
}

int CatmullClarkLimit::numPatchFaces() const {
  return tables_->osd.firstPatchFace.back();
}

int CatmullClarkLimit::firstPatchFace(int baseFace) const {
  if (baseFace < 0 || baseFace > numBaseFaces())
    throw InputError(std::string(kSource) + ": base face " + std::to_string(baseFace) +
                     " out of range (the net has " + std::to_string(numBaseFaces()) + " faces)");
  return tables_->osd.firstPatchFace[std::size_t(baseFace)];
}

FaceCounts CatmullClarkLimit::faceCounts() const {
  return tables_->counts;
}

int CatmullClarkLimit::numPatchPoints() const {
  return static_cast<int>(tables_->points.size());
}

const CatmullClarkOptions& CatmullClarkLimit::options() const {
  return tables_->options;
}

}  // namespace mspline::spline
