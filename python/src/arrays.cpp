#include "python/src/arrays.h"

#include <algorithm>

#include "mspline/structure/core/errors.h"

namespace mspline::python {

namespace {

py::array anyArray(const py::handle& object, const char* name) {
  py::array array = py::array::ensure(object);
  if (!array)
    throw py::type_error(std::string(name) + ": expected an array, got " +
                         std::string(py::str(py::type::handle_of(object).attr("__name__"))));
  return array;
}

std::string shapeText(const py::array& array) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < array.ndim(); ++d)
    text += (d ? ", " : "") + std::to_string(array.shape(d));
  return text + (array.ndim() == 1 ? ",)" : ")");
}

void checkShape(const py::array& array, const char* name, int columns, bool allowVector) {
  const bool matrix = array.ndim() == 2 && (columns < 0 || array.shape(1) == columns);
  const bool vector =
      array.ndim() == 1 && (columns == 0 || (allowVector && array.shape(0) == columns));
  if (matrix || vector) return;
  const std::string wanted = columns == 0  ? "(n,)"
                             : columns < 0 ? "(n, k)"
                                           : "(n, " + std::to_string(columns) + ")";
  throw py::value_error(std::string(name) + ": expected shape " + wanted + ", got " +
                        shapeText(array));
}

}  // namespace

DoubleArray realMatrix(const py::handle& object, const char* name, int columns, bool allowVector) {
  const py::array array = anyArray(object, name);
  const char kind = array.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(std::string(name) + ": expected real numbers, got dtype " +
                         std::string(py::str(array.dtype())));
  checkShape(array, name, columns, allowVector);
  DoubleArray converted = DoubleArray::ensure(array);
  if (converted.ndim() == 1) converted = converted.reshape({py::ssize_t(1), converted.shape(0)});
  return converted;
}

IndexArray indexMatrix(const py::handle& object, const char* name, int columns) {
  const py::array array = anyArray(object, name);
  const char kind = array.dtype().kind();
  if (kind != 'i' && kind != 'u')
    throw py::type_error(std::string(name) + ": expected integers, got dtype " +
                         std::string(py::str(array.dtype())));
  checkShape(array, name, columns, false);
  return IndexArray::ensure(array);
}

Eigen::MatrixX3d toPoints(const DoubleArray& array) {
  const auto view = array.unchecked<2>();
  Eigen::MatrixX3d points(view.shape(0), 3);
  for (py::ssize_t i = 0; i < view.shape(0); ++i)
    for (py::ssize_t j = 0; j < 3; ++j) points(i, j) = view(i, j);
  return points;
}

structure::PolygonSoup toSoup(const py::handle& vertices, const py::handle& faces,
                              const std::string& name) {
  const DoubleArray vertexArray = realMatrix(vertices, "V", 3);
  const IndexArray faceArray = indexMatrix(faces, "F", 3);
  const auto positions = vertexArray.unchecked<2>();
  const auto corners = faceArray.unchecked<2>();
  structure::PolygonSoup soup;
  soup.sourceName = name;
  for (py::ssize_t i = 0; i < positions.shape(0); ++i)
    soup.positions.push_back({positions(i, 0), positions(i, 1), positions(i, 2)});
  for (py::ssize_t i = 0; i < corners.shape(0); ++i)
    soup.faces.push_back({corners(i, 0), corners(i, 1), corners(i, 2)});
  return soup;
}

std::string pathString(const py::handle& path) {
  return py::module_::import("os").attr("fspath")(path).cast<std::string>();
}

DoubleArray pointsArray(const Eigen::MatrixXd& points) {
  DoubleArray out({py::ssize_t(points.rows()), py::ssize_t(points.cols())});
  auto view = out.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    for (Eigen::Index j = 0; j < points.cols(); ++j) view(i, j) = points(i, j);
  return out;
}

IndexArray trianglesArray(const std::vector<std::vector<std::int64_t>>& faces) {
  IndexArray out({py::ssize_t(faces.size()), py::ssize_t(3)});
  auto view = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < faces.size(); ++i) {
    MSPLINE_ASSERT(faces[i].size() == 3, "a face that is not a triangle");
    for (std::size_t j = 0; j < 3; ++j) view(py::ssize_t(i), py::ssize_t(j)) = faces[i][j];
  }
  return out;
}

IndexArray indexArray(const std::vector<std::int64_t>& values) {
  IndexArray out(py::ssize_t(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

}  // namespace mspline::python
