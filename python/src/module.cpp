// hullmap._hullmap: the library from Python. Front-end code only: it converts arguments (numpy
// arrays, keywords) into the library's types, calls the library, and converts the results back.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "build_request.hpp"
#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/collision/path_check.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/mapper/frame.hpp"
#include "hullmap/mapper/level_check.hpp"
#include "hullmap/pipeline/map_obstacles.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/planning/ompl_planner.hpp"
#include "hullmap/planning/path_planner.hpp"
#include "hullmap/plot/colour.hpp"
#include "map.hpp"

namespace hullmap::python {
namespace {

namespace py = pybind11;
using collision::SegmentCheck;

// Python objects the module makes once and keeps for the life of the process (never freed: a
// static py::object would be released after the interpreter is gone).
struct Types {
  py::object error;          ///< hullmap.Error, a ValueError
  py::object build_warning;  ///< hullmap.BuildWarning, a UserWarning
  py::object voxels;         ///< namedtuple Voxels
  py::object path_check;     ///< namedtuple PathCheck
  py::object plan;           ///< namedtuple Plan
  py::object surface;        ///< namedtuple Surface
  py::object height_field;   ///< namedtuple HeightField
};
Types* types = nullptr;

py::object toPython(const nlohmann::json& j) {
  using Type = nlohmann::json::value_t;
  switch (j.type()) {
    case Type::boolean:
      return py::bool_(j.get<bool>());
    case Type::number_integer:
      return py::int_(j.get<std::int64_t>());
    case Type::number_unsigned:
      return py::int_(j.get<std::uint64_t>());
    case Type::number_float:
      return py::float_(j.get<double>());
    case Type::string:
      return py::str(j.get_ref<const std::string&>());
    case Type::array: {
      py::list list;
      for (const auto& item : j) list.append(toPython(item));
      return std::move(list);
    }
    case Type::object: {
      py::dict dict;
      for (const auto& [key, value] : j.items()) dict[py::str(key)] = toPython(value);
      return std::move(dict);
    }
    default:
      return py::none();
  }
}

std::vector<std::string> pathStrings(py::handle object, const std::string& name) {
  std::vector<std::string> out;
  if (isPath(object)) {
    out.push_back(toPath(object).string());
  } else if (py::isinstance<py::list>(object) || py::isinstance<py::tuple>(object)) {
    for (const auto item : py::reinterpret_borrow<py::sequence>(object)) {
      if (!isPath(item))
        throw Error::inParameter(name, "expected a path or a list of paths, got " + std::string(py::repr(item)));
      out.push_back(toPath(item).string());
    }
  }
  if (out.empty())
    throw Error::inParameter(name, "expected a path or a list of paths, got " + std::string(py::repr(object)));
  return out;
}

py::array_t<double> readPoints(py::handle path, const std::string& up, double scale) {
  const auto paths = pathStrings(path, "path");
  const mapper::FrameParams frame{mapper::parseUpAxis(up), scale};
  io::PointSet set;
  {
    py::gil_scoped_release release;
    set = pipeline::readInputPoints(paths);
    mapper::toMapFrame(frame, set.points);
  }
  return own(std::move(set.points));
}

std::vector<std::uint32_t> dbscanWeights(py::handle object, std::size_t n) {
  const py::array array = py::isinstance<py::array>(object)
                              ? py::reinterpret_borrow<py::array>(object)
                              : py::array(py::module_::import("numpy").attr("asarray")(object));
  const std::string expected = "expected a (N,) array of positive integers (map points per point)";
  if (array.ndim() != 1)
    throw Error::inParameter("weights", expected + ", got " + std::to_string(array.ndim()) + " dimensions");
  if (array.dtype().kind() != 'i' && array.dtype().kind() != 'u')
    throw Error::inParameter("weights", expected + ", got dtype " + std::string(py::str(array.dtype())));
  if (static_cast<std::size_t>(array.shape(0)) != n)
    throw Error::inParameter("weights",
                             std::to_string(array.shape(0)) + " weights for " + std::to_string(n) + " points");
  // Any integer dtype and layout: numpy converts to int64 (values checked below), then they are copied.
  const auto values = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(array);
  std::vector<std::uint32_t> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t w = values.at(static_cast<py::ssize_t>(i));
    if (w < 0 || w > std::int64_t(UINT32_MAX))
      throw Error::inParameter(
          "weights", "weight of point " + std::to_string(i) + " is " + std::to_string(w) + ", not in 1..4294967295");
    out[i] = static_cast<std::uint32_t>(w);
  }
  return out;
}

py::array_t<std::int32_t> dbscan(py::handle points, double eps, int min_pts, py::handle weights,
                                 const std::string& metric) {
  const auto rows = rowsArray(points, 3, "points", "x y z");
  clustering::DbscanParams params{eps, min_pts, clustering::parseMetric(metric)};
  std::vector<Eigen::Vector3d> p = python::points(rows);
  std::vector<std::uint32_t> w;
  if (!weights.is_none()) w = dbscanWeights(weights, p.size());
  clustering::DbscanResult result;
  {
    py::gil_scoped_release release;
    result = clustering::dbscan(p, w, params);
  }
  return own(std::move(result.labels));
}

std::unique_ptr<Map> build(py::handle points, py::handle trajectory, py::handle align, py::handle origin,
                           const py::kwargs& keywords) {
  BuildRequest request = buildRequest(points, trajectory, align, origin, keywords);
  pipeline::BuildResult result;
  {
    py::gil_scoped_release release;
    if (request.points) {
      result = pipeline::buildFromPoints(std::move(*request.points), std::move(request.keyframes), request.params,
                                         "points", "trajectory");
    } else if (request.keyframes) {
      // Files with a trajectory array: the files are read whole (as any build with a trajectory does).
      io::PointSet set = pipeline::readInputPoints(
          std::vector<std::string>(request.params.inputs.begin(), request.params.inputs.end()));
      std::string name;
      for (const auto& input : request.params.inputs) name += (name.empty() ? "" : ",") + input.string();
      result = pipeline::buildFromPoints(std::move(set.points), std::move(request.keyframes), request.params, name,
                                         "trajectory");
    } else {
      result = pipeline::build(request.params);
    }
  }
  // As `hullmap build`: the ORB-SLAM frame hint joins the warnings (report.json records them).
  std::vector<io::InputStats> named = result.report.inputs;
  if (request.params.trajectory) {
    named.emplace_back();
    named.back().path = request.params.trajectory->string();
    named.back().format = "tum";
  }
  auto& warnings = result.report.warnings;
  if (auto hint = mapper::orbSlamUpHint(named, request.up_given)) warnings.insert(warnings.begin(), *hint);
  auto map = std::make_unique<Map>(std::move(result));
  for (const auto& warning : map->report()["warnings"]) {
    if (PyErr_WarnEx(types->build_warning.ptr(), warning.get<std::string>().c_str(), 1) != 0)
      throw py::error_already_set();
  }
  return map;
}

/// The checks as a structured array, one row a segment: collides, obstacle, part, surface (the name of
/// the floor or ceiling hit first, "" else), t, clearance. Filled in one pass (a SegmentCheck holds
/// the surface's name as a string, so it is not plain data numpy could take over).
py::array checkArray(const std::vector<SegmentCheck>& results) {
  std::size_t width = 1;
  for (const auto& r : results) width = std::max(width, r.surface.size());
  py::list fields;
  fields.append(py::make_tuple("collides", "?"));
  fields.append(py::make_tuple("obstacle", "<i4"));
  fields.append(py::make_tuple("part", "<i4"));
  fields.append(py::make_tuple("surface", "<U" + std::to_string(width)));
  fields.append(py::make_tuple("t", "<f8"));
  fields.append(py::make_tuple("clearance", "<f8"));
  const py::module_ np = py::module_::import("numpy");
  const py::object dtype = np.attr("dtype")(fields);
  py::array out = np.attr("zeros")(results.size(), dtype);
  const py::dict layout = dtype.attr("fields");
  const auto offset = [&](const char* name) { return py::cast<std::size_t>(layout[name].cast<py::tuple>()[1]); };
  const std::size_t collides = offset("collides"), obstacle = offset("obstacle"), part = offset("part"),
                    surface = offset("surface"), t = offset("t"), clearance = offset("clearance");
  const auto size = static_cast<std::size_t>(out.itemsize());
  auto* row = static_cast<char*>(out.mutable_data());
  for (const auto& r : results) {
    const bool hit = r.collides;
    const std::int32_t id = r.obstacle, index = r.part;
    std::memcpy(row + collides, &hit, 1);
    std::memcpy(row + obstacle, &id, 4);
    std::memcpy(row + part, &index, 4);
    for (std::size_t i = 0; i < r.surface.size(); ++i) {
      const std::uint32_t c = static_cast<unsigned char>(r.surface[i]);  // numpy's U: UCS-4
      std::memcpy(row + surface + 4 * i, &c, 4);
    }
    std::memcpy(row + t, &r.t, 8);
    std::memcpy(row + clearance, &r.clearance, 8);
    row += size;
  }
  return out;
}

collision::CheckRequest checkRequest(double radius, double contact_tolerance) {
  collision::CheckRequest request;
  request.radius = radius;
  request.contact_tolerance = contact_tolerance;
  return request;
}

void requireAgainst(const std::string& against) {
  if (against != "hulls" && against != "octree")
    throw Error::inParameter("against", "expected 'hulls' or 'octree', got '" + against + "'");
}

py::array check(Map& map, py::handle segments, double radius, const std::string& against, double contact_tolerance,
                const std::string& frame) {
  requireAgainst(against);
  // As `hullmap check --frame`: the segments are moved into the map frame; t is the same fraction.
  const mapper::Similarity to_map = pipeline::toMapFrame(map.map(), pipeline::parseQueryFrame(frame));
  const auto rows = rowsArray(segments, 6, "segments", "x0 y0 z0 x1 y1 z1");
  const auto n = static_cast<std::size_t>(rows.shape(0));
  const double* p = rows.data();
  std::vector<collision::Segment> list(n);
  for (std::size_t i = 0; i < n; ++i, p += 6) list[i] = {to_map({p[0], p[1], p[2]}), to_map({p[3], p[4], p[5]})};
  const collision::CheckRequest request = checkRequest(radius, contact_tolerance);
  std::vector<SegmentCheck> results;
  if (against == "hulls") {
    const collision::HullChecker& checker = map.hulls();
    py::gil_scoped_release release;
    results = checker.checkBatch(list, request);
  } else {
    // As `hullmap check --against octree`: one segment after the other.
    const collision::OctreeChecker& checker = map.octree();
    py::gil_scoped_release release;
    results.reserve(n);
    for (const auto& s : list) results.push_back(checker.check(s, request));
  }
  return checkArray(results);
}

py::object checkPath(Map& map, py::handle waypoints, double radius, const std::string& against,
                     double contact_tolerance, const std::string& frame) {
  requireAgainst(against);
  const mapper::Similarity to_map = pipeline::toMapFrame(map.map(), pipeline::parseQueryFrame(frame));
  const auto rows = rowsArray(waypoints, 3, "waypoints", "x y z");
  const std::vector<Eigen::Vector3d> given = python::points(rows);
  std::vector<Eigen::Vector3d> points = given;
  for (auto& w : points) w = to_map(w);
  const collision::CheckRequest request = checkRequest(radius, contact_tolerance);
  collision::PathCheck path;
  if (against == "hulls") {
    const collision::HullChecker& checker = map.hulls();
    py::gil_scoped_release release;
    path = checker.checkPath(points, request);
  } else {
    const collision::OctreeChecker& checker = map.octree();
    py::gil_scoped_release release;
    path = checker.checkPath(points, request);
  }
  py::object first = py::none();
  py::object contact = py::none();
  if (path.first_colliding_segment) {
    // On the path as given (either frame), as `hullmap check --path` prints it.
    const std::size_t i = *path.first_colliding_segment;
    const Eigen::Vector3d& a = given[i];
    const Eigen::Vector3d& b = given.size() == 1 ? a : given[i + 1];
    first = py::int_(i);
    contact = own(std::vector<Eigen::Vector3d>{a + path.segments[i].t * (b - a)}).attr("reshape")(3);
  }
  return types->path_check(checkArray(path.segments), first, contact);
}

py::object plan(Map& map, py::handle start, py::handle goal, double radius, const std::string& method,
                std::optional<double> flight_z, std::optional<double> time_limit, const std::string& frame) {
  // As `hullmap plan --frame`: start and goal into the map frame, the path back out of it.
  const mapper::Similarity to_map = pipeline::toMapFrame(map.map(), pipeline::parseQueryFrame(frame));
  planning::PlanRequest request;
  request.start = to_map(vector3(start, "start"));
  request.goal = to_map(vector3(goal, "goal"));
  // Checked here as `hullmap plan` checks it: planPath sizes the roadmap's band from the radius first.
  if (!(radius >= 0.0) || !std::isfinite(radius))
    throw Error::inParameter("radius", "must be a finite number >= 0, got " + std::to_string(radius));
  request.radius = radius;
  request.flight_z = flight_z;
  if (method != "roadmap" && method != "ompl")
    throw Error::inParameter("method", "expected 'roadmap' or 'ompl', got '" + method + "'");
  if (time_limit && method != "ompl") throw Error::inParameter("time_limit", "applies only to method 'ompl'");
  planning::PlanResult result;
  {
    py::gil_scoped_release release;
    if (method == "ompl") {
      planning::OmplParams params;
      if (time_limit) params.time_limit = *time_limit;
      planning::OmplPlanResult found = planning::planPathOmpl(map.obstacles(), request, params, map.map().surfaces);
      result.path = std::move(found.path);
      result.length = found.length;
      result.blocked = std::move(found.blocked);
    } else {
      result = planning::planPath(map.obstacles(), request, std::nullopt, map.map().surfaces);
    }
    if (result.path) {
      const mapper::Similarity from_map = mapper::inverse(to_map);
      for (auto& p : *result.path) p = from_map(p);
    }
  }
  py::object path = result.path ? py::object(own(std::move(*result.path))) : py::none();
  return types->plan(path, result.length, result.blocked);
}

std::string describe(const Map& map) {
  std::size_t parts = 0;
  for (const auto& o : map.obstacles()) parts += o.parts.empty() ? 1 : o.parts.size();
  std::string text = "<hullmap.Map: " + std::to_string(map.obstacles().size()) + " obstacles in " +
                     std::to_string(parts) + " convex parts, " + std::to_string(map.centers().size()) + " voxels";
  if (!map.directory().empty()) text += ", read from " + map.directory().string();
  return text + ">";
}

template <typename T>
void bindShape(py::class_<T>& c) {
  c.def_property_readonly(
       "voxel_count", [](const T& o) { return o.voxel_count; }, "occupied voxels")
      .def_property_readonly(
          "point_weight", [](const T& o) { return o.point_weight; }, "map points in its voxels")
      .def_property_readonly(
          "aabb_min", [](py::object self) { return view(self.cast<const T&>().aabb_min, self); },
          "(3,) lower corner of the axis-aligned box, map frame")
      .def_property_readonly(
          "aabb_max", [](py::object self) { return view(self.cast<const T&>().aabb_max, self); }, "(3,) upper corner")
      .def_property_readonly(
          "centroid", [](py::object self) { return view(self.cast<const T&>().centroid, self); },
          "(3,) centroid of the hull's volume")
      .def_property_readonly(
          "volume", [](const T& o) { return o.volume; }, "of the hull, map units cubed")
      .def_property_readonly(
          "hull", [](const T& o) -> const hulls::ConvexHull& { return o.hull; },
          py::return_value_policy::reference_internal, "its convex hull (ConvexHull)")
      .def_property_readonly(
          "footprint", [](const T& o) -> const hulls::Footprint& { return o.footprint; },
          py::return_value_policy::reference_internal, "its footprint (Footprint)");
}

void bindObstacles(py::module_& m) {
  py::class_<hulls::ConvexHull>(m, "ConvexHull",
                                "A convex polyhedron, map frame: vertices (V, 3) float64 and triangles (F, 3) "
                                "int32, counter-clockwise seen from outside. Read-only views into the Map.")
      .def_property_readonly("vertices",
                             [](py::object self) { return view(self.cast<const hulls::ConvexHull&>().vertices, self); })
      .def_property_readonly(
          "triangles",
          [](py::object self) {
            static_assert(sizeof(std::array<int, 3>) == 3 * sizeof(std::int32_t), "triangles are three packed ints");
            const auto& t = self.cast<const hulls::ConvexHull&>().triangles;
            static const std::int32_t none[3] = {0, 0, 0};
            return view(t.empty() ? none : t.front().data(), {static_cast<py::ssize_t>(t.size()), 3}, self);
          })
      .def("__repr__", [](const hulls::ConvexHull& h) {
        return "<hullmap.ConvexHull: " + std::to_string(h.vertices.size()) + " vertices, " +
               std::to_string(h.triangles.size()) + " triangles>";
      });
  py::class_<hulls::Footprint>(m, "Footprint",
                               "The ground-plane footprint: a convex polygon (P, 2), counter-clockwise, and "
                               "its z range.")
      .def_property_readonly("polygon",
                             [](py::object self) { return view(self.cast<const hulls::Footprint&>().polygon, self); })
      .def_property_readonly("z_min", [](const hulls::Footprint& f) { return f.z_min; })
      .def_property_readonly("z_max", [](const hulls::Footprint& f) { return f.z_max; })
      .def("__repr__", [](const hulls::Footprint& f) {
        return "<hullmap.Footprint: " + std::to_string(f.polygon.size()) + " corners, z " + std::to_string(f.z_min) +
               " to " + std::to_string(f.z_max) + ">";
      });

  py::class_<hulls::ObstaclePart> part(m, "ObstaclePart", "One convex part of an obstacle (obstacles.json's parts[]).");
  bindShape(part);
  part.def_property_readonly("concavity_bound", [](const hulls::ObstaclePart& p) { return p.concavity_bound; })
      .def_property_readonly("flat", [](const hulls::ObstaclePart& p) { return p.flat; })
      .def_property_readonly("filled", [](const hulls::ObstaclePart& p) { return p.filled; })
      .def_property_readonly(
          "faces", [](const hulls::ObstaclePart& p) { return p.faces; },
          "passed by the face-hole rule (CONVEX_PARTS.md)")
      .def_property_readonly("free_voxels_inside", [](const hulls::ObstaclePart& p) { return p.free_voxels_inside; })
      .def_property_readonly("free_voxels_off_surface",
                             [](const hulls::ObstaclePart& p) { return p.free_voxels_off_surface; })
      .def("__repr__", [](const hulls::ObstaclePart& p) {
        return "<hullmap.ObstaclePart: " + std::to_string(p.voxel_count) + " voxels, " +
               std::to_string(p.hull.vertices.size()) + " hull vertices>";
      });

  py::class_<hulls::Obstacle> obstacle(m, "Obstacle",
                                       "One obstacle: a cluster of occupied voxels, its hull, footprint and "
                                       "convex parts (obstacles.json's obstacles[]).");
  obstacle.def_property_readonly(
      "id", [](const hulls::Obstacle& o) { return o.id; }, "cluster label");
  bindShape(obstacle);
  obstacle
      .def_property_readonly(
          "parts",
          [](py::object self) {
            py::list list;
            for (const auto& p : self.cast<const hulls::Obstacle&>().parts)
              list.append(py::cast(&p, py::return_value_policy::reference_internal, self));
            return list;
          },
          "its convex parts (ObstaclePart), empty when not split")
      .def("__repr__", [](const hulls::Obstacle& o) {
        return "<hullmap.Obstacle " + std::to_string(o.id) + ": " + std::to_string(o.voxel_count) + " voxels, " +
               std::to_string(o.parts.size()) + " parts>";
      });
}

void bindMap(py::module_& m) {
  py::class_<Map>(m, "Map", "A build: its report, voxels and obstacles, and the path checks and plans on them.")
      .def_property_readonly(
          "report", [](const Map& map) { return toPython(map.report()); }, "report.json as a dict")
      .def_property_readonly("resolution", &Map::resolution, "voxel size, map units")
      .def_property_readonly(
          "voxels",
          [](py::object self) {
            const Map& map = self.cast<const Map&>();
            const auto n = static_cast<py::ssize_t>(map.centers().size());
            return types->voxels(view(map.centers(), self), view(map.labels().data(), {n}, self),
                                 view(map.weights().data(), {n}, self),
                                 view(reinterpret_cast<const bool*>(map.core().data()), {n}, self));
          },
          "Voxels(centers (N, 3), labels (N,) int32, weights (N,) uint32, core (N,) bool): "
          "voxels.csv, read-only views")
      .def_property_readonly(
          "obstacles",
          [](py::object self) {
            py::list list;
            for (const auto& o : self.cast<const Map&>().obstacles())
              list.append(py::cast(&o, py::return_value_policy::reference_internal, self));
            return list;
          },
          "the obstacles (Obstacle), as obstacles.json holds them")
      .def_property_readonly(
          "surfaces",
          [](py::object self) {
            py::list list;
            for (const auto& s : self.cast<const Map&>().map().surfaces) {
              if (s.field) {
                const HeightField& f = *s.field;
                py::array_t<double> heights({py::ssize_t(f.ny), py::ssize_t(f.nx)}), origin(2);
                std::copy(f.heights.begin(), f.heights.end(), heights.mutable_data());
                origin.mutable_data()[0] = f.origin.x();
                origin.mutable_data()[1] = f.origin.y();
                list.append(
                    types->surface(s.name, py::none(), py::none(), types->height_field(origin, f.step, heights)));
                continue;
              }
              list.append(types->surface(s.name, own(std::vector<Eigen::Vector3d>{s.normal}).attr("reshape")(3),
                                         s.offset, py::none()));
            }
            return list;
          },
          "the floor, ceiling and ground, solids that the checks and plans treat as obstacles: "
          "Surface(name, normal (3,), offset, field): a plane's solid is normal . x <= offset (field None); "
          "the ground's is every point under field, HeightField(origin (2,), step, heights (ny, nx)), "
          "normal and offset None")
      .def_property_readonly(
          "frame", [](const Map& map) { return map.map().frame; }, "the build's description of its frame")
      .def("check", &check, py::arg("segments"), py::arg("radius"), py::arg("against") = "hulls",
           py::arg("contact_tolerance") = collision::kContactTolerance, py::arg("frame") = "map",
           "Checks segments (N, 6) float64, rows x0 y0 z0 x1 y1 z1 (map frame), swept by a sphere of `radius`; "
           "returns a structured array (collides, obstacle, part, surface, t, clearance), one row a segment. "
           "against='octree' checks every occupied voxel instead of the hulls.")
      .def("check_path", &checkPath, py::arg("waypoints"), py::arg("radius"), py::arg("against") = "hulls",
           py::arg("contact_tolerance") = collision::kContactTolerance, py::arg("frame") = "map",
           "Checks a path of waypoints (M, 3) as one: PathCheck(segments, first_colliding_segment, first_contact).")
      .def("plan", &plan, py::arg("start"), py::arg("goal"), py::arg("radius"), py::arg("method") = "roadmap",
           py::arg("flight_z") = py::none(), py::arg("time_limit") = py::none(), py::arg("frame") = "map",
           "A path for a drone of `radius` from start to goal: Plan(path (K, 3) or None, length, blocked).")
      .def(
          "save",
          [](const Map& map, py::handle dir, bool parents) {
            const auto path = toPath(dir);
            py::gil_scoped_release release;
            map.save(path, parents);
          },
          py::arg("dir"), py::arg("parents") = false,
          "Writes what `hullmap build -o DIR` writes (parents=True: as -p).")
      .def("__repr__", &describe);
}

}  // namespace
}  // namespace hullmap::python

PYBIND11_MODULE(_hullmap, m) {
  using namespace hullmap;
  using namespace hullmap::python;
  m.doc() = "hullmap's library: read points, DBSCAN, build obstacles, check and plan paths";
  m.attr("__version__") = HULLMAP_VERSION;
  types = new Types();
  types->error = py::exception<Error>(m, "Error", PyExc_ValueError);
  types->error.attr("parameter") = py::none();
  types->error.attr("__doc__") =
      "A hullmap error (a ValueError): its message names the file and line, or the parameter at fault; "
      "`parameter` is that parameter's name, or None.";
  types->build_warning = py::reinterpret_steal<py::object>(
      PyErr_NewExceptionWithDoc("hullmap.BuildWarning",
                                "What a build's outputs leave out or misstate (report.json's "
                                "warnings).",
                                PyExc_UserWarning, nullptr));
  m.attr("BuildWarning") = types->build_warning;
  const py::object namedtuple = py::module_::import("collections").attr("namedtuple");
  types->voxels = namedtuple("Voxels", "centers labels weights core", py::arg("module") = "hullmap");
  types->path_check =
      namedtuple("PathCheck", "segments first_colliding_segment first_contact", py::arg("module") = "hullmap");
  types->plan = namedtuple("Plan", "path length blocked", py::arg("module") = "hullmap");
  types->surface = namedtuple("Surface", "name normal offset field", py::arg("module") = "hullmap");
  types->height_field = namedtuple("HeightField", "origin step heights", py::arg("module") = "hullmap");
  m.attr("HeightField") = types->height_field;
  m.attr("Surface") = types->surface;
  m.attr("Voxels") = types->voxels;
  m.attr("PathCheck") = types->path_check;
  m.attr("Plan") = types->plan;

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      py::object error = types->error(e.what());
      error.attr("parameter") = e.parameter().empty() ? py::object(py::none()) : py::object(py::str(e.parameter()));
      PyErr_SetObject(types->error.ptr(), error.ptr());
    }
  });

  bindObstacles(m);
  bindMap(m);

  m.def("read_points", &readPoints, py::arg("path"), py::arg("up") = "z", py::arg("scale") = 1.0,
        "Reads point files (ORB-SLAM dumps, text/CSV/XYZ, PCD, PLY; the format found from the content) as an "
        "(N, 3) float64 array in the z-up map frame: scaled by `scale`, the input axis `up` turned to +z.");
  m.def("dbscan", &dbscan, py::arg("points"), py::arg("eps"), py::arg("min_pts"), py::arg("weights") = py::none(),
        py::arg("metric") = "xyz",
        "Exact DBSCAN of (N, 3) float64 points: (N,) int32 labels, -1 for noise, clusters numbered by first "
        "point. weights: map points per point (min_pts counts them); metric 'xy' ignores z.");
  m.def("build", &build, py::arg("points"), py::arg("trajectory") = py::none(), py::arg("align") = py::none(),
        py::arg("origin") = py::none(),
        "What `hullmap build` does, from point files or an (N, 3) array: returns a Map. Keywords are the "
        "library's parameter names with the CLI's defaults (eps='auto', min_pts='auto', floor='auto', ...).");
  m.def(
      "load", [](py::handle dir) { return Map::load(toPath(dir)); }, py::arg("dir"),
      "Reads a `hullmap build` output directory (or what Map.save wrote) as a Map.");
  m.def(
      "cluster_colour",
      [](int label) {
        const plot::Rgb c = plot::clusterColour(label);
        return py::make_tuple(c.r, c.g, c.b);
      },
      py::arg("label"), "The colour hullmap's pictures give a cluster label: (r, g, b), 0-255.");
}
