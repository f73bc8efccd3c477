#pragma once
// numpy arrays in and out of the bindings: checked on the way in (a wrong dtype is a TypeError, a
// wrong shape a ValueError, both naming the argument), copied into Eigen or mspline types, and
// copied back out as new float64 / int64 arrays.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>

#include "mspline/structure/mesh/polygon_soup.h"

namespace mspline::python {

namespace py = pybind11;

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IndexArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

/// A real array (float or integer dtype) of shape (n, columns) (columns < 0: any), converted to
/// float64; (columns,) too when `allowVector` (then n = 1 and the result is 2-dimensional).
DoubleArray realMatrix(const py::handle& array, const char* name, int columns,
                       bool allowVector = false);
/// An integer array of shape (n, columns) (columns 0: one-dimensional, shape (n,)) as int64.
IndexArray indexMatrix(const py::handle& array, const char* name, int columns);

Eigen::MatrixX3d toPoints(const DoubleArray& array);
/// Vertices (n, 3) and triangles (m, 3) as a soup named `name` (the name every message about it
/// carries).
structure::PolygonSoup toSoup(const py::handle& vertices, const py::handle& faces,
                              const std::string& name);

/// A file path given as str or os.PathLike.
std::string pathString(const py::handle& path);

/// New arrays holding a copy.
DoubleArray pointsArray(const Eigen::MatrixXd& points);
template <std::size_t columns>
DoubleArray pointsArray(const std::vector<std::array<double, columns>>& points) {
  DoubleArray out({py::ssize_t(points.size()), py::ssize_t(columns)});
  auto view = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t j = 0; j < columns; ++j) view(py::ssize_t(i), py::ssize_t(j)) = points[i][j];
  return out;
}
IndexArray trianglesArray(const std::vector<std::vector<std::int64_t>>& faces);
IndexArray indexArray(const std::vector<std::int64_t>& values);

}  // namespace mspline::python
