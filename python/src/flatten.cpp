// mspline.flatten: structure::flattenSurface on arrays.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>

#include "mspline/structure/flatten/flatten_surface.h"
#include "python/src/arrays.h"
#include "python/src/pipelines.h"

namespace mspline::python {

namespace {

using structure::BoundaryShape;
using structure::MetricScheme;

MetricScheme metricScheme(const std::string& name) {
  for (const MetricScheme scheme :
       {MetricScheme::Yamabe, MetricScheme::Tangential, MetricScheme::Inversive})
    if (structure::metricSchemeName(scheme) == name) return scheme;
  throw py::value_error("flatten: scheme must be 'yamabe', 'tangential' or 'inversive', not '" +
                        name + "'");
}

BoundaryShape boundaryShape(const std::string& name) {
  if (name == "free") return BoundaryShape::Free;
  if (name == "fixed") return BoundaryShape::Fixed;
  if (name == "rectangle") return BoundaryShape::Rectangle;
  throw py::value_error("flatten: boundary must be 'free', 'fixed' or 'rectangle', not '" + name +
                        "'");
}

// The surface laid out (the input, or its common subdivision with the intrinsic triangulation
// when flips were needed) with its corners in the layout's order.
py::dict flatteningDict(const structure::Flattening& flattening) {
  const structure::TriMesh& surface = flattening.surface();
  std::vector<std::array<double, 3>> positions;
  for (const auto v : surface.vertices()) {
    const auto& p = surface.point(v);
    positions.push_back({p[0], p[1], p[2]});
  }
  std::vector<std::vector<std::int64_t>> faces;
  for (const auto f : surface.faces()) {
    std::vector<std::int64_t> corners;
    for (const auto v : surface.fv_range(f)) corners.push_back(v.idx());
    faces.push_back(corners);
  }
  const Eigen::MatrixXd& cornerUV = flattening.layout.cornerUV;
  DoubleArray uvs({py::ssize_t(cornerUV.rows() / 3), py::ssize_t(3), py::ssize_t(2)});
  auto uv = uvs.mutable_unchecked<3>();
  for (Eigen::Index row = 0; row < cornerUV.rows(); ++row)
    for (Eigen::Index j = 0; j < 2; ++j) uv(row / 3, row % 3, j) = cornerUV(row, j);
  py::list cones;
  for (const structure::Cone& cone : flattening.cones)
    cones.append(py::make_tuple(cone.vertex, cone.curvature));
  py::dict seconds;
  for (const auto& [stage, value] : flattening.stageSeconds) seconds[py::str(stage)] = value;

  py::dict out;
  out["V"] = pointsArray(positions);
  out["F"] = trianglesArray(faces);
  out["uvs"] = uvs;
  out["cones"] = cones;
  out["rejected_cone_counts"] = flattening.rejectedConeCounts;
  out["cone_placement"] = flattening.conePlacement;
  out["reached_max_cones"] = flattening.reachedMaxCones;
  out["converged"] = flattening.converged;
  out["message"] = flattening.message;
  out["iterations"] = flattening.flow.iterations;
  out["max_curvature_error"] = flattening.flow.maxCurvatureError;
  out["flips"] = flattening.flips;
  out["flipped_triangles"] = flattening.layout.flippedTriangles;
  out["seconds"] = seconds;
  return out;
}

py::dict flatten(const py::handle& vertices, const py::handle& faces,
                 const std::optional<std::vector<std::pair<int, double>>>& cones, int coneCount,
                 bool quantize, int maxConeQuarterTurns, bool singleCone, const std::string& scheme,
                 const std::string& boundary, double tolerance, int maxIterations,
                 const py::object& progress, const std::string& name) {
  const structure::PolygonSoup soup = toSoup(vertices, faces, name);
  structure::FlattenOptions options;
  if (cones) {
    options.cones.emplace();
    for (const auto& [vertex, curvature] : *cones) options.cones->push_back({vertex, curvature});
  }
  options.coneCount = coneCount;
  options.quantize = quantize;
  options.maxConeQuarterTurns = maxConeQuarterTurns;
  options.singleCone = singleCone;
  options.scheme = metricScheme(scheme);
  options.boundary = boundaryShape(boundary);
  options.tolerance = tolerance;
  options.maxIterations = maxIterations;
  options.name = name;
  const structure::Progress report = progressOf(progress, "flatten");
  // The mesh outlives the flattening, which may refer to it.
  std::optional<structure::TriMesh> mesh;
  std::optional<structure::Flattening> flattening;
  {
    py::gil_scoped_release release;
    mesh = validatedMesh(soup);
    flattening = structure::flattenSurface(*mesh, options, report);
  }
  return flatteningDict(*flattening);
}

}  // namespace

void bindFlatten(py::module_& module) {
  const structure::FlattenOptions defaults;
  module.def("flatten", &flatten, py::arg("V"), py::arg("F"), py::arg("cones") = py::none(),
             py::arg("cone_count") = defaults.coneCount, py::arg("quantize") = defaults.quantize,
             py::arg("max_cone_quarter_turns") = defaults.maxConeQuarterTurns,
             py::arg("single_cone") = defaults.singleCone,
             py::arg("scheme") = structure::metricSchemeName(defaults.scheme),
             py::arg("boundary") = "free", py::arg("tolerance") = defaults.tolerance,
             py::arg("max_iterations") = defaults.maxIterations, py::arg("progress") = py::none(),
             py::arg("name") = "<arrays>",
             "A flat metric with cones on the mesh (V, F), laid out, as `mspline flatten` "
             "computes it. cones: None (placed automatically, cone_count of them when >= 0) or "
             "(vertex, curvature) pairs ([] for none); quantize: cone curvatures multiples of "
             "pi/2, at most max_cone_quarter_turns; single_cone: genus >= 2, all curvature in "
             "one cone; scheme 'yamabe', 'tangential' or 'inversive'; boundary 'free', 'fixed' or "
             "'rectangle'; progress: None or a callable (stage, fraction). Returns a dict: V, F "
             "(the surface laid out: the input, or its subdivision by intrinsic flips), uvs "
             "(per corner of F, (m, 3, 2); empty when the flow did not converge), cones "
             "[(vertex, curvature)], converged, message, iterations, max_curvature_error, flips, "
             "flipped_triangles, seconds.");
}

}  // namespace mspline::python
