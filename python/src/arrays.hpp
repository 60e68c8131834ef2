#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <Eigen/Core>

/// numpy in and out for the bindings: what an array argument must be, and arrays that own or view
/// the library's vectors without copying them.
namespace hullmap::python {

namespace py = pybind11;

/// A C-contiguous float64 array of shape (N, cols), N >= 1, as every array argument is taken:
/// a numpy array must already be one (float64, C order, that shape); a list of rows (anything that
/// is not an ndarray) is converted. Throws hullmap::Error naming `name` and saying what was wrong
/// (shape, dtype, a non-contiguous view, no rows). `what` describes the columns ("x y z").
py::array_t<double> rowsArray(py::handle object, py::ssize_t cols, const std::string& name, const std::string& what);

/// One point: a sequence or array of three numbers. Throws hullmap::Error naming `name`.
Eigen::Vector3d vector3(py::handle object, const std::string& name);

/// The rows of a (N, 3) array from rowsArray, copied into the library's point vector.
std::vector<Eigen::Vector3d> points(const py::array_t<double>& rows);

/// Throws hullmap::Error naming `name` and the first row holding a NaN or an infinity.
void requireFinite(const py::array_t<double>& rows, const std::string& name);

/// The rows as text, one a line, numbers in their shortest round-trip form separated by spaces: the
/// bytes the library's text parsers read, so that an array is checked and converted by exactly the
/// code that reads a file.
std::string rowsText(const py::array_t<double>& rows);

/// A numpy array that takes over `values` (no copy): it frees them when it is collected.
template <typename T>
py::array_t<T> own(std::vector<T>&& values) {
  auto* held = new std::vector<T>(std::move(values));
  py::capsule owner(held, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>({static_cast<py::ssize_t>(held->size())}, held->data(), owner);
}

/// The same for points: an (N, 3) float64 array over the vector's memory.
py::array_t<double> own(std::vector<Eigen::Vector3d>&& points);

/// A read-only array over memory that `owner` keeps alive (no copy): shape `shape`, C order.
template <typename T>
py::array_t<T> view(const T* data, std::vector<py::ssize_t> shape, py::handle owner) {
  py::array_t<T> array(std::move(shape), data, owner);
  py::detail::array_proxy(array.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return array;
}

/// Read-only (N, 3) and (N, 2) views of Eigen vectors, and (3,) of one.
py::array_t<double> view(const std::vector<Eigen::Vector3d>& points, py::handle owner);
py::array_t<double> view(const std::vector<Eigen::Vector2d>& points, py::handle owner);
py::array_t<double> view(const Eigen::Vector3d& point, py::handle owner);

}  // namespace hullmap::python
