#include "spline/subd_fit_space.h"

#include <algorithm>
#include <array>
#include <string>
#include <utility>

#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include "spline/tmesh_walk.h"
#include "spline/tspline_fit_space.h"
#include "spline/tspline_osd.h"
#include "structure/errors.h"

namespace mspline::spline {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;
using structure::InputError;

namespace {

const char* const kSource = "Catmull-Clark fit space";

// The largest patch OpenSubdiv builds for Catmull-Clark: a Gregory basis end cap.
constexpr int kMaxPatchVertices = 20;

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

// The weights of OpenSubdiv's 20-point Gregory basis patch at (s, t) with the exact derivatives of
// its rational interior weights, as CatmullClarkLimit evaluates them (catmull_clark_limit.cpp's
// gregoryBasis, which is private to that file): OpenSubdiv's EvaluateBasis leaves its derivatives
// about 1% off those of the position, and fitting needs the true ones. w[0] position, w[1], w[2]
// the s and t derivatives, w[3..5] (with `second`) ss, st, tt.
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
    // At the corner itself (d = 0) the Bezier factor and its first derivatives vanish.
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

}  // namespace

struct SubdSpace::Tables {
  TMesh mesh;
  std::unique_ptr<Far::TopologyRefiner> refiner;
  std::unique_ptr<Far::PatchTable> patchTable;
  std::unique_ptr<Far::PatchMap> patchMap;
  // Per patch point (refined vertices of every level, the net's first, then the local points of
  // the end caps): its stencil over the net's points, stencilIndex/Weight[stencilStart[i] ..
  // stencilStart[i + 1]).
  std::vector<int> stencilStart, stencilIndex;
  std::vector<double> stencilWeight;

  void buildStencils() {
    using Factory = Far::StencilTableFactoryReal<double>;
    Factory::Options options;
    options.generateControlVerts = true;
    options.generateIntermediateLevels = true;
    options.factorizeIntermediateLevels = true;
    options.generateOffsets = true;
    options.maxLevel = refiner->GetMaxLevel();
    const std::unique_ptr<const Far::StencilTableReal<double>> base(
        Factory::Create(*refiner, options));
    const int refined = refiner->GetNumVerticesTotal();
    MSPLINE_ASSERT(base->GetNumStencils() == refined,
                   "OpenSubdiv's stencils do not cover every refined vertex");
    stencilStart.assign(1, 0);
    for (int i = 0; i < refined; ++i) {
      const auto stencil = base->GetStencil(Far::Index(i));
      for (int k = 0; k < stencil.GetSize(); ++k) {
        stencilIndex.push_back(stencil.GetVertexIndices()[k]);
        stencilWeight.push_back(stencil.GetWeights()[k]);
      }
      stencilStart.push_back(int(stencilIndex.size()));
    }
    // Local points combine refined vertices: expand them into net points.
    const Far::StencilTableReal<double>* local = patchTable->GetLocalPointStencilTable<double>();
    if (!local) return;
    std::vector<std::pair<int, double>> terms;
    for (int j = 0; j < local->GetNumStencils(); ++j) {
      const auto stencil = local->GetStencil(Far::Index(j));
      terms.clear();
      for (int k = 0; k < stencil.GetSize(); ++k) {
        const int source = stencil.GetVertexIndices()[k];
        MSPLINE_ASSERT(source >= 0 && source < refined, "local point stencil out of range");
        for (int m = stencilStart[source]; m < stencilStart[source + 1]; ++m)
          terms.emplace_back(stencilIndex[m], stencil.GetWeights()[k] * stencilWeight[m]);
      }
      std::sort(terms.begin(), terms.end(),
                [](const auto& a, const auto& b) { return a.first < b.first; });
      for (std::size_t m = 0; m < terms.size(); ++m) {
        if (m > 0 && terms[m].first == terms[m - 1].first) {
          stencilWeight.back() += terms[m].second;
          continue;
        }
        stencilIndex.push_back(terms[m].first);
        stencilWeight.push_back(terms[m].second);
      }
      stencilStart.push_back(int(stencilIndex.size()));
    }
  }
};

SubdSpace::SubdSpace(TMesh mesh, const CatmullClarkOptions& options)
    : tables_(std::make_unique<Tables>()) {
  if (options.isolationLevel < 1 || options.isolationLevel > 10)
    throw InputError(std::string(kSource) + ": isolation level " +
                     std::to_string(options.isolationLevel) + " is outside 1..10");
  Tables& t = *tables_;
  t.mesh = std::move(mesh);
  const std::vector<std::vector<int>> faces = catmullClarkNetFaces(t.mesh, kSource);
  if (faces.empty()) throw InputError(std::string(kSource) + ": the T-mesh has no faces");
  std::vector<int> sizes(faces.size(), 4), indices;
  for (const auto& face : faces) indices.insert(indices.end(), face.begin(), face.end());
  Far::TopologyDescriptor descriptor;
  descriptor.numVertices = t.mesh.numVertices;
  descriptor.numFaces = int(faces.size());
  descriptor.numVertsPerFace = sizes.data();
  descriptor.vertIndicesPerFace = indices.data();

  // As CatmullClarkLimit, so that the two are one surface.
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
  patchOptions.generateVaryingTables = false;
  t.refiner->RefineAdaptive(patchOptions.GetRefineAdaptiveOptions());
  t.patchTable.reset(Far::PatchTableFactory::Create(*t.refiner, patchOptions));
  MSPLINE_ASSERT(t.patchTable->GetNumPtexFaces() == t.mesh.numFaces(),
                 "OpenSubdiv counts other patch faces than the T-mesh's faces");
  for (int array = 0; array < t.patchTable->GetNumPatchArrays(); ++array)
    MSPLINE_ASSERT(
        t.patchTable->GetPatchArrayDescriptor(array).GetNumControlVertices() <= kMaxPatchVertices,
        "patch with more control points than a Gregory basis");
  t.patchMap = std::make_unique<Far::PatchMap>(*t.patchTable);
  t.buildStencils();
}

SubdSpace::~SubdSpace() = default;
SubdSpace::SubdSpace(SubdSpace&&) noexcept = default;
SubdSpace& SubdSpace::operator=(SubdSpace&&) noexcept = default;

const TMesh& SubdSpace::mesh() const {
  return tables_->mesh;
}

int SubdSpace::numBasis() const {
  return tables_->mesh.numVertices;
}

void SubdSpace::basisAt(int face, const Eigen::Vector2d& p, std::vector<FitBasisTerm>& out,
                        int derivatives) const {
  const Tables& t = *tables_;
  out.clear();
  if (face < 0 || face >= t.mesh.numFaces())
    throw InputError(std::string(kSource) + ": face " + std::to_string(face) + " out of range (" +
                     std::to_string(t.mesh.numFaces()) + " faces)");
  if (!p.allFinite())
    throw InputError(std::string(kSource) + ": a point of face " + std::to_string(face) +
                     " is not finite");
  const TMeshFace& f = t.mesh.faces[std::size_t(face)];
  const double u = std::clamp(p.x() / f.width, 0.0, 1.0);
  const double v = std::clamp(p.y() / f.height, 0.0, 1.0);
  const Far::PatchTable::PatchHandle* handle = t.patchMap->FindPatch(face, u, v);
  if (!handle) return;
  const bool second = derivatives >= 2;
  double w[6][kMaxPatchVertices];
  const Far::PatchParam param = t.patchTable->GetPatchParam(*handle);
  const Far::ConstIndexArray cvs = t.patchTable->GetPatchVertices(*handle);
  // Derivatives per unit of the patch face (EvaluateBasis gives them so; the Gregory basis per
  // unit of the patch, which spans 2^-depth of the face).
  double factor = 1.0;
  if (t.patchTable->GetPatchDescriptor(*handle).GetType() == Far::PatchDescriptor::GREGORY_BASIS) {
    double s = u, r = v;
    param.Normalize(s, r);
    gregoryBasis(s, r, w, second);
    factor = double(1 << param.GetDepth());
  } else if (second) {
    t.patchTable->EvaluateBasis(*handle, u, v, w[0], w[1], w[2], w[3], w[4], w[5]);
  } else {
    t.patchTable->EvaluateBasis(*handle, u, v, w[0], w[1], w[2]);
  }
  // Into the face frame: d/dx = d/du / width.
  const double fx = factor / f.width, fy = factor / f.height;
  thread_local std::vector<FitBasisTerm> terms;
  terms.clear();
  for (int i = 0; i < cvs.size(); ++i) {
    const int point = cvs[i];
    for (int m = t.stencilStart[point]; m < t.stencilStart[point + 1]; ++m) {
      const double c = t.stencilWeight[std::size_t(m)];
      FitBasisTerm term;
      term.index = t.stencilIndex[std::size_t(m)];
      term.value = c * w[0][i];
      if (derivatives >= 1) {
        term.ds = c * w[1][i] * fx;
        term.dt = c * w[2][i] * fy;
      }
      if (second) {
        term.dss = c * w[3][i] * fx * fx;
        term.dst = c * w[4][i] * fx * fy;
        term.dtt = c * w[5][i] * fy * fy;
      }
      terms.push_back(term);
    }
  }
  std::sort(terms.begin(), terms.end(),
            [](const FitBasisTerm& a, const FitBasisTerm& b) { return a.index < b.index; });
  for (const FitBasisTerm& term : terms) {
    if (!out.empty() && out.back().index == term.index) {
      FitBasisTerm& sum = out.back();
      sum.value += term.value;
      sum.ds += term.ds;
      sum.dt += term.dt;
      sum.dss += term.dss;
      sum.dst += term.dst;
      sum.dtt += term.dtt;
    } else {
      out.push_back(term);
    }
  }
}

bool SubdSpace::evaluate(const Eigen::MatrixXd& control, int face, const Eigen::Vector2d& p,
                         Eigen::Vector3d& position, Eigen::Vector3d* ds,
                         Eigen::Vector3d* dt) const {
  if (control.rows() != numBasis() || control.cols() != 3)
    throw InputError(std::string(kSource) + ": control points must be " +
                     std::to_string(numBasis()) + " x 3, got " + std::to_string(control.rows()) +
                     " x " + std::to_string(control.cols()));
  thread_local std::vector<FitBasisTerm> terms;
  basisAt(face, p, terms, ds || dt ? 1 : 0);
  if (terms.empty()) return false;
  position.setZero();
  if (ds) ds->setZero();
  if (dt) dt->setZero();
  for (const FitBasisTerm& term : terms) {
    const auto c = control.row(term.index).transpose();
    position += term.value * c;
    if (ds) *ds += term.ds * c;
    if (dt) *dt += term.dt * c;
  }
  return true;
}

void SubdFitSpace::basisAt(const FitParameter& p, std::vector<FitBasisTerm>& out,
                           int derivatives) const {
  space_.basisAt(p.face, p.position, out, derivatives);
}

FitParameter SubdFitSpace::walk(const FitParameter& p, const Eigen::Vector2d& step) const {
  const TMeshPoint end = walkTMesh(space_.mesh(), TMeshPoint{p.face, p.position}, step);
  return {end.face, end.position};
}

double SubdFitSpace::faceSize(int face) const {
  return tmeshFaceSize(space_.mesh(), face);
}

void SubdFitSpace::quadrature(std::vector<FitParameter>& nodes,
                              std::vector<double>& weights) const {
  tmeshQuadrature(space_.mesh(), nodes, weights);
}

}  // namespace mspline::spline
