#include "mspline/spline/subd/subd_fit_space.h"

#include <algorithm>
#include <array>
#include <string>
#include <utility>

#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include "mspline/spline/subd/osd_patches.h"
#include "mspline/spline/subd/tspline_osd.h"
#include "mspline/spline/tspline/tmesh_walk.h"
#include "mspline/spline/tspline/tspline_fit_space.h"
#include "mspline/structure/core/errors.h"

namespace mspline::spline {

namespace Far = OpenSubdiv::Far;
using structure::InputError;

namespace {

const char* const kSource = "Catmull-Clark fit space";

}  // namespace

struct SubdSpace::Tables {
  TMesh mesh;
  // As CatmullClarkLimit's, so that the two are one surface.
  OsdPatches osd;
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
    options.maxLevel = osd.refiner->GetMaxLevel();
    const std::unique_ptr<const Far::StencilTableReal<double>> base(
        Factory::Create(*osd.refiner, options));
    const int refined = osd.refiner->GetNumVerticesTotal();
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
    const Far::StencilTableReal<double>* local =
        osd.patchTable->GetLocalPointStencilTable<double>();
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
  checkIsolationLevel(options, kSource);
  Tables& t = *tables_;
  t.mesh = std::move(mesh);
  const std::vector<std::vector<int>> faces = catmullClarkNetFaces(t.mesh, kSource);
  if (faces.empty()) throw InputError(std::string(kSource) + ": the T-mesh has no faces");
  t.osd = buildOsdPatches(t.mesh.numVertices, faces, options, kSource);
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
  const Far::PatchTable::PatchHandle* handle = t.osd.patchMap->FindPatch(face, u, v);
  if (!handle) return;
  const bool second = derivatives >= 2;
  double w[6][kMaxOsdPatchVertices];
  const Far::ConstIndexArray cvs = osdPatchWeights(*t.osd.patchTable, *handle, u, v, w, second);
  // Into the face frame: d/dx = d/du / width.
  const double fx = 1.0 / f.width, fy = 1.0 / f.height;
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

void SubdFitSpace::basisAt(const FacePoint& p, std::vector<FitBasisTerm>& out,
                           int derivatives) const {
  space_.basisAt(p.face, p.position, out, derivatives);
}

FacePoint SubdFitSpace::walk(const FacePoint& p, const Eigen::Vector2d& step) const {
  const FacePoint end = walkTMesh(space_.mesh(), FacePoint{p.face, p.position}, step);
  return {end.face, end.position};
}

double SubdFitSpace::faceSize(int face) const {
  return tmeshFaceSize(space_.mesh(), face);
}

void SubdFitSpace::quadrature(std::vector<FacePoint>& nodes, std::vector<double>& weights) const {
  tmeshQuadrature(space_.mesh(), nodes, weights);
}

}  // namespace mspline::spline
