#include "arrays.hpp"

#include <charconv>
#include <cmath>

#include "hullmap/core/error.hpp"

namespace hullmap::python {
namespace {

std::string shapeText(const py::array& array) {
  std::string text = "(";
  for (py::ssize_t i = 0; i < array.ndim(); ++i) text += (i ? ", " : "") + std::to_string(array.shape(i));
  return text + (array.ndim() == 1 ? ",)" : ")");
}

std::string typeName(py::handle object) { return py::str(py::type::handle_of(object).attr("__name__")); }

}  // namespace

py::array_t<double> rowsArray(py::handle object, py::ssize_t cols, const std::string& name, const std::string& what) {
  const std::string expected = "expected an (N, " + std::to_string(cols) + ") float64 array (" + what + " a row)";
  py::array array;
  if (py::isinstance<py::array>(object)) {
    array = py::reinterpret_borrow<py::array>(object);
  } else {
    // A list of rows: numpy makes the array (and refuses ragged or non-numeric rows).
    try {
      array = py::module_::import("numpy").attr("asarray")(object, py::arg("dtype") = "float64");
    } catch (const py::error_already_set&) {
      throw Error::inParameter(name, expected + ", got a " + typeName(object) + " numpy cannot make one of");
    }
  }
  if (array.ndim() != 2 || array.shape(1) != cols)
    throw Error::inParameter(name, expected + ", got shape " + shapeText(array));
  if (!array.dtype().is(py::dtype::of<double>()))
    throw Error::inParameter(name, expected + ", got dtype " + std::string(py::str(array.dtype())) +
                                       " (.astype(numpy.float64) converts it)");
  if (!(array.flags() & py::array::c_style))
    throw Error::inParameter(name, expected + ", got a non-contiguous view (numpy.ascontiguousarray copies it)");
  if (array.shape(0) == 0) throw Error::inParameter(name, "empty: no rows");
  return py::reinterpret_borrow<py::array_t<double>>(array);
}

Eigen::Vector3d vector3(py::handle object, const std::string& name) {
  // One point is tiny: any sequence of three numbers is taken (ints too), converted.
  py::array_t<double> p;
  try {
    p = py::module_::import("numpy").attr("asarray")(object, py::arg("dtype") = "float64").attr("reshape")(-1);
  } catch (const py::error_already_set&) {
    throw Error::inParameter(name, "expected three numbers (x, y, z), got a " + typeName(object));
  }
  if (p.size() != 3)
    throw Error::inParameter(name, "expected three numbers (x, y, z), got " + std::to_string(p.size()));
  const Eigen::Vector3d v(p.at(0), p.at(1), p.at(2));
  if (!v.allFinite()) throw Error::inParameter(name, "must be finite");
  return v;
}

std::vector<Eigen::Vector3d> points(const py::array_t<double>& rows) {
  const auto n = static_cast<std::size_t>(rows.shape(0));
  const double* p = rows.data();
  std::vector<Eigen::Vector3d> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = Eigen::Vector3d(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
  return out;
}

void requireFinite(const py::array_t<double>& rows, const std::string& name) {
  const auto n = static_cast<std::size_t>(rows.shape(0));
  const auto cols = static_cast<std::size_t>(rows.shape(1));
  const double* p = rows.data();
  for (std::size_t i = 0; i < n * cols; ++i) {
    if (!std::isfinite(p[i]))
      throw Error::inParameter(name, "row " + std::to_string(i / cols) + " holds a NaN or an infinity");
  }
}

std::string rowsText(const py::array_t<double>& rows) {
  const auto n = static_cast<std::size_t>(rows.shape(0));
  const auto cols = static_cast<std::size_t>(rows.shape(1));
  const double* p = rows.data();
  std::string text;
  text.reserve(n * cols * 24);
  char buffer[32];
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < cols; ++j) {
      if (j) text += ' ';
      text.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, p[i * cols + j]).ptr);
    }
    text += '\n';
  }
  return text;
}

py::array_t<double> own(std::vector<Eigen::Vector3d>&& points) {
  static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double), "Eigen::Vector3d is three packed doubles");
  auto* held = new std::vector<Eigen::Vector3d>(std::move(points));
  py::capsule owner(held, [](void* p) { delete static_cast<std::vector<Eigen::Vector3d>*>(p); });
  return py::array_t<double>({static_cast<py::ssize_t>(held->size()), py::ssize_t(3)},
                             held->empty() ? nullptr : held->front().data(), owner);
}

py::array_t<double> view(const std::vector<Eigen::Vector3d>& points, py::handle owner) {
  static const double none[3] = {0, 0, 0};
  return view(points.empty() ? none : points.front().data(), {static_cast<py::ssize_t>(points.size()), 3}, owner);
}

py::array_t<double> view(const std::vector<Eigen::Vector2d>& points, py::handle owner) {
  static_assert(sizeof(Eigen::Vector2d) == 2 * sizeof(double), "Eigen::Vector2d is two packed doubles");
  static const double none[2] = {0, 0};
  return view(points.empty() ? none : points.front().data(), {static_cast<py::ssize_t>(points.size()), 2}, owner);
}

py::array_t<double> view(const Eigen::Vector3d& point, py::handle owner) { return view(point.data(), {3}, owner); }

}  // namespace hullmap::python
