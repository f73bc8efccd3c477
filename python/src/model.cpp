#include "python/src/model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include <pybind11/numpy.h>
#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include "mspline/io/spline_model_file.h"
#include "mspline/spline/fitting/surface_fit.h"
#include "mspline/spline/quality/surface_quality.h"
#include "mspline/spline/tribspline/spline_domain.h"
#include "mspline/structure/core/errors.h"
#include "python/src/arrays.h"

namespace mspline::python {

namespace {

using spline::FacePoint;
using spline::SplineKind;
using spline::SplineModel;

// The parameter domain's faces: a triangular B-spline's domain triangles (positions in the frame
// of spline::canonicalCorners), a T-mesh's rectangles [0, width] x [0, height] otherwise.
int faceCount(const SplineModel& model) {
  return model.kind == SplineKind::TriangularBSpline ? model.domain.faceCount()
                                                     : model.tmesh.numFaces();
}

bool insideFace(const SplineModel& model, int face, const Eigen::Vector2d& uv) {
  constexpr double kSlack = 1e-9;  // relative to the face's size: positions on a side, rounded
  if (model.kind == SplineKind::TriangularBSpline)
    return spline::frameBarycentric(model.domain, face, uv).minCoeff() >= -kSlack;
  const spline::TMeshFace& f = model.tmesh.faces[std::size_t(face)];
  const double slack = kSlack * std::max(f.width, f.height);
  return uv.x() >= -slack && uv.y() >= -slack && uv.x() <= f.width + slack &&
         uv.y() <= f.height + slack;
}

// Uniform in the face (in its frame).
Eigen::Vector2d randomPointInFace(const SplineModel& model, int face, std::mt19937_64& random) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double s = unit(random), t = unit(random);
  if (model.kind == SplineKind::TriangularBSpline) {
    if (s + t > 1.0) {
      s = 1.0 - s;
      t = 1.0 - t;
    }
    const auto corners = spline::canonicalCorners(model.domain, face);
    return corners[0] + s * (corners[1] - corners[0]) + t * (corners[2] - corners[0]);
  }
  const spline::TMeshFace& f = model.tmesh.faces[std::size_t(face)];
  return {s * f.width, t * f.height};
}

// (faces, uvs) checked: a face of the domain each, its uv inside it.
std::vector<FacePoint> toParameters(const Model& self, const IndexArray& faces,
                                    const DoubleArray& uvs) {
  if (faces.shape(0) != uvs.shape(0))
    throw py::value_error("evaluate: " + std::to_string(faces.shape(0)) + " faces for " +
                          std::to_string(uvs.shape(0)) + " uvs");
  const auto face = faces.unchecked<1>();
  const auto uv = uvs.unchecked<2>();
  const int count = faceCount(self.model);
  std::vector<FacePoint> parameters;
  for (py::ssize_t k = 0; k < face.shape(0); ++k) {
    if (face(k) < 0 || face(k) >= count)
      throw py::value_error("evaluate: face " + std::to_string(face(k)) + " (entry " +
                            std::to_string(k) + ") is not one of the model's " +
                            std::to_string(count) + " faces");
    const FacePoint p{int(face(k)), {uv(k, 0), uv(k, 1)}};
    if (!insideFace(self.model, p.face, p.position))
      throw py::value_error("evaluate: uv (" + std::to_string(uv(k, 0)) + ", " +
                            std::to_string(uv(k, 1)) + ") (entry " + std::to_string(k) +
                            ") lies outside face " + std::to_string(p.face));
    parameters.push_back(p);
  }
  return parameters;
}

// The surface at every parameter, NaN where it is undefined (a cone point, a hole).
Eigen::MatrixXd evaluateAll(const Model& self, const std::vector<FacePoint>& parameters) {
  Eigen::MatrixXd points(Eigen::Index(parameters.size()), 3);
  tbb::parallel_for(std::size_t(0), parameters.size(), [&](std::size_t k) {
    points.row(Eigen::Index(k)) =
        spline::evaluateFitSurface(self.surface->fitSpace(), self.model.controlPoints,
                                   parameters[k])
            .transpose();
  });
  return points;
}

py::dict parametersDict(const Model& self, const std::vector<FacePoint>& parameters) {
  Eigen::MatrixXd uvs(Eigen::Index(parameters.size()), 2);
  std::vector<std::int64_t> faces;
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    faces.push_back(parameters[k].face);
    uvs.row(Eigen::Index(k)) = parameters[k].position.transpose();
  }
  py::dict out;
  out["faces"] = indexArray(faces);
  out["uvs"] = pointsArray(uvs);
  return out;
}

py::object evaluate(const Model& self, const py::handle& faces, const py::handle& uvs) {
  py::array faceArray = py::array::ensure(faces);
  const bool single = faceArray && faceArray.ndim() == 0;
  if (single) faceArray = faceArray.reshape({py::ssize_t(1)});
  const IndexArray faceIndices = indexMatrix(single ? py::handle(faceArray) : faces, "faces", 0);
  const std::vector<FacePoint> parameters =
      toParameters(self, faceIndices, realMatrix(uvs, "uvs", 2, single));
  Eigen::MatrixXd points;
  {
    py::gil_scoped_release release;
    points = evaluateAll(self, parameters);
  }
  DoubleArray out = pointsArray(points);
  return single ? py::object(out.reshape({py::ssize_t(3)})) : py::object(out);
}

// Projections start from the closest point of a tessellation this fine.
constexpr int kProjectionResolution = 4;
constexpr int kProjectionSteps = 30;

py::dict project(const Model& self, const py::handle& points) {
  const Eigen::MatrixX3d targets = toPoints(realMatrix(points, "points", 3));
  std::vector<FacePoint> parameters(std::size_t(targets.rows()));
  Eigen::VectorXd distances(targets.rows());
  Eigen::MatrixXd closest;
  {
    py::gil_scoped_release release;
    const spline::ModelTessellation tessellation =
        self.surface->tessellate(self.model.controlPoints, kProjectionResolution);
    const std::vector<spline::ClosestSurfacePoint> found = spline::closestSurfacePoints(
        *self.surface, self.model.controlPoints, tessellation, targets, {}, kProjectionSteps);
    // Where the spline is undefined at every start: no point.
    for (std::size_t k = 0; k < found.size(); ++k) {
      parameters[k] = found[k].onSpline ? found[k].parameter : FacePoint{};
      distances[Eigen::Index(k)] =
          found[k].onSpline ? found[k].distance : std::numeric_limits<double>::quiet_NaN();
    }
    closest = evaluateAll(self, parameters);
  }
  py::dict out = parametersDict(self, parameters);
  out["points"] = pointsArray(closest);
  DoubleArray distanceArray(distances.size());
  std::copy(distances.begin(), distances.end(), distanceArray.mutable_data());
  out["distances"] = distanceArray;
  return out;
}

// The area element |S_s x S_t| at `p` (NaN where the surface is undefined).
double areaElement(const spline::FitSpace& space, const Eigen::MatrixXd& control,
                   const FacePoint& p, std::vector<spline::FitBasisTerm>& terms) {
  Eigen::Vector3d ds, dt;
  if (!spline::evaluateFitTangents(space, control, p, terms, ds, dt))
    return std::numeric_limits<double>::quiet_NaN();
  return ds.cross(dt).norm();
}

// Points uniform by surface area, by rejection: a face drawn by its parameter area times a bound
// on its area element, a uv uniform in it, kept with probability area element / bound. The bound
// is twice the largest area element at the space's quadrature nodes in the face; a draw that
// exceeds it raises it, and the points kept so far, drawn under a bound that was not one, are
// drawn again. Drawing faces by their area and uv uniform in them, as it was, put too many points
// where a face's parameterization compresses the surface.
py::dict sample(const Model& self, int count, unsigned long long seed) {
  if (count < 0) throw py::value_error("sample: a negative count (" + std::to_string(count) + ")");
  std::vector<FacePoint> parameters;
  Eigen::MatrixXd points(count, 3);
  {
    py::gil_scoped_release release;
    const spline::FitSpace& space = self.surface->fitSpace();
    const Eigen::MatrixXd& control = self.model.controlPoints;
    std::vector<FacePoint> nodes;
    std::vector<double> weights;
    space.quadrature(nodes, weights);
    std::vector<spline::FitBasisTerm> terms;
    std::vector<double> parameterArea(std::size_t(faceCount(self.model)), 0.0);
    std::vector<double> bound(parameterArea.size(), 0.0);
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      const auto f = std::size_t(nodes[k].face);
      parameterArea[f] += weights[k];
      const double element = areaElement(space, control, nodes[k], terms);
      if (std::isfinite(element)) bound[f] = std::max(bound[f], 2.0 * element);
    }
    std::vector<double> envelope(parameterArea.size());
    for (std::size_t f = 0; f < envelope.size(); ++f) envelope[f] = parameterArea[f] * bound[f];
    if (!(std::accumulate(envelope.begin(), envelope.end(), 0.0) > 0.0))
      throw structure::InputError(self.name + ": the surface has no area to sample");
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::discrete_distribution<int> pickFace(envelope.begin(), envelope.end());
    // Points where the surface is undefined (a cone point, a T-spline's hole) are drawn again.
    constexpr int kAttempts = 100000;
    for (int k = 0; k < count; ++k) {
      for (int attempt = 0;; ++attempt) {
        if (attempt == kAttempts)
          throw structure::SolverError(self.name + ": no surface point kept in " +
                                       std::to_string(kAttempts) + " random draws");
        const int face = pickFace(random);
        const FacePoint p{face, randomPointInFace(self.model, face, random)};
        const double element = areaElement(space, control, p, terms);
        if (!std::isfinite(element)) continue;
        double& faceBound = bound[std::size_t(face)];
        if (element > faceBound) {
          faceBound = 2.0 * element;
          envelope[std::size_t(face)] = parameterArea[std::size_t(face)] * faceBound;
          pickFace = std::discrete_distribution<int>(envelope.begin(), envelope.end());
          parameters.clear();
          k = -1;
          break;
        }
        if (unit(random) * faceBound > element) continue;
        const Eigen::Vector3d point = spline::evaluateFitSurface(space, control, p);
        if (!point.allFinite()) continue;
        parameters.push_back(p);
        points.row(k) = point.transpose();
        break;
      }
    }
  }
  py::dict out = parametersDict(self, parameters);
  out["points"] = pointsArray(points);
  return out;
}

py::tuple tessellate(const Model& self, int resolution) {
  spline::ModelTessellation tessellation;
  {
    py::gil_scoped_release release;
    tessellation = self.surface->tessellate(self.model.controlPoints, resolution);
  }
  return py::make_tuple(pointsArray(tessellation.mesh.positions),
                        trianglesArray(tessellation.mesh.faces), pointsArray(tessellation.normals));
}

// A writable view of the control points (column-major, as Eigen holds them): edits in place
// reach the model; the view keeps the model alive.
py::array controlPointsView(const py::object& object) {
  Eigen::MatrixXd& control = object.cast<Model&>().model.controlPoints;
  const auto rows = py::ssize_t(control.rows()), columns = py::ssize_t(control.cols());
  const auto size = py::ssize_t(sizeof(double));
  return py::array_t<double>({rows, columns}, {size, size * rows}, control.data(), object);
}

void setControlPoints(Model& self, const py::handle& value) {
  Eigen::MatrixXd& control = self.model.controlPoints;
  const DoubleArray array = realMatrix(value, "control_points", 3);
  const auto values = array.unchecked<2>();
  if (values.shape(0) != control.rows())
    throw py::value_error("control_points: expected shape (" + std::to_string(control.rows()) +
                          ", 3), got (" + std::to_string(values.shape(0)) + ", 3)");
  // Element by element into the same storage: views handed out before stay valid.
  for (Eigen::Index i = 0; i < control.rows(); ++i)
    for (Eigen::Index j = 0; j < 3; ++j) control(i, j) = values(i, j);
}

}  // namespace

Model::Model(spline::SplineModel splineModel, std::string modelName)
    : model(std::move(splineModel)),
      name(std::move(modelName)),
      surface(std::make_unique<spline::ModelSurface>(model, name)) {}

py::class_<Model> bindModel(py::module_& module) {
  return py::class_<Model>(module, "Model",
                           "A spline surface: a triangular B-spline, a T-spline or a subdivision "
                           "surface on a flat structure of a mesh, with its control points.")
      .def_property_readonly(
          "kind", [](const Model& self) { return self.surface->kindName(); },
          "'tribspline', 'tspline' or 'subd'")
      .def_readonly("name", &Model::name, "Names the model (its file, or the fitted scan)")
      .def_property_readonly(
          "face_count", [](const Model& self) { return faceCount(self.model); },
          "Faces of the parameter domain (what evaluate's faces index)")
      .def_property("control_points", &controlPointsView, &setControlPoints,
                    "float64 (n, 3): a writable view; assigning needs the same shape")
      .def_property_readonly(
          "fit_report",
          [](const Model& self) { return self.fitReport ? self.fitReport : py::none(); },
          "The fit's figures (dict) for a fitted model, None for a loaded one")
      .def("evaluate", &evaluate, py::arg("face"), py::arg("uv"),
           "The surface point at a domain face and a position uv in its frame: (3,) for one "
           "face and uv (2,), (n, 3) for faces (n,) and uvs (n, 2); NaN where the surface is "
           "undefined (a cone point, a T-spline's hole). ValueError for a face out of range or "
           "a uv outside its face.")
      .def("project", &project, py::arg("points"),
           "Closest surface points of points (n, 3) (Newton's method from the nearest point of "
           "a tessellation): dict of points (n, 3), faces (n,), uvs (n, 2), distances (n,).")
      .def("sample", &sample, py::arg("n"), py::arg("seed") = 0,
           "n random surface points, uniform by surface area (rejection sampling on the area "
           "element): dict of points (n, 3), faces (n,), uvs (n, 2).")
      .def("tessellate", &tessellate, py::arg("resolution") = 4,
           "Triangles sampling every face `resolution` times along each side: "
           "(vertices (n, 3), triangles (m, 3), unit normals (n, 3)).")
      .def(
          "save",
          [](const Model& self, const py::handle& path) {
            const std::string file = pathString(path);
            py::gil_scoped_release release;
            io::writeSplineModel(file, self.model);
          },
          py::arg("path"), "Writes the model file (.msp), atomically.")
      .def("__repr__", [](const Model& self) {
        return "<mspline.Model " + self.surface->kindName() + " with " +
               std::to_string(self.model.controlPoints.rows()) + " control points>";
      });
}

}  // namespace mspline::python
