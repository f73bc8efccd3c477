#pragma once
// The library's pipelines called from Python: mspline.flatten (structure::flattenSurface),
// mspline.fit and Model.quality (spline::fitScan, spline::measureQuality), and what they share.
#include <string>

#include <pybind11/pybind11.h>

#include "mspline/structure/core/progress.h"
#include "mspline/structure/mesh/polygon_soup.h"
#include "mspline/structure/mesh/tri_mesh.h"
#include "python/src/model.h"

namespace mspline::python {

namespace py = pybind11;

/// The progress callable (or None) as a structure::Progress that calls it with the GIL. The
/// function refers to `callable`, which must outlive it, instead of holding a reference: copies
/// made without the GIL then touch no reference count. TypeError when it is not callable.
structure::Progress progressOf(const py::object& callable, const std::string& function);

/// The soup as a validated mesh, as io::loadMesh makes one of a file (InputError with the
/// validation summary, which names the soup).
structure::TriMesh validatedMesh(const structure::PolygonSoup& soup);

void bindFlatten(py::module_& module);
void bindFit(py::module_& module, py::class_<Model>& model);

}  // namespace mspline::python
