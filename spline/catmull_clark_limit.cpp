#include "spline/catmull_clark_limit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>

#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include "structure/errors.h"
#include "structure/polygon_soup.h"
#include "structure/validate.h"

namespace mspline::spline {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;
using structure::InputError;

namespace {

const char* const kSource = "Catmull-Clark control net";

// The largest patch OpenSubdiv builds for Catmull-Clark: a Gregory basis end cap.
constexpr int kMaxPatchVertices = 20;

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

// Cubic Bezier basis at s with first and second derivatives.
void bezierBasis(double s, double b[4], double d1[4], double d2[4]) {
  const double r = 1.0 - s;
  b[0] = r * r * r;
  b[1] = 3 * s * r * r;
  b[2] = 3 * s * s * r;
  b[3] = s * s * s;
  d1[0] = -3 * r * r;
  d1[1] = 3 * r * (r - 2 * s);
  d1[2] = 3 * s * (2 * r - s);
  d1[3] = 3 * s * s;
  d2[0] = 6 * r;
  d2[1] = 18 * s - 12;
  d2[2] = 6 - 18 * s;
  d2[3] = 6 * s;
}

// Weights of OpenSubdiv's 20-point Gregory basis patch at (s, t) of the patch, with the exact
// derivatives of its rational interior weights. (OpenSubdiv's own EvaluateBasis differentiates
// only the Bezier factor, which leaves its derivatives about 1% off those of the position.) The
// points come in 4 groups of 5 per corner: corner point, edge points along the corner's two edges
// (counter-clockwise first), and the two face points that blend into one Bezier interior point.
// w[0] gets the position weights, w[1], w[2] the s and t derivatives, w[3..5] (with `second`)
// the ss, st and tt derivatives.
void gregoryBasis(double s, double t, double (*w)[kMaxPatchVertices], bool second) {
  static const int boundaryPoint[12] = {0, 1, 7, 5, 2, 6, 16, 12, 15, 17, 11, 10};
  static const int boundaryCol[12] = {0, 1, 2, 3, 0, 3, 0, 3, 0, 1, 2, 3};
  static const int boundaryRow[12] = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 3, 3};
  // Per corner: the Bezier interior point and the face point f+ weight N / D, both linear in
  // (s, t): N = n0 + ns s + nt t, D = d0 + ds s + dt t. f- gets 1 - N / D.
  static const int interiorCol[4] = {1, 2, 2, 1}, interiorRow[4] = {1, 1, 2, 2};
  static const double n0[4] = {0, 0, 1, 1}, ns[4] = {1, 0, -1, 0}, nt[4] = {0, 1, 0, -1};
  static const double d0[4] = {0, 1, 2, 1}, ds[4] = {1, -1, -1, 1}, dt[4] = {1, 1, -1, -1};

  double bs[4], bs1[4], bs2[4], bt[4], bt1[4], bt2[4];
  bezierBasis(s, bs, bs1, bs2);
  bezierBasis(t, bt, bt1, bt2);
  for (int i = 0; i < 12; ++i) {
    const int p = boundaryPoint[i], c = boundaryCol[i], r = boundaryRow[i];
    w[0][p] = bs[c] * bt[r];
    w[1][p] = bs1[c] * bt[r];
    w[2][p] = bs[c] * bt1[r];
    if (second) {
      w[3][p] = bs2[c] * bt[r];
      w[4][p] = bs1[c] * bt1[r];
      w[5][p] = bs[c] * bt2[r];
    }
  }
  for (int corner = 0; corner < 4; ++corner) {
    const double d = d0[corner] + ds[corner] * s + dt[corner] * t;
    // At the corner itself (d = 0) the Bezier factor and its first derivatives vanish; any finite
    // G will do.
    double g = 0, gs = 0, gt = 0, gss = 0, gst = 0, gtt = 0;
    if (d > 0) {
      g = (n0[corner] + ns[corner] * s + nt[corner] * t) / d;
      gs = (ns[corner] - g * ds[corner]) / d;
      gt = (nt[corner] - g * dt[corner]) / d;
      gss = -2 * gs * ds[corner] / d;
      gst = -(gs * dt[corner] + gt * ds[corner]) / d;
      gtt = -2 * gt * dt[corner] / d;
    }
    const int c = interiorCol[corner], r = interiorRow[corner];
    const double b = bs[c] * bt[r], b_s = bs1[c] * bt[r], b_t = bs[c] * bt1[r];
    // f+ with G, f- with 1 - G (whose derivatives are those of G negated).
    for (int side = 0; side < 2; ++side) {
      const int p = 5 * corner + 3 + side;
      const double sign = side == 0 ? 1.0 : -1.0;
      const double gp = side == 0 ? g : 1.0 - g;
      w[0][p] = b * gp;
      w[1][p] = b_s * gp + sign * b * gs;
      w[2][p] = b_t * gp + sign * b * gt;
      if (second) {
        const double b_ss = bs2[c] * bt[r], b_st = bs1[c] * bt1[r], b_tt = bs[c] * bt2[r];
        w[3][p] = b_ss * gp + sign * (2 * b_s * gs + b * gss);
        w[4][p] = b_st * gp + sign * (b_s * gt + b_t * gs + b * gst);
        w[5][p] = b_tt * gp + sign * (2 * b_t * gt + b * gtt);
      }
    }
  }
}

Sdc::Options::VtxBoundaryInterpolation boundaryInterpolation(BoundaryRule rule) {
  switch (rule) {
    case BoundaryRule::None:
      return Sdc::Options::VTX_BOUNDARY_NONE;
    case BoundaryRule::EdgeOnly:
      return Sdc::Options::VTX_BOUNDARY_EDGE_ONLY;
    case BoundaryRule::EdgeAndCorner:
      return Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER;
  }
  throw InputError(std::string(kSource) + ": unknown boundary rule");
}

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
  std::vector<int> firstPatchFace;
  std::unique_ptr<Far::TopologyRefiner> refiner;
  std::unique_ptr<Far::PatchTable> patchTable;
  std::unique_ptr<Far::PatchMap> patchMap;
  /// Refined vertices of every level (the control points first), then the local points.
  std::vector<Point> points;
  FaceCounts counts;

  void computePoints(const Eigen::MatrixXd& controlPoints) {
    for (int i = 0; i < numControlPoints; ++i)
      for (int c = 0; c < 3; ++c) points[std::size_t(i)].x[c] = controlPoints(i, c);
    Far::PrimvarRefinerReal<double> primvar(*refiner);
    Point* src = points.data();
    for (int level = 1; level < refiner->GetNumLevels(); ++level) {
      Point* dst = src + refiner->GetLevel(level - 1).GetNumVertices();
      primvar.Interpolate(level, src, dst);
      src = dst;
    }
    // The double-precision stencils: ComputeLocalPointValues would read float ones.
    if (patchTable->GetNumLocalPoints() > 0)
      patchTable->GetLocalPointStencilTable<double>()->UpdateValues(
          points.data(), points.data() + refiner->GetNumVerticesTotal());
  }

  void countFaces() {
    const int numFaces = static_cast<int>(firstPatchFace.size()) - 1;
    std::vector<int> baseOf(static_cast<std::size_t>(firstPatchFace.back()));
    for (int f = 0; f < numFaces; ++f)
      std::fill(baseOf.begin() + firstPatchFace[f], baseOf.begin() + firstPatchFace[f + 1], f);
    std::vector<char> hasPatch(std::size_t(numFaces), 0), irregular(std::size_t(numFaces), 0);
    for (int array = 0; array < patchTable->GetNumPatchArrays(); ++array) {
      const bool regularType =
          patchTable->GetPatchArrayDescriptor(array).GetType() == Far::PatchDescriptor::REGULAR;
      for (int patch = 0; patch < patchTable->GetNumPatches(array); ++patch) {
        const Far::PatchParam param = patchTable->GetPatchParam(array, patch);
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
    if (face < 0 || face >= firstPatchFace.back())
      throw InputError(std::string(kSource) + ": patch face " + std::to_string(face) +
                       " out of range (the net has " + std::to_string(firstPatchFace.back()) +
                       " patch faces)");
    if (!(u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0))
      throw InputError(std::string(kSource) + ": parameter (" + std::to_string(u) + ", " +
                       std::to_string(v) + ") of patch face " + std::to_string(face) +
                       " is outside [0,1]^2");
  }

  // The weights of the patch points at (u, v) of the patch face (w as in gregoryBasis), with
  // derivatives per unit of the patch face's u and v; returns the patch points.
  Far::ConstIndexArray weights(const Far::PatchTable::PatchHandle& handle, double u, double v,
                               double (*w)[kMaxPatchVertices], bool second) const {
    const Far::PatchParam param = patchTable->GetPatchParam(handle);
    const Far::ConstIndexArray cvs = patchTable->GetPatchVertices(handle);
    // The patch spans 2^-level of the patch face in each direction; level is the depth, minus one
    // on the sub-faces of non-quads, which start at depth 1.
    const double patchScale = double(1 << (param.GetDepth() - (param.NonQuadRoot() ? 1 : 0)));
    double factor = patchScale;  // from derivatives per unit of the patch
    if (patchTable->GetPatchDescriptor(handle).GetType() == Far::PatchDescriptor::GREGORY_BASIS) {
      double s = u, t = v;
      param.Normalize(s, t);
      gregoryBasis(s, t, w, second);
    } else {
      if (second)
        patchTable->EvaluateBasis(handle, u, v, w[0], w[1], w[2], w[3], w[4], w[5]);
      else
        patchTable->EvaluateBasis(handle, u, v, w[0], w[1], w[2]);
      // OpenSubdiv 3.5 scales derivatives by 2^depth, which is twice too much on non-quads'
      // sub-faces.
      factor = patchScale / double(1 << param.GetDepth());
    }
    if (factor != 1.0)
      for (int i = 0; i < cvs.size(); ++i) {
        w[1][i] *= factor;
        w[2][i] *= factor;
        if (second) {
          w[3][i] *= factor * factor;
          w[4][i] *= factor * factor;
          w[5][i] *= factor * factor;
        }
      }
    return cvs;
  }
};

CatmullClarkLimit::CatmullClarkLimit(const Eigen::MatrixXd& controlPoints,
                                     const std::vector<std::vector<int>>& faces,
                                     const CatmullClarkOptions& options)
    : tables_(std::make_unique<Tables>()) {
  if (options.isolationLevel < 1 || options.isolationLevel > 10)
    throw InputError(std::string(kSource) + ": isolation level " +
                     std::to_string(options.isolationLevel) + " is outside 1..10");
  checkPoints(controlPoints, -1);
  checkNet(controlPoints, faces);
  Tables& t = *tables_;
  t.options = options;
  t.numControlPoints = static_cast<int>(controlPoints.rows());

  std::vector<int> sizes, indices;
  sizes.reserve(faces.size());
  t.firstPatchFace.assign(1, 0);
  for (const auto& face : faces) {
    const int n = static_cast<int>(face.size());
    sizes.push_back(n);
    indices.insert(indices.end(), face.begin(), face.end());
    t.firstPatchFace.push_back(t.firstPatchFace.back() + (n == 4 ? 1 : n));
  }
  Far::TopologyDescriptor descriptor;
  descriptor.numVertices = t.numControlPoints;
  descriptor.numFaces = static_cast<int>(faces.size());
  descriptor.numVertsPerFace = sizes.data();
  descriptor.vertIndicesPerFace = indices.data();

  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(boundaryInterpolation(options.boundary));
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  t.refiner.reset(Factory::Create(descriptor, Factory::Options(Sdc::SCHEME_CATMARK, sdc)));
  if (!t.refiner) throw InputError(std::string(kSource) + ": OpenSubdiv rejected the topology");

  Far::PatchTableFactory::Options patchOptions(static_cast<unsigned>(options.isolationLevel));
  patchOptions.SetPatchPrecision<double>();
  patchOptions.endCapType = Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS;
  patchOptions.useInfSharpPatch = true;
  patchOptions.generateLegacySharpCornerPatches = false;
  patchOptions.generateVaryingTables = false;  // only vertex data is evaluated
  t.refiner->RefineAdaptive(patchOptions.GetRefineAdaptiveOptions());
  t.patchTable.reset(Far::PatchTableFactory::Create(*t.refiner, patchOptions));
  MSPLINE_ASSERT(t.patchTable->GetNumPtexFaces() == t.firstPatchFace.back(),
                 "OpenSubdiv counts other patch faces than the net's quads and polygon corners");
  for (int array = 0; array < t.patchTable->GetNumPatchArrays(); ++array)
    MSPLINE_ASSERT(
        t.patchTable->GetPatchArrayDescriptor(array).GetNumControlVertices() <= kMaxPatchVertices,
        "patch with more control points than a Gregory basis");
  t.patchMap = std::make_unique<Far::PatchMap>(*t.patchTable);

  t.points.resize(
      std::size_t(t.refiner->GetNumVerticesTotal() + t.patchTable->GetNumLocalPoints()));
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
  const Far::PatchTable::PatchHandle* handle = t.patchMap->FindPatch(face, u, v);
  if (!handle) return std::nullopt;
  double w[6][kMaxPatchVertices];
  const Far::ConstIndexArray cvs = t.weights(*handle, u, v, w, secondDerivatives);
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
  double w[6][kMaxPatchVertices];
  for (Eigen::Index k = 0; k < n; ++k) {
    const FaceParameter& p = points[std::size_t(k)];
    const Far::PatchTable::PatchHandle* handle = t.patchMap->FindPatch(p.face, p.u, p.v);
    if (!handle) {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      out.position.row(k).setConstant(nan);
      out.du.row(k).setConstant(nan);
      out.dv.row(k).setConstant(nan);
      continue;
    }
    const Far::ConstIndexArray cvs = t.weights(*handle, p.u, p.v, w, false);
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
  return static_cast<int>(tables_->firstPatchFace.size()) - 1;
}

int CatmullClarkLimit::numPatchFaces() const {
  return tables_->firstPatchFace.back();
}

int CatmullClarkLimit::firstPatchFace(int baseFace) const {
  if (baseFace < 0 || baseFace > numBaseFaces())
    throw InputError(std::string(kSource) + ": base face " + std::to_string(baseFace) +
                     " out of range (the net has " + std::to_string(numBaseFaces()) + " faces)");
  return tables_->firstPatchFace[std::size_t(baseFace)];
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
