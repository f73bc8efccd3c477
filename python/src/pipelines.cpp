#include "python/src/pipelines.h"

#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/validate.h"

namespace mspline::python {

structure::Progress progressOf(const py::object& callable, const std::string& function) {
  if (callable.is_none()) return {};
  if (!PyCallable_Check(callable.ptr()))
    throw py::type_error(function + ": progress must be a callable (stage, fraction) or None");
  const py::object* target = &callable;
  return [target](const std::string& stage, double fraction) {
    py::gil_scoped_acquire gil;
    (*target)(stage, fraction);
  };
}

structure::TriMesh validatedMesh(const structure::PolygonSoup& soup) {
  const structure::ValidationReport validation = structure::validate(soup);
  if (!validation.ok()) throw structure::InputError(validation.summary());
  return structure::toTriMesh(soup);
}

}  // namespace mspline::python
