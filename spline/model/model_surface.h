#pragma once
// A spline model's surface, whatever its kind, as export and the viewer need it: a watertight
// tessellation with normals and chart coordinates, the control net, and per tessellation vertex
// the basis functions it is a combination of, so that moving control points re-evaluates only
// the vertices in their supports (SurfaceSamples).
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "mspline/spline/core/spline_model.h"
#include "mspline/spline/fitting/fit_space.h"
#include "mspline/structure/mesh/polygon_soup.h"

namespace mspline::spline {

/// Per tessellation vertex, the surface point as a linear function of the control points:
/// position = sum_k value_k c_k over the vertex's row of `value`. Rows of the vertices that stand
/// for a point where the surface is undefined (ModelTessellation::meanVertices: the samples that
/// close a cone's hole) are the mean of their evaluations; `ds` and `dt` hold the first
/// derivatives in the frame of the evaluated point's face for every other vertex (the normal is
/// ds x dt normalized) and are empty rows for the means (their normals come from the triangles
/// around them). Only non-zero entries are stored (ds and dt share the pattern of the terms with a
/// non-zero derivative).
struct SurfaceSamples {
  /// vertices x control points, row-major (a row is one vertex's evaluation).
  Eigen::SparseMatrix<double, Eigen::RowMajor> value, ds, dt;
  /// Per vertex: 1 when it is one of the tessellation's meanVertices (ds, dt rows empty).
  std::vector<char> isMean;
};

/// A figure of a tessellation for reports.
struct TessellationFigure {
  std::string name;
  double value = 0.0;
  /// A count (to report as a whole number).
  bool count = false;
};

/// The tessellation of ModelSurface::tessellate.
struct ModelTessellation {
  /// Triangles, counter-clockwise in the chart frames.
  structure::PolygonSoup mesh;
  /// Per vertex: unit normal (as tessellate.h / tspline_tessellate.h define it).
  std::vector<std::array<double, 3>> normals;
  /// Per vertex: chart coordinates (position in its sampling face's frame).
  std::vector<std::array<double, 2>> uvs;
  /// Vertices that stand for a cone point of the structure (a T-mesh's extraordinary vertex, a
  /// triangular B-spline's cone vertex), ascending.
  std::vector<std::int64_t> coneVertices;
  /// Vertices that stand for a point where the surface is undefined (the hole samples of a T-mesh
  /// surface: a T-spline's around its extraordinary vertices; a triangular B-spline's cone
  /// samples), ascending: their position is the mean of the surface around that point, their
  /// normal not the surface's at a point.
  std::vector<std::int64_t> meanVertices;
  /// The kind's own figures for reports, in report order (min_denominator, hole_samples, ...).
  std::vector<TessellationFigure> report;
  /// Where the surface was evaluated: vertex v's position is the mean of the surface at
  /// samplePoints[sampleOffsets[v] .. sampleOffsets[v + 1]) (one point for most vertices;
  /// several for the samples that close a hole around a cone). sampleOffsets has one entry more
  /// than there are vertices.
  std::vector<std::int64_t> sampleOffsets;
  std::vector<FacePoint> samplePoints;
};

/// The control net: points are control point rows, lines join two of them.
struct ModelControlNet {
  /// Control point rows shown as net points: a T-spline's anchored T-mesh vertices' in vertex
  /// order (which is row order), every row for the other kinds.
  std::vector<int> points;
  /// Pairs of control point rows: the T-mesh edges between two vertices with control points, the
  /// triangular B-spline's beta -- beta - e_i + e_j within each domain face.
  std::vector<std::array<int, 2>> lines;
  /// Control point rows at an extraordinary T-mesh vertex (valence other than 4), ascending: a
  /// subdivision net's; none for a T-spline, which anchors no function there (or a triangular
  /// B-spline).
  std::vector<int> extraordinary;
  /// Control point rows at a T-junction (a T-mesh vertex inside a side of a face), ascending.
  std::vector<int> tJunctions;
};

/// A model's spline space, built once: evaluation state for its kind.
class ModelSurface {
 public:
  /// Builds the model's space; throws InputError (prefixed with `name`) when the model's
  /// structure is invalid for its kind or the control points or weights do not fit it. Keeps no
  /// reference to `model`.
  ModelSurface(const SplineModel& model, const std::string& name);
  ~ModelSurface();
  ModelSurface(const ModelSurface&) = delete;
  ModelSurface& operator=(const ModelSurface&) = delete;

  SplineKind kind() const;
  /// "tribspline", "tspline" or "subd".
  std::string kindName() const;
  int numControlPoints() const;
  /// The space as fitting sees it (basis with derivatives at a parameter).
  const FitSpace& fitSpace() const;

  /// The surface with control points `control` (numControlPoints x 3) sampled `resolution` times
  /// along every side of every face (resolution >= 1): tessellate.h's tessellation for a
  /// triangular B-spline, tspline_tessellate.h's for the others. Throws InputError (prefixed with
  /// the name) as those do.
  ModelTessellation tessellate(const Eigen::MatrixXd& control, int resolution) const;
  /// The tessellation's vertices as functions of the control points (FitSpace::basisAt at its
  /// sample points, on all cores).
  SurfaceSamples samples(const ModelTessellation& tessellation) const;
  ModelControlNet controlNet() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mspline::spline
