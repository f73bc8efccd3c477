#include "mspline/spline/model/model_surface.h"

#include <algorithm>
#include <iterator>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include <tbb/parallel_for.h>

#include "mspline/spline/subd/subd_fit_space.h"
#include "mspline/spline/subd/subd_tessellate.h"
#include "mspline/spline/tribspline/tessellate.h"
#include "mspline/spline/tribspline/tri_bspline.h"
#include "mspline/spline/tribspline/tri_bspline_fit_space.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_fit_space.h"
#include "mspline/spline/tspline/tspline_tessellate.h"
#include "mspline/structure/core/errors.h"

namespace mspline::spline {

using structure::InputError;

namespace {

// Vertices per task of samples(): large enough that a task's bookkeeping is negligible.
constexpr std::size_t kSampleChunk = 2048;

// Calls edge(a, b) once for every T-mesh edge (vertices a to b).
template <class Edge>
void forEachTMeshEdge(const TMesh& mesh, Edge&& edge) {
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const TMeshFace& face = mesh.faces[std::size_t(f)];
    const std::size_t n = face.vertices.size();
    for (std::size_t k = 0; k < n; ++k) {
      const int g = face.twinFace[k];
      if (g >= 0 && (g < f || (g == f && std::size_t(face.twinEdge[k]) < k))) continue;
      edge(face.vertices[k], face.vertices[(k + 1) % n]);
    }
  }
}

// The net of a T-mesh whose vertex v has control point row rowOf[v] (-1: none, the vertex and its
// edges are left out).
ModelControlNet tmeshNet(const TMesh& mesh, const std::vector<int>& rowOf) {
  ModelControlNet net;
  for (int v = 0; v < mesh.numVertices; ++v) {
    const int row = rowOf[std::size_t(v)];
    if (row < 0) continue;
    net.points.push_back(row);
    if (mesh.isExtraordinary(v)) net.extraordinary.push_back(row);
  }
  forEachTMeshEdge(mesh, [&](int from, int to) {
    const int p = rowOf[std::size_t(from)], q = rowOf[std::size_t(to)];
    if (p >= 0 && q >= 0) net.lines.push_back({p, q});
  });
  // A T-junction is a face's boundary vertex that is no corner of its rectangle.
  for (const TMeshFace& face : mesh.faces) {
    const Eigen::Vector2d corners[4] = {
        {0.0, 0.0}, {face.width, 0.0}, {face.width, face.height}, {0.0, face.height}};
    const double tolerance = 1e-9 * std::max(face.width, face.height);
    for (std::size_t k = 0; k < face.vertices.size(); ++k) {
      const int row = rowOf[std::size_t(face.vertices[k])];
      const bool corner = std::any_of(std::begin(corners), std::end(corners), [&](const auto& c) {
        return (face.positions[k] - c).norm() <= tolerance;
      });
      if (row >= 0 && !corner) net.tJunctions.push_back(row);
    }
  }
  std::sort(net.extraordinary.begin(), net.extraordinary.end());
  std::sort(net.tJunctions.begin(), net.tJunctions.end());
  net.tJunctions.erase(std::unique(net.tJunctions.begin(), net.tJunctions.end()),
                       net.tJunctions.end());
  return net;
}

// The parts of a T-mesh tessellation every T-mesh kind shares.
ModelTessellation fromTMeshTessellation(TMeshTessellation t, const TMesh& mesh) {
  ModelTessellation out;
  out.mesh = std::move(t.mesh);
  out.normals = std::move(t.normals);
  out.uvs = std::move(t.uvs);
  // T-mesh vertex v is sampled by mesh vertex v.
  for (int v = 0; v < mesh.numVertices; ++v)
    if (mesh.isExtraordinary(v)) out.coneVertices.push_back(v);
  out.meanVertices.assign(t.holeVertices.begin(), t.holeVertices.end());
  out.sampleOffsets = std::move(t.sampleOffsets);
  out.samplePoints.reserve(t.samplePoints.size());
  for (const FacePoint& p : t.samplePoints) out.samplePoints.push_back({p.face, p.position});
  return out;
}

// One vertex's term of samples(): a control point row with the value and derivatives there.
struct SampleTerm {
  int index;
  double value, ds, dt;
};

// Consecutive rows of a sparse matrix: entries per row, and their (column, value) pairs, columns
// ascending within a row.
struct RowRun {
  std::vector<int> counts, columns;
  std::vector<double> values;
};

// samples()'s rows of a run of vertices.
struct SampleRows {
  RowRun value, ds, dt;
};

// The row-major matrix of the runs `part` of `chunks`, one after the other.
Eigen::SparseMatrix<double, Eigen::RowMajor> assembleRows(Eigen::Index rows, Eigen::Index columns,
                                                          const std::vector<SampleRows>& chunks,
                                                          RowRun SampleRows::*part) {
  Eigen::SparseMatrix<double, Eigen::RowMajor> m(rows, columns);
  std::size_t total = 0;
  for (const SampleRows& c : chunks) total += (c.*part).columns.size();
  MSPLINE_ASSERT(total <= std::size_t(std::numeric_limits<int>::max()),
                 "too many basis terms for one sparse matrix");
  m.resizeNonZeros(Eigen::Index(total));
  int* outer = m.outerIndexPtr();
  outer[0] = 0;
  Eigen::Index row = 0;
  std::size_t at = 0;
  for (const SampleRows& c : chunks) {
    const RowRun& run = c.*part;
    for (int count : run.counts) {
      outer[row + 1] = outer[row] + count;
      ++row;
    }
    std::copy(run.columns.begin(), run.columns.end(), m.innerIndexPtr() + at);
    std::copy(run.values.begin(), run.values.end(), m.valuePtr() + at);
    at += run.columns.size();
  }
  MSPLINE_ASSERT(row == rows, "one row per vertex");
  return m;
}

}  // namespace

struct ModelSurface::Impl {
  SplineKind kind = SplineKind::TriangularBSpline;
  std::string name;
  // The space of the model's kind (one of them), and it as fitting sees it (which keeps
  // references to the space and the weights).
  std::unique_ptr<TriBSplineSpace> triBSpline;
  std::unique_ptr<TSplineSpace> tSpline;
  std::unique_ptr<SubdSpace> subd;
  Eigen::VectorXd weights;
  std::unique_ptr<FitSpace> fit;

  const TMesh& tmesh() const { return tSpline ? tSpline->mesh() : subd->mesh(); }
};

ModelSurface::ModelSurface(const SplineModel& model, const std::string& name)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.kind = model.kind;
  m.name = name;
  std::string what;  // what the control points have to fit
  try {
    if (model.kind == SplineKind::TSpline) {
      m.tSpline = std::make_unique<TSplineSpace>(model.tmesh);
      m.weights = model.weights;
      m.fit = std::make_unique<TSplineFitSpace>(*m.tSpline, m.weights);
      what = "the T-spline";
    } else if (model.kind == SplineKind::Subdivision) {
      m.subd = std::make_unique<SubdSpace>(model.tmesh);
      m.fit = std::make_unique<SubdFitSpace>(*m.subd);
      what = "the subdivision net";
    } else {
      m.triBSpline = std::make_unique<TriBSplineSpace>(model.domain, model.knots);
      m.fit = std::make_unique<TriBSplineFitSpace>(*m.triBSpline);
      what = "the spline";
    }
  } catch (const InputError& e) {
    throw InputError(name + ": " + e.what());
  }
  if (model.controlPoints.rows() != m.fit->numBasis() || model.controlPoints.cols() != 3)
    throw InputError(name + ": the control points do not fit " + what + " (" +
                     std::to_string(model.controlPoints.rows()) + " x " +
                     std::to_string(model.controlPoints.cols()) + " for " +
                     std::to_string(m.fit->numBasis()) + " functions)");
  if (m.tSpline && m.weights.size() != 0 && m.weights.size() != m.fit->numBasis())
    throw InputError(name + ": the weights do not fit the T-spline (" +
                     std::to_string(m.weights.size()) + " for " +
                     std::to_string(m.fit->numBasis()) + " functions)");
}

ModelSurface::~ModelSurface() = default;

SplineKind ModelSurface::kind() const {
  return impl_->kind;
}

std::string ModelSurface::kindName() const {
  return impl_->tSpline ? "tspline" : impl_->subd ? "subd" : "tribspline";
}

int ModelSurface::numControlPoints() const {
  return impl_->fit->numBasis();
}

const FitSpace& ModelSurface::fitSpace() const {
  return *impl_->fit;
}

ModelTessellation ModelSurface::tessellate(const Eigen::MatrixXd& control, int resolution) const {
  const Impl& m = *impl_;
  try {
    if (m.tSpline) {
      TSplineTessellation t = tessellateTSpline(*m.tSpline, control, m.weights, resolution);
      std::vector<TessellationFigure> report{
          {"min_denominator", t.minDenominator, false},
          {"hole_samples", double(t.holeVertices.size()), true},
          {"hole_offset", t.holeOffset, false},
          {"collapsed_edge_samples", double(t.collapsedEdgeSamples), true}};
      ModelTessellation out = fromTMeshTessellation(std::move(t), m.tmesh());
      out.report = std::move(report);
      return out;
    }
    if (m.subd)
      return fromTMeshTessellation(tessellateSubd(*m.subd, control, resolution), m.tmesh());
    Tessellation t = spline::tessellate(*m.triBSpline, control, resolution);
    ModelTessellation out;
    out.mesh = std::move(t.mesh);
    out.normals = std::move(t.normals);
    out.uvs = std::move(t.uvs);
    out.coneVertices = t.coneSamples;
    out.meanVertices = t.coneSamples;
    out.report = {{"min_denominator", t.minDenominator, false},
                  {"cone_vertices", double(t.coneVertices), true}};
    out.sampleOffsets = std::move(t.sampleOffsets);
    out.samplePoints.reserve(t.samplePoints.size());
    for (const SurfacePoint& p : t.samplePoints)
      out.samplePoints.push_back(toFitParameter(*m.triBSpline, p));
    return out;
  } catch (const InputError& e) {
    throw InputError(m.name + ": " + e.what());
  }
}

SurfaceSamples ModelSurface::samples(const ModelTessellation& tessellation) const {
  const FitSpace& space = *impl_->fit;
  const std::size_t vertices = tessellation.mesh.positions.size();
  MSPLINE_ASSERT(
      tessellation.sampleOffsets.size() == vertices + 1 &&
          std::size_t(tessellation.sampleOffsets.back()) == tessellation.samplePoints.size(),
      "one run of sample points per tessellation vertex");
  SurfaceSamples out;
  out.isMean.assign(vertices, 0);
  for (std::int64_t v : tessellation.meanVertices) out.isMean[std::size_t(v)] = 1;

  std::vector<SampleRows> chunks((vertices + kSampleChunk - 1) / kSampleChunk);
  tbb::parallel_for(std::size_t(0), chunks.size(), [&](std::size_t c) {
    SampleRows& rows = chunks[c];
    std::vector<FitBasisTerm> basis;
    std::vector<SampleTerm> terms;
    for (std::size_t v = c * kSampleChunk; v < std::min(vertices, (c + 1) * kSampleChunk); ++v) {
      const bool mean = out.isMean[v];
      const std::int64_t begin = tessellation.sampleOffsets[v],
                         end = tessellation.sampleOffsets[v + 1];
      const double share = 1.0 / double(end - begin);
      terms.clear();
      for (std::int64_t k = begin; k < end; ++k) {
        space.basisAt(tessellation.samplePoints[std::size_t(k)], basis, mean ? 0 : 1);
        MSPLINE_ASSERT(!basis.empty(), "the surface is defined where the tessellation sampled it");
        for (const FitBasisTerm& b : basis)
          terms.push_back({b.index, share * b.value, share * b.ds, share * b.dt});
      }
      // One term per control point, ascending (the means' points share functions).
      std::sort(terms.begin(), terms.end(),
                [](const SampleTerm& a, const SampleTerm& b) { return a.index < b.index; });
      int values = 0, derivatives = 0;
      for (std::size_t i = 0; i < terms.size();) {
        SampleTerm sum = terms[i];
        for (++i; i < terms.size() && terms[i].index == sum.index; ++i) {
          sum.value += terms[i].value;
          sum.ds += terms[i].ds;
          sum.dt += terms[i].dt;
        }
        if (sum.value != 0.0) {
          rows.value.columns.push_back(sum.index);
          rows.value.values.push_back(sum.value);
          ++values;
        }
        if (!mean && (sum.ds != 0.0 || sum.dt != 0.0)) {
          rows.ds.columns.push_back(sum.index);
          rows.ds.values.push_back(sum.ds);
          rows.dt.columns.push_back(sum.index);
          rows.dt.values.push_back(sum.dt);
          ++derivatives;
        }
      }
      rows.value.counts.push_back(values);
      rows.ds.counts.push_back(derivatives);
      rows.dt.counts.push_back(derivatives);
    }
  });
  const auto n = Eigen::Index(vertices), columns = Eigen::Index(space.numBasis());
  out.value = assembleRows(n, columns, chunks, &SampleRows::value);
  out.ds = assembleRows(n, columns, chunks, &SampleRows::ds);
  out.dt = assembleRows(n, columns, chunks, &SampleRows::dt);
  return out;
}

ModelControlNet ModelSurface::controlNet() const {
  const Impl& m = *impl_;
  if (m.tSpline) return tmeshNet(m.tmesh(), m.tSpline->anchorOfVertex());
  if (m.subd) {
    std::vector<int> rowOf(std::size_t(m.tmesh().numVertices));
    std::iota(rowOf.begin(), rowOf.end(), 0);  // one net point per T-mesh vertex
    return tmeshNet(m.tmesh(), rowOf);
  }
  // Every row; per domain face, lines between the control points of beta and beta - e_i + e_j.
  const TriBSplineSpace& space = *m.triBSpline;
  ModelControlNet net;
  for (int k = 0; k < space.numBasis(); ++k) net.points.push_back(k);
  const int n = space.degree();
  // Row of beta within its face: beta_0 descending, then beta_1 descending (spline_model.h).
  std::vector<std::array<int, 3>> betas;
  for (int b0 = n; b0 >= 0; --b0)
    for (int b1 = n - b0; b1 >= 0; --b1) betas.push_back({b0, b1, n - b0 - b1});
  const auto rowOf = [&](const std::array<int, 3>& beta) {
    return int(std::find(betas.begin(), betas.end(), beta) - betas.begin());
  };
  for (int f = 0; f < space.domain().faceCount(); ++f)
    for (std::size_t k = 0; k < betas.size(); ++k)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          std::array<int, 3> other = betas[k];
          if (i == j || other[std::size_t(i)] == 0) continue;
          --other[std::size_t(i)];
          ++other[std::size_t(j)];
          const int row = rowOf(other);
          if (row > int(k))
            net.lines.push_back(
                {f * space.basisPerFace() + int(k), f * space.basisPerFace() + row});
        }
  return net;
}

}  // namespace mspline::spline
