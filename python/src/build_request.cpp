#include "build_request.hpp"

#include <charconv>
#include <climits>
#include <set>
#include <string>

#include "arrays.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/align.hpp"
#include "hullmap/mapper/floor.hpp"
#include "hullmap/mapper/frame.hpp"
#include "hullmap/mapper/occupancy_map.hpp"

namespace hullmap::python {
namespace {

std::string reprOf(py::handle value) { return py::repr(value); }

/// The keyword arguments of build(), taken one by one; those left at the end do not exist.
class Keywords {
 public:
  explicit Keywords(const py::dict& keywords) {
    for (const auto& [key, value] : keywords)
      given_[py::cast<std::string>(key)] = py::reinterpret_borrow<py::object>(value);
  }

  bool has(const std::string& name) const { return given_.count(name) > 0; }

  /// The value given for `name`, or None.
  py::object take(const std::string& name) {
    known_.insert(name);
    const auto it = given_.find(name);
    return it == given_.end() ? py::none() : it->second;
  }

  /// A keyword that build() does not take is a TypeError, as for any Python function.
  void refuseUnknown() const {
    for (const auto& [name, value] : given_) {
      if (known_.count(name)) continue;
      std::string names;
      for (const auto& k : known_) names += (names.empty() ? "" : ", ") + k;
      throw py::type_error("build() got an unexpected keyword argument '" + name + "' (it takes " + names + ")");
    }
  }

 private:
  std::map<std::string, py::object> given_;
  std::set<std::string> known_;
};

bool isWord(py::handle value) { return py::isinstance<py::str>(value); }
std::string word(py::handle value) { return py::cast<std::string>(value); }

double number(py::handle value, const std::string& name, const std::string& expected = "a number") {
  if (isWord(value) || py::isinstance<py::bool_>(value) || value.is_none())
    throw Error::inParameter(name, "expected " + expected + ", got " + reprOf(value));
  try {
    return py::cast<double>(value);
  } catch (const py::cast_error&) {
    throw Error::inParameter(name, "expected " + expected + ", got " + reprOf(value));
  }
}

int wholeNumber(py::handle value, const std::string& name, const std::string& expected) {
  if (py::isinstance<py::bool_>(value) || !PyIndex_Check(value.ptr()))
    throw Error::inParameter(name, "expected " + expected + ", got " + reprOf(value));
  const auto n = py::cast<long long>(value.attr("__index__")());
  if (n < INT_MIN || n > INT_MAX) throw Error::inParameter(name, "out of range: " + std::to_string(n));
  return static_cast<int>(n);
}

std::string numberText(double v) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
}

/// floor / ceiling: "auto", "none" (or None), or a height.
mapper::PlaneSetting planeSetting(py::handle value, const std::string& name) {
  if (value.is_none()) return {mapper::PlaneSetting::Mode::kNone, 0.0};
  if (isWord(value)) return mapper::parsePlaneSetting(name, word(value));
  return {mapper::PlaneSetting::Mode::kHeight, number(value, name, "'auto', 'none' or a height")};
}

/// One path, or a list of them (points only).
std::optional<std::vector<std::filesystem::path>> paths(py::handle object) {
  if (isPath(object)) return std::vector<std::filesystem::path>{toPath(object)};
  if (!py::isinstance<py::list>(object) && !py::isinstance<py::tuple>(object)) return std::nullopt;
  const auto items = py::reinterpret_borrow<py::sequence>(object);
  if (items.size() == 0) return std::nullopt;
  std::vector<std::filesystem::path> out;
  for (const auto item : items) {
    if (!isPath(item)) return std::nullopt;
    out.push_back(toPath(item));
  }
  return out;
}

/// The reference trajectory as an array: (K, 4) rows `t x y z` (TUM) or `t lat lon alt` (GPS),
/// or (K, 8) TUM rows; parsed as the lines of a file would be.
std::vector<io::ReferencePose> referencePoses(py::handle align, io::ReferenceFormat format) {
  const bool eight = py::isinstance<py::array>(align) && py::reinterpret_borrow<py::array>(align).ndim() == 2 &&
                     py::reinterpret_borrow<py::array>(align).shape(1) == 8 && format == io::ReferenceFormat::kTum;
  const auto rows =
      rowsArray(align, eight ? 8 : 4, "align", format == io::ReferenceFormat::kGps ? "t lat lon alt" : "t x y z");
  return io::parseReferenceTrajectory(rowsText(rows), "align", format);
}

/// `hullmap build` refuses options that cannot apply to the run (recording them as applied would
/// misstate the outputs); build() refuses the same keywords, by the same rules.
void refuseMisfits(const std::set<std::string>& named, const BuildRequest& request, bool has_rays) {
  const auto given = [&](std::initializer_list<const char*> names) {
    std::string list;
    for (const char* name : names)
      if (named.count(name)) list += (list.empty() ? "" : "/") + std::string(name);
    return list;
  };
  const pipeline::BuildParams& params = request.params;
  if (!params.align) {
    const std::string list = given({"align_format", "align_tolerance", "align_model"});
    if (!list.empty()) throw Error::inParameter(list, "applies only with align (a reference trajectory)");
  }
  if (!params.convex_parts && named.count("flat_gap"))
    throw Error::inParameter("flat_gap",
                             "applies only to convex parts, and concavity 'none' makes one hull per "
                             "cluster; leave it out");
  if (request.points || !pipeline::readsOctree(params)) {
    if (has_rays) return;
    const std::string list = given({"max_range", "miss"});
    if (!list.empty())
      throw Error::inParameter(list,
                               "applies only to free space cast along rays (with trajectory or origin); a "
                               "points-only build casts none: leave it out");
    return;
  }
  const std::string list =
      given({"trajectory", "origin", "up", "scale", "crop", "z_min", "z_max", "resolution", "max_range", "hit", "miss",
             "clamp_min", "clamp_max", "occupancy_threshold", "align", "floor", "level", "camera_frame", "ceiling"});
  if (!list.empty())
    throw Error::inParameter(list, "cannot apply to " + params.inputs.front().string() +
                                       ", a finished octree read as it is (its own frame, resolution and sensor "
                                       "model); leave it out, or build from the map points");
}

}  // namespace

bool isPath(py::handle object) { return py::isinstance<py::str>(object) || py::hasattr(object, "__fspath__"); }

std::filesystem::path toPath(py::handle object) {
  return py::cast<std::string>(py::module_::import("os").attr("fspath")(object));
}

namespace {

// up, scale, crop, z_min, z_max: the input frame and the bounds.
void takeFrame(Keywords& k, py::handle align, BuildRequest& request) {
  pipeline::BuildParams& params = request.params;
  if (py::object v = k.take("up"); !v.is_none()) {
    if (!isWord(v)) throw Error::inParameter("up", "expected one of x, -x, y, -y, z, -z, got " + reprOf(v));
    params.frame.up = mapper::parseUpAxis(word(v));
  }
  if (py::object v = k.take("scale"); !v.is_none()) params.frame.scale = number(v, "scale");
  request.up_given = k.has("up") || !align.is_none();

  if (py::object v = k.take("crop"); !v.is_none()) {
    py::array_t<double> box;
    try {
      box = py::module_::import("numpy").attr("asarray")(v, py::arg("dtype") = "float64").attr("reshape")(-1);
    } catch (const py::error_already_set&) {
      throw Error::inParameter("crop", "expected six numbers (x0, y0, z0, x1, y1, z1), got " + reprOf(v));
    }
    if (box.size() != 6)
      throw Error::inParameter("crop", "expected six numbers (x0, y0, z0, x1, y1, z1), got " + reprOf(v));
    std::string text;
    for (py::ssize_t i = 0; i < 6; ++i) text += (i ? "," : "") + numberText(box.at(i));
    params.filters.crop = mapper::parseBox("crop", text);
  }
  if (py::object v = k.take("z_min"); !v.is_none()) params.filters.z_min = number(v, "z_min");
  if (py::object v = k.take("z_max"); !v.is_none()) params.filters.z_max = number(v, "z_max");
}

// The octree's resolution, ray length and sensor model.
void takeOctree(Keywords& k, pipeline::BuildParams& params) {
  mapper::OctreeParams& octree = params.octree;
  for (auto [name, field] : {std::pair<const char*, double*>{"resolution", &octree.resolution},
                             {"max_range", &octree.max_range},
                             {"hit", &octree.sensor.hit},
                             {"miss", &octree.sensor.miss},
                             {"clamp_min", &octree.sensor.clamp_min},
                             {"clamp_max", &octree.sensor.clamp_max},
                             {"occupancy_threshold", &octree.sensor.occupancy_threshold}}) {
    if (py::object v = k.take(name); !v.is_none()) {
      *field = number(v, name);
      // A resolution given is the octree's, as `hullmap build --resolution` gives it.
      if (field == &octree.resolution) params.adapt_resolution = false;
    }
  }
}

// align (a file or an array of poses), align_format, align_tolerance, align_model.
void takeAlign(Keywords& k, py::handle align, pipeline::BuildParams& params) {
  py::object format = k.take("align_format");
  py::object tolerance = k.take("align_tolerance");
  py::object model = k.take("align_model");
  if (!align.is_none()) {
    pipeline::AlignSettings settings;
    if (!format.is_none()) {
      if (!isWord(format)) throw Error::inParameter("align_format", "expected 'tum' or 'gps', got " + reprOf(format));
      settings.format = io::parseReferenceFormat(word(format));
    }
    if (!tolerance.is_none()) settings.params.stamp_tolerance = number(tolerance, "align_tolerance");
    if (!model.is_none()) {
      if (!isWord(model))
        throw Error::inParameter("align_model", "expected 'auto', 'similarity' or 'drift', got " + reprOf(model));
      try {
        settings.params.model = mapper::parseAlignModel(word(model));
      } catch (const Error&) {
        throw Error::inParameter("align_model", "expected 'auto', 'similarity' or 'drift', got " + reprOf(model));
      }
    }
    if (isPath(align)) {
      settings.reference = toPath(align);
    } else {
      settings.poses = referencePoses(align, settings.format);
      settings.reference = "align";
    }
    params.align = std::move(settings);
  }
}

// floor, ceiling, level, camera_frame.
void takeSurfaces(Keywords& k, pipeline::BuildParams& params) {
  if (py::object v = k.take("floor"); k.has("floor")) params.floor = planeSetting(v, "floor");
  if (py::object v = k.take("ceiling"); k.has("ceiling")) params.ceiling = planeSetting(v, "ceiling");
  if (py::object v = k.take("level"); !v.is_none()) {
    const bool on = py::isinstance<py::bool_>(v) ? py::cast<bool>(v) : isWord(v) && word(v) == "on";
    const bool off = py::isinstance<py::bool_>(v) ? !py::cast<bool>(v) : isWord(v) && word(v) == "off";
    if (!on && !off && !(isWord(v) && word(v) == "auto"))
      throw Error::inParameter("level", "expected 'auto', True or False ('on', 'off'), got " + reprOf(v));
    params.level = on ? pipeline::Level::kOn : off ? pipeline::Level::kOff : pipeline::Level::kAuto;
  }
  if (py::object v = k.take("camera_frame"); !v.is_none()) {
    if (!py::isinstance<py::bool_>(v))
      throw Error::inParameter("camera_frame", "expected True, False or None, got " + reprOf(v));
    params.camera_frame = py::cast<bool>(v);
  }
}

// DBSCAN (eps, min_pts, metric, extension), the convex parts (concavity, flat_gap, stray_parts,
// sparse_edges), write_ot.
void takeClustering(Keywords& k, pipeline::BuildParams& params) {
  if (py::object v = k.take("eps"); !v.is_none()) {
    if (!isWord(v) || word(v) != "auto") params.eps = number(v, "eps", "a number or 'auto'");
  }
  if (py::object v = k.take("min_pts"); !v.is_none()) {
    if (!isWord(v) || word(v) != "auto") params.min_pts = wholeNumber(v, "min_pts", "a whole number or 'auto'");
  }
  if (py::object v = k.take("metric"); !v.is_none()) {
    if (!isWord(v)) throw Error::inParameter("metric", "expected xyz or xy, got " + reprOf(v));
    params.metric = clustering::parseMetric(word(v));
  }
  if (py::object v = k.take("concavity"); k.has("concavity")) {
    if (v.is_none() || (isWord(v) && word(v) == "none")) {
      params.convex_parts.reset();
    } else if (!isWord(v) || word(v) != "default") {
      params.convex_parts->concavity = number(v, "concavity", "a number, 'default' or 'none'");
    }
  }
  if (py::object v = k.take("flat_gap"); !v.is_none() && params.convex_parts) {
    if (!isWord(v) || word(v) != "auto") params.convex_parts->flat_gap = number(v, "flat_gap", "a number or 'auto'");
  }
  if (py::object v = k.take("extension"); !v.is_none()) {
    if (py::isinstance<py::bool_>(v)) {
      params.extension = py::cast<bool>(v);
    } else if (isWord(v) && (word(v) == "on" || word(v) == "off")) {
      params.extension = word(v) == "on";
    } else if (!isWord(v) || word(v) != "auto") {
      throw Error::inParameter("extension", "expected 'auto', True or False ('on', 'off'), got " + reprOf(v));
    }
  }
  if (py::object v = k.take("stray_parts"); !v.is_none()) {
    const auto n = wholeNumber(v, "stray_parts", "a whole number >= 0");
    if (n < 0) throw Error::inParameter("stray_parts", "expected a whole number >= 0, got " + reprOf(v));
    params.stray_part_voxels = static_cast<std::size_t>(n);
  }
  if (py::object v = k.take("sparse_edges"); !v.is_none()) {
    if (!py::isinstance<py::bool_>(v))
      throw Error::inParameter("sparse_edges", "expected True or False, got " + reprOf(v));
    params.sparse_edges = py::cast<bool>(v);
  }
  if (py::object v = k.take("write_ot"); !v.is_none()) {
    if (!py::isinstance<py::bool_>(v)) throw Error::inParameter("write_ot", "expected True or False, got " + reprOf(v));
    params.write_ot = py::cast<bool>(v);
  }
}
}  // namespace

BuildRequest buildRequest(py::handle points, py::handle trajectory, py::handle align, py::handle origin,
                          const py::dict& keywords) {
  BuildRequest request;
  pipeline::BuildParams& params = request.params;
  Keywords k(keywords);

  if (auto files = paths(points)) {
    params.inputs = std::move(*files);
  } else {
    const auto rows = rowsArray(points, 3, "points", "x y z");
    requireFinite(rows, "points");
    request.points = python::points(rows);
  }

  if (!trajectory.is_none()) {
    if (isPath(trajectory)) {
      params.trajectory = toPath(trajectory);
    } else {
      request.keyframes =
          io::parseTumTrajectory(rowsText(rowsArray(trajectory, 8, "trajectory", "t x y z qx qy qz qw")), "trajectory");
    }
  }
  if (!origin.is_none()) params.origin = vector3(origin, "origin");

  takeFrame(k, align, request);
  takeOctree(k, params);
  takeAlign(k, align, params);
  takeSurfaces(k, params);
  takeClustering(k, params);
  k.refuseUnknown();
  std::set<std::string> named;
  for (const auto& [key, value] : keywords) named.insert(py::cast<std::string>(key));
  for (auto [name, value] :
       {std::pair<const char*, py::handle>{"trajectory", trajectory}, {"align", align}, {"origin", origin}}) {
    if (!value.is_none()) named.insert(name);
  }
  refuseMisfits(named, request, params.trajectory || request.keyframes || params.origin);
  // The octree's parameters are checked where the octree is made, after the floor search that uses
  // the resolution (whose own message would then speak of the floor): an empty map made here
  // refuses them first, with the mapper's message.
  if (request.points || !pipeline::readsOctree(params)) mapper::OccupancyMap probe(params.octree);
  return request;
}

}  // namespace hullmap::python
