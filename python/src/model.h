#pragma once
// The Python Model: a spline model with its space built once (spline::ModelSurface), evaluated,
// projected onto, sampled, tessellated and saved from Python.
#include <memory>
#include <string>

#include <pybind11/pybind11.h>

#include "mspline/spline/core/spline_model.h"
#include "mspline/spline/model/model_surface.h"

namespace mspline::python {

namespace py = pybind11;

struct Model {
  /// Builds the model's space; InputError (naming `name`) when the model is invalid for its kind.
  Model(spline::SplineModel splineModel, std::string modelName);

  spline::SplineModel model;
  /// Names the model (its file, or the fitted scan) in messages.
  std::string name;
  std::unique_ptr<spline::ModelSurface> surface;
  /// The fit's figures (a dict) for a fitted model; null for a loaded one (a null handle, so that
  /// a Model can be made without the GIL).
  py::object fitReport;
};

/// Registers the Model class.
py::class_<Model> bindModel(py::module_& module);

}  // namespace mspline::python
