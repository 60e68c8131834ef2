#pragma once

#include <optional>
#include <vector>

#include <pybind11/pybind11.h>

#include "hullmap/pipeline/pipeline.hpp"

namespace hullmap::python {

namespace py = pybind11;

/// What hullmap.build() was asked, as the library takes it.
struct BuildRequest {
  pipeline::BuildParams params;      ///< params.inputs: the point files, when points named files
  std::optional<io::Points> points;  ///< points given as an array (input frame)
  /// A trajectory given as an array (input frame), parsed as a TUM file's lines would be.
  std::optional<std::vector<io::Keyframe>> keyframes;
  bool up_given = false;  ///< `up` or `align` was given (no ORB-SLAM frame hint then)
};

/// hullmap.build()'s arguments as BuildParams: `points` a path, a list of paths or an (N, 3) array;
/// `trajectory` a TUM path or an (K, 8) array; `align` a path or an (K, 4) array (TUM: t x y z, or
/// GPS: t lat lon alt with align_format "gps"; (K, 8) TUM rows too); `origin` three numbers or None;
/// `keywords` the others, by the names of report.json's "parameters" (the library's field names),
/// with `hullmap build`'s defaults and words ("auto", "none", "default"). Keywords that cannot apply
/// to the run are refused as `hullmap build` refuses their options. Throws hullmap::Error naming the
/// keyword at fault, and py::type_error for a keyword that does not exist.
BuildRequest buildRequest(py::handle points, py::handle trajectory, py::handle align, py::handle origin,
                          const py::dict& keywords);

/// True for a str or an os.PathLike.
bool isPath(py::handle object);

/// os.fspath(object) as a path.
std::filesystem::path toPath(py::handle object);

}  // namespace hullmap::python
