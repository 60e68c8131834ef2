#include "hullmap/view/html_view.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <tuple>
#include <utility>

#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/core/markup.hpp"
#include "hullmap/pipeline/map_obstacles.hpp"
#include "hullmap/pipeline/path_checker.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/pipeline/report.hpp"
#include "hullmap/pipeline/trajectory_file.hpp"
#include "hullmap/pipeline/voxels_csv.hpp"
#include "hullmap/plot/colour.hpp"
#include "hullmap/plot/svg_plot.hpp"
#include "page_assets.hpp"

namespace hullmap::view {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Colours of the page's own things (clusters and drones take plot's, as `hullmap plot` draws them).
constexpr const char* kNoiseColour = "#8c8c8c";
constexpr const char* kFloorColour = "#a89a78";
constexpr const char* kCeilingColour = "#7890a8";

std::string labelColour(std::int32_t label) {
  if (label >= 0) return plot::toHex(plot::clusterColour(label));
  if (label == pipeline::kFloorLabel || label == pipeline::kGroundLabel) return kFloorColour;
  if (label == pipeline::kCeilingLabel) return kCeilingColour;
  return kNoiseColour;
}

// Little-endian bytes of typed arrays, base64-encoded (the page decodes them with atob).
class Bytes {
 public:
  void u16(std::uint16_t v) {
    bytes_.push_back(static_cast<char>(v & 0xff));
    bytes_.push_back(static_cast<char>(v >> 8));
  }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes_.push_back(static_cast<char>(v >> (8 * i) & 0xff));
  }
  void f32(double v) {
    const float f = static_cast<float>(v);
    std::uint32_t bits = 0;
    std::memcpy(&bits, &f, sizeof bits);
    u32(bits);
  }
  std::string base64() const {
    static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes_.size() + 2) / 3 * 4);
    std::size_t i = 0;
    const auto at = [&](std::size_t k) { return static_cast<std::uint32_t>(static_cast<unsigned char>(bytes_[k])); };
    for (; i + 2 < bytes_.size(); i += 3) {
      const std::uint32_t v = at(i) << 16 | at(i + 1) << 8 | at(i + 2);
      for (int s = 18; s >= 0; s -= 6) out.push_back(kAlphabet[v >> s & 63]);
    }
    if (i + 1 == bytes_.size()) {
      const std::uint32_t v = at(i) << 16;
      out += {kAlphabet[v >> 18 & 63], kAlphabet[v >> 12 & 63], '=', '='};
    } else if (i + 2 == bytes_.size()) {
      const std::uint32_t v = at(i) << 16 | at(i + 1) << 8;
      out += {kAlphabet[v >> 18 & 63], kAlphabet[v >> 12 & 63], kAlphabet[v >> 6 & 63], '='};
    }
    return out;
  }

 private:
  std::string bytes_;
};

json vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

// A finite number, or null (JSON has no infinity).
json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

void putLocal(Bytes& b, const Eigen::Vector3d& p, const Eigen::Vector3d& shift) {
  b.f32(p.x() - shift.x());
  b.f32(p.y() - shift.y());
  b.f32(p.z() - shift.z());
}

// What the camera frames: the bulk of the voxels (2% to 98% on each axis, so far outliers do not
// shrink the map to a dot), the obstacles, the keyframes and the paths.
Eigen::AlignedBox3d viewBox(const ViewScene& scene) {
  Eigen::AlignedBox3d box;
  if (!scene.centers.empty()) {
    Eigen::Vector3d lo, hi;
    std::vector<double> axis(scene.centers.size());
    for (int a = 0; a < 3; ++a) {
      for (std::size_t i = 0; i < scene.centers.size(); ++i) axis[i] = scene.centers[i][a];
      const auto at = [&](double q) {
        const auto k = static_cast<std::size_t>(q * static_cast<double>(axis.size() - 1));
        std::nth_element(axis.begin(), axis.begin() + static_cast<std::ptrdiff_t>(k), axis.end());
        return axis[k];
      };
      lo[a] = at(0.02) - scene.resolution / 2;
      hi[a] = at(0.98) + scene.resolution / 2;
    }
    box.extend(lo);
    box.extend(hi);
  }
  for (const auto& o : scene.obstacles) {
    box.extend(o.aabb_min);
    box.extend(o.aabb_max);
  }
  for (const auto& k : scene.keyframes) box.extend(k.position);
  for (const auto& p : scene.paths)
    for (const auto& w : p.path.waypoints) box.extend(w);
  if (box.isEmpty()) {
    box.extend(Eigen::Vector3d(-1, -1, -1));
    box.extend(Eigen::Vector3d(1, 1, 1));
  }
  return box;
}

json planeJson(const json& report, const char* key) {
  const auto it = report.find(key);
  if (it == report.end() || !it->is_object()) return nullptr;
  const auto plane = it->find("plane");
  if (plane == it->end() || !plane->is_object()) return nullptr;
  const auto normal = plane->find("normal");
  const auto offset = plane->find("offset");
  if (normal == plane->end() || !normal->is_array() || normal->size() != 3 || offset == plane->end() ||
      !offset->is_number())
    return nullptr;
  for (const auto& v : *normal)
    if (!v.is_number()) return nullptr;
  return {{"normal", *normal}, {"offset", *offset}};
}

json reportValue(const json& report, std::initializer_list<const char*> keys) {
  const json* at = &report;
  for (const char* key : keys) {
    if (!at->is_object()) return nullptr;
    const auto it = at->find(key);
    if (it == at->end()) return nullptr;
    at = &*it;
  }
  return *at;
}

std::string readWhole(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw Error::inParameter("three_dir", path.string() + " not found: three.js r111 comes from Debian's " +
                                              std::string(kThreePackage) + " (apt-get install " + kThreePackage + ")");
  }
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// An inline script must not hold "</script" (it would end the element early).
std::string scriptSafe(std::string text) {
  for (std::size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3))
    text.insert(at + 1, "\\");
  return text;
}

// Line segments (pairs of points) of a truth shape's wireframe.
void truthSegments(const sim::TruthShape& s, std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& out) {
  using Shape = sim::TruthShape::Shape;
  if (s.shape == Shape::kUnion) {
    for (const auto& part : s.parts) truthSegments(part, out);
  } else if (s.shape == Shape::kBox) {
    const Eigen::Vector3d h = s.size / 2;
    const double c = std::cos(s.yaw), n = std::sin(s.yaw);
    const auto corner = [&](int i) {
      const Eigen::Vector3d q((i & 1 ? 1 : -1) * h.x(), (i & 2 ? 1 : -1) * h.y(), (i & 4 ? 1 : -1) * h.z());
      return Eigen::Vector3d(s.center.x() + c * q.x() - n * q.y(), s.center.y() + n * q.x() + c * q.y(),
                             s.center.z() + q.z());
    };
    for (int i = 0; i < 8; ++i)
      for (int bit : {1, 2, 4})
        if (!(i & bit)) out.emplace_back(corner(i), corner(i | bit));
  } else if (s.shape == Shape::kCylinder) {
    constexpr int kSides = 24;
    const double r = s.size.x() / 2, h = s.size.z() / 2;
    const auto at = [&](int k, double z) {
      const double a = 2 * 3.14159265358979323846 * k / kSides;
      return Eigen::Vector3d(s.center.x() + r * std::cos(a), s.center.y() + r * std::sin(a), s.center.z() + z);
    };
    for (int k = 0; k < kSides; ++k) {
      out.emplace_back(at(k, -h), at(k + 1, -h));
      out.emplace_back(at(k, h), at(k + 1, h));
      if (k % 6 == 0) out.emplace_back(at(k, -h), at(k, h));
    }
  } else if (s.shape == Shape::kHeightField) {
    // A terrain: its grid lines through every k-th node each way (about 40 each way), on the surface.
    const sim::HeightGrid& g = s.grid;
    const std::size_t k = std::max<std::size_t>(1, (std::max(g.nx, g.ny) + 39) / 40);
    const auto node = [&g](std::size_t i, std::size_t j) {
      return Eigen::Vector3d(g.origin.x() + g.step * double(i), g.origin.y() + g.step * double(j), g.at(i, j));
    };
    for (std::size_t j = 0; j < g.ny; ++j)
      for (std::size_t i = 0; i + 1 < g.nx; ++i)
        if (j % k == 0 || j + 1 == g.ny) out.emplace_back(node(i, j), node(i + 1, j));
    for (std::size_t i = 0; i < g.nx; ++i)
      for (std::size_t j = 0; j + 1 < g.ny; ++j)
        if (i % k == 0 || i + 1 == g.nx) out.emplace_back(node(i, j), node(i, j + 1));
  } else {
    // A mesh: each edge of its triangles once.
    using Key = std::tuple<double, double, double, double, double, double>;
    std::set<Key> seen;
    for (const auto& t : s.triangles) {
      for (int e = 0; e < 3; ++e) {
        Eigen::Vector3d a = t[e], b = t[(e + 1) % 3];
        if (std::lexicographical_compare(b.data(), b.data() + 3, a.data(), a.data() + 3)) std::swap(a, b);
        if (seen.insert({a.x(), a.y(), a.z(), b.x(), b.y(), b.z()}).second) out.emplace_back(a, b);
      }
    }
  }
}

// The build's figures, parameters and warnings, the view box and the colours.
json pageHeader(const ViewScene& scene, const Eigen::AlignedBox3d& box) {
  const json& report = scene.report;
  const Eigen::Vector3d shift = box.center();
  return {
      {"format", "hullmap-view/1"},
      {"title", scene.title},
      {"hullmap_version", reportValue(report, {"hullmap_version"})},
      {"frame", reportValue(report, {"frame"})},
      {"parameters", reportValue(report, {"parameters"})},
      {"warnings", report.contains("warnings") && report["warnings"].is_array() ? report["warnings"] : json::array()},
      {"report",
       {{"occupied_voxels", reportValue(report, {"octree", "occupied_voxels"})},
        {"clusters", reportValue(report, {"clusters", "count"})},
        {"noise_voxels", reportValue(report, {"clusters", "noise_voxels"})},
        {"floor_voxels", reportValue(report, {"floor", "voxels"})},
        {"ceiling_voxels", reportValue(report, {"ceiling", "voxels"})},
        {"obstacles", reportValue(report, {"obstacles"})},
        {"parts", reportValue(report, {"parts", "count"})}}},
      {"resolution", scene.resolution},
      {"shift", vec(shift)},
      {"view", {{"min", vec(box.min())}, {"max", vec(box.max())}}},
      {"radius", scene.radius},
      {"colours",
       {{"noise", kNoiseColour},
        {"floor", kFloorColour},
        {"ceiling", kCeilingColour},
        {"floor_plane", "#b9a77f"},
        {"ceiling_plane", "#7fa3b9"},
        {"keyframes", "#6d28d9"},
        {"clear", "#00b000"},
        {"collides", "#ff0000"},
        {"roadmap", "#0e7490"},
        {"truth", "#374151"},
        {"axis_x", "#c0392b"},
        {"axis_y", "#2e8b57"},
        {"axis_z", "#1f4fd1"}}},
  };
}

// Voxels: counts of the build, then each level's cells as 16-bit indices from its first cell.
json voxelsJson(const ViewScene& scene, const std::vector<VoxelCells>& levels, std::size_t max_instances) {
  std::size_t clustered = 0, noise = 0, floor = 0, ceiling = 0;
  for (const std::int32_t l : scene.labels) {
    if (l >= 0)
      ++clustered;
    else if (l == pipeline::kFloorLabel || l == pipeline::kGroundLabel)  // the ground is drawn as a floor
      ++floor;
    else if (l == pipeline::kCeilingLabel)
      ++ceiling;
    else
      ++noise;
  }
  json level_data = json::array();
  for (const VoxelCells& cells : levels) {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    if (!cells.centers.empty()) {
      origin = cells.centers.front();
      for (const auto& c : cells.centers) origin = origin.cwiseMin(c);
    }
    Bytes cell_bytes;
    std::vector<std::pair<std::int32_t, std::size_t>> runs;  // label, cells: the cells come sorted by label
    for (std::size_t i = 0; i < cells.centers.size(); ++i) {
      for (int a = 0; a < 3; ++a)
        cell_bytes.u16(static_cast<std::uint16_t>(std::llround((cells.centers[i][a] - origin[a]) / cells.cell)));
      if (runs.empty() || runs.back().first != cells.labels[i]) runs.emplace_back(cells.labels[i], 0);
      ++runs.back().second;
    }
    json groups = json::array();
    for (const auto& [label, count] : runs)
      groups.push_back({{"label", label}, {"count", count}, {"colour", labelColour(label)}});
    level_data.push_back({{"factor", cells.factor},
                          {"cell", cells.cell},
                          {"instances", cells.centers.size()},
                          {"origin", vec(origin)},
                          {"groups", groups},
                          {"cells", cell_bytes.base64()}});
  }
  return {{"total", scene.centers.size()},
          {"clustered", clustered},
          {"noise", noise},
          {"floor", floor},
          {"ceiling", ceiling},
          {"max_instances", max_instances},
          {"levels", level_data}};
}

// Obstacles and their hulls: one per convex part (the whole hull for an obstacle without parts).
void addHulls(const ViewScene& scene, const Eigen::Vector3d& shift, json& data) {
  json obstacles = json::array();
  json items = json::array(), vertex_counts = json::array(), triangle_counts = json::array();
  Bytes vertices, triangles;
  const auto addHull = [&](const hulls::ConvexHull& hull, int obstacle, int part, double volume, std::size_t voxels,
                           bool flat) {
    items.push_back({{"obstacle", obstacle},
                     {"part", part},
                     {"volume", volume},
                     {"voxels", voxels},
                     {"colour", labelColour(obstacle)},
                     {"flat", flat}});
    vertex_counts.push_back(hull.vertices.size());
    triangle_counts.push_back(hull.triangles.size());
    for (const auto& v : hull.vertices) putLocal(vertices, v, shift);
    for (const auto& t : hull.triangles)
      for (int k : t) triangles.u32(static_cast<std::uint32_t>(k));
  };
  for (const auto& o : scene.obstacles) {
    obstacles.push_back({{"id", o.id},
                         {"colour", labelColour(o.id)},
                         {"voxels", o.voxel_count},
                         {"volume", o.volume},
                         {"parts", o.parts.size()}});
    if (o.parts.empty()) {
      addHull(o.hull, o.id, -1, o.volume, o.voxel_count, false);
    } else {
      for (std::size_t k = 0; k < o.parts.size(); ++k) {
        const auto& p = o.parts[k];
        addHull(p.hull, o.id, static_cast<int>(k), p.volume, p.voxel_count, p.flat);
      }
    }
  }
  data["obstacles"] = obstacles;
  data["hulls"] = {{"items", items},
                   {"vertex_counts", vertex_counts},
                   {"triangle_counts", triangle_counts},
                   {"vertices", vertices.base64()},
                   {"triangles", triangles.base64()}};
}

// Keyframes, each with a tick along its viewing direction (the camera's +z); null without any.
json keyframesJson(const ViewScene& scene, const Eigen::Vector3d& shift) {
  if (scene.keyframes.empty()) return nullptr;
  Bytes positions, ticks;
  const double tick = 4 * scene.resolution;
  for (const auto& k : scene.keyframes) {
    putLocal(positions, k.position, shift);
    putLocal(ticks, k.position, shift);
    putLocal(ticks, k.position + tick * (k.orientation * Eigen::Vector3d::UnitZ()), shift);
  }
  return {{"count", scene.keyframes.size()}, {"positions", positions.base64()}, {"ticks", ticks.base64()}};
}

// Paths: their checks as `hullmap check --json` prints them.
json pathsJson(const ViewScene& scene) {
  json paths = json::array();
  for (std::size_t i = 0; i < scene.paths.size(); ++i) {
    const auto& p = scene.paths[i];
    json waypoints = json::array(), segments = json::array();
    for (const auto& w : p.path.waypoints) waypoints.push_back(vec(w));
    for (std::size_t s = 0; s < p.check.segments.size(); ++s) {
      const auto& c = p.check.segments[s];
      segments.push_back({{"index", s},
                          {"collides", c.collides},
                          {"obstacle", c.collides && c.obstacle >= 0 ? json(c.obstacle) : json(nullptr)},
                          {"part", c.part},
                          {"surface", c.surface.empty() ? json(nullptr) : json(c.surface)},
                          {"t", c.collides ? json(c.t) : json(nullptr)},
                          {"clearance", number(c.clearance)}});
    }
    paths.push_back({{"name", p.path.name},
                     {"colour", plot::toHex(plot::pathColour(i))},
                     {"waypoints", waypoints},
                     {"segments", segments},
                     {"first_colliding_segment",
                      p.check.first_colliding_segment ? json(*p.check.first_colliding_segment) : json(nullptr)},
                     {"first_contact", p.check.first_contact ? vec(*p.check.first_contact) : json(nullptr)}});
  }
  return paths;
}

// The roadmap's nodes and edges at its height; null without one.
json roadmapJson(const ViewScene& scene, const Eigen::Vector3d& shift) {
  if (!scene.roadmap) return nullptr;
  const ViewRoadmap& r = *scene.roadmap;
  Bytes nodes, edges;
  for (const auto& n : r.nodes) putLocal(nodes, Eigen::Vector3d(n.x(), n.y(), r.z), shift);
  for (const auto& e : r.edges) {
    for (std::size_t k = 0; k + 1 < e.size(); ++k) {
      putLocal(edges, Eigen::Vector3d(e[k].x(), e[k].y(), r.z), shift);
      putLocal(edges, Eigen::Vector3d(e[k + 1].x(), e[k + 1].y(), r.z), shift);
    }
  }
  return {{"name", r.name},
          {"z", r.z},
          {"nodes", r.nodes.size()},
          {"edges", r.edges.size()},
          {"node_positions", nodes.base64()},
          {"edge_segments", edges.base64()}};
}

// The ground truth's shapes as wireframe segments; null without one.
json truthJson(const ViewScene& scene, const Eigen::Vector3d& shift) {
  if (!scene.truth) return nullptr;
  Bytes segments;
  json shapes = json::array();
  for (const auto& s : scene.truth->shapes) {
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> lines;
    truthSegments(s, lines);
    for (const auto& [a, b] : lines) {
      putLocal(segments, a, shift);
      putLocal(segments, b, shift);
    }
    shapes.push_back({{"label", s.label}, {"surface", s.surface}, {"segments", lines.size()}});
  }
  return {{"name", scene.truth_name}, {"shapes", shapes}, {"segments", segments.base64()}};
}

json pageData(const ViewScene& scene, const std::vector<VoxelCells>& levels, std::size_t max_instances) {
  const Eigen::AlignedBox3d box = viewBox(scene);
  const Eigen::Vector3d shift = box.center();
  json data = pageHeader(scene, box);
  data["voxels"] = voxelsJson(scene, levels, max_instances);
  addHulls(scene, shift, data);
  data["floor"] = planeJson(scene.report, "floor");
  data["ceiling"] = planeJson(scene.report, "ceiling");
  data["keyframes"] = keyframesJson(scene, shift);
  data["paths"] = pathsJson(scene);
  data["roadmap"] = roadmapJson(scene, shift);
  data["truth"] = truthJson(scene, shift);
  return data;
}

}  // namespace

ViewScene readScene(const fs::path& build_dir, ViewInputs inputs) {
  if (!inputs.paths.empty() && !(inputs.radius >= 0.0 && std::isfinite(inputs.radius)))
    throw Error::inParameter("radius", "must be a finite number >= 0");
  for (const auto& p : inputs.paths) {
    if (p.waypoints.size() < 2)
      throw Error::inParameter(
          "paths", p.name + ": a path needs at least two waypoints, got " + std::to_string(p.waypoints.size()));
  }
  std::error_code ec;
  if (!fs::is_directory(build_dir, ec))
    throw Error(build_dir.string() + ": not a directory (a `hullmap build` output)");
  ViewScene scene;
  fs::path name = build_dir.lexically_normal();
  if (name.filename().empty()) name = name.parent_path();
  scene.title = name.filename().string();
  if (scene.title.empty() || scene.title == ".")
    scene.title = fs::absolute(build_dir).lexically_normal().filename().string();
  scene.report = pipeline::readReport(build_dir / "report.json");
  scene.resolution = scene.report["parameters"]["resolution"].get<double>();
  for (const auto& row : pipeline::readVoxelsCsv(build_dir / "voxels.csv")) {
    scene.centers.push_back(row.center);
    scene.labels.push_back(row.label);
  }
  const pipeline::MapObstacles map = pipeline::readMapObstacles(build_dir / "obstacles.json");
  scene.obstacles = map.obstacles;
  if (auto keyframes = pipeline::readBuildTrajectory(build_dir)) scene.keyframes = std::move(*keyframes);
  scene.radius = inputs.radius;
  if (!inputs.paths.empty()) {
    const collision::HullChecker checker = pipeline::pathChecker(map);
    for (auto& p : inputs.paths) {
      CheckedPath checked;
      checked.check = checker.checkPath(p.waypoints, collision::CheckRequest{inputs.radius});
      checked.path = std::move(p);
      scene.paths.push_back(std::move(checked));
    }
  }
  scene.roadmap = std::move(inputs.roadmap);
  scene.truth = std::move(inputs.truth);
  scene.truth_name = std::move(inputs.truth_name);
  return scene;
}

ViewPage renderPage(const ViewScene& scene, const ViewParams& params) {
  if (!(scene.resolution > 0.0) || !std::isfinite(scene.resolution))
    throw Error::inParameter("resolution", "must be a positive finite number");
  const std::string three = readWhole(params.three_dir / "three.min.js");
  const std::string orbit = readWhole(params.three_dir / "examples" / "js" / "controls" / "OrbitControls.js");
  const std::vector<VoxelCells> levels =
      voxelLevels(scene.centers, scene.labels, scene.resolution, params.max_instances);

  ViewPage page;
  page.voxels = scene.centers.size();
  page.instances = levels.front().centers.size();
  page.merge_factor = levels.front().factor;
  for (const auto& level : levels) page.levels.push_back(level.centers.size());
  for (const auto& o : scene.obstacles) page.hulls += std::max<std::size_t>(1, o.parts.size());
  for (const auto& p : scene.paths) page.colliding_paths += p.check.first_colliding_segment.has_value();

  const json data = pageData(scene, levels, params.max_instances);
  std::string& html = page.html;
  html += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html += "<meta name=\"generator\" content=\"hullmap view\">\n";
  html += "<title>hullmap view: " + core::escapeMarkup(scene.title) + "</title>\n";
  html += "<style>\n" + std::string(detail::kViewerCss) + "</style>\n";
  // Errors are collected before anything else runs, so that the page can say it failed.
  html += "<script>\n" + std::string(detail::kErrorHook) + "</script>\n</head>\n<body>\n";
  html += "<script>/* three.js r111 (MIT License), read from " +
          core::escapeMarkup((params.three_dir / "three.min.js").string()) + " (Debian's " + kThreePackage +
          ") when this page was written */\n" + scriptSafe(three) + "\n</script>\n";
  html += "<script>/* OrbitControls from three.js r111's examples (MIT License), Debian's " +
          std::string(kThreePackage) + " */\n" + scriptSafe(orbit) + "\n</script>\n";
  // "<" only occurs inside JSON strings, where \u003c reads back the same: nothing can end the element.
  std::string json_text;
  for (char c : data.dump()) {
    if (c == '<')
      json_text += "\\u003c";
    else
      json_text += c;
  }
  html += "<script type=\"application/json\" id=\"hullmap-data\">" + json_text + "</script>\n";
  html += "<script>\n" + std::string(detail::kViewerScript) + "</script>\n</body>\n</html>\n";
  return page;
}

ViewPage writePage(const ViewScene& scene, const fs::path& html, const ViewParams& params) {
  ViewPage page = renderPage(scene, params);
  core::writeFileAtomically(html.string(), [&](std::ostream& os) { os << page.html; });
  return page;
}

}  // namespace hullmap::view
