// The mspline Python module (_mspline; python/mspline/__init__.py re-exports it): meshes, spline
// models, fitting and flattening with numpy arrays in and out. Long work runs without the GIL.
#include <exception>
#include <string>

#include <pybind11/pybind11.h>

#include "mspline/io/load_mesh.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/structure/core/errors.h"
#include "python/src/arrays.h"
#include "python/src/model.h"
#include "python/src/pipelines.h"

namespace mspline::python {

namespace {

// Bad input (arguments, files, topology) is a ValueError; a failed computation a RuntimeError.
void translateErrors(std::exception_ptr error) {
  try {
    if (error) std::rethrow_exception(error);
  } catch (const structure::InputError& e) {
    PyErr_SetString(PyExc_ValueError, e.what());
  } catch (const structure::IoError& e) {
    PyErr_SetString(PyExc_ValueError, e.what());
  } catch (const structure::SolverError& e) {
    PyErr_SetString(PyExc_RuntimeError, e.what());
  }
}

py::tuple readMesh(const py::handle& path) {
  const std::string file = pathString(path);
  io::LoadedMesh loaded;
  {
    py::gil_scoped_release release;
    loaded = io::loadMesh(file);
  }
  return py::make_tuple(pointsArray(loaded.soup.positions), trianglesArray(loaded.soup.faces));
}

Model load(const py::handle& path) {
  const std::string file = pathString(path);
  py::gil_scoped_release release;
  return Model(io::readSplineModel(file), file);
}

}  // namespace

}  // namespace mspline::python

PYBIND11_MODULE(_mspline, module) {
  using namespace mspline::python;
  module.doc() = "mspline: manifold splines on meshes (numpy arrays in and out)";
  py::register_exception_translator(&translateErrors);
  py::class_<Model> model = bindModel(module);
  bindFlatten(module);
  bindFit(module, model);
  module.def("read_mesh", &readMesh, py::arg("path"),
             "Reads and validates a mesh file (OFF, OBJ, PLY, STL): (vertices float64 (n, 3), "
             "triangles int64 (m, 3)). ValueError naming the file when it cannot be read or is "
             "not a valid mesh.");
  module.def("load", &load, py::arg("path"), "Reads a model file (.msp) into a Model.");
}
