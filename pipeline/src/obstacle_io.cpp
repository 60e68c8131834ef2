#include "hullmap/pipeline/obstacle_io.hpp"

#include <fstream>
#include <iomanip>
#include <limits>

#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::pipeline {
namespace {

using nlohmann::json;

json vec3(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

/// Reading side: every access names the file and the JSON path that is wrong.
struct Reader {
  const std::string& file;

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw Error(file + ": " + where + ": " + what);
  }
  const json& field(const json& object, const char* key, const std::string& where) const {
    if (!object.is_object()) fail(where, "expected an object");
    const auto it = object.find(key);
    if (it == object.end()) fail(where, std::string("missing \"") + key + "\"");
    return *it;
  }
  double number(const json& j, const std::string& where) const {
    if (!j.is_number()) fail(where, "expected a number");
    return j.get<double>();
  }
  std::uint64_t count(const json& j, const std::string& where) const {
    if (!j.is_number_unsigned() && !(j.is_number_integer() && j.get<std::int64_t>() >= 0))
      fail(where, "expected a non-negative integer");
    return j.get<std::uint64_t>();
  }
  Eigen::Vector3d point3(const json& j, const std::string& where) const {
    if (!j.is_array() || j.size() != 3) fail(where, "expected [x, y, z]");
    return {number(j[0], where), number(j[1], where), number(j[2], where)};
  }
  const json& array(const json& j, const std::string& where) const {
    if (!j.is_array()) fail(where, "expected an array");
    return j;
  }
};

}  // namespace

void writeObstaclesJson(const std::string& path, const std::vector<clustering::Obstacle>& obstacles,
                        const ObstaclesMeta& meta) {
  json doc;
  doc["format"] = kObstaclesFormat;
  doc["frame"] = meta.frame;
  doc["parameters"] = meta.parameters;
  json list = json::array();
  for (const auto& o : obstacles) {
    json vertices = json::array();
    for (const auto& v : o.hull.vertices) vertices.push_back(vec3(v));
    json triangles = json::array();
    for (const auto& t : o.hull.triangles) triangles.push_back({t[0], t[1], t[2]});
    json polygon = json::array();
    for (const auto& p : o.footprint.polygon) polygon.push_back({p.x(), p.y()});
    list.push_back({{"id", o.id},
                    {"voxel_count", o.voxel_count},
                    {"point_weight", o.point_weight},
                    {"aabb", {{"min", vec3(o.aabb_min)}, {"max", vec3(o.aabb_max)}}},
                    {"centroid", vec3(o.centroid)},
                    {"volume", o.volume},
                    {"hull", {{"vertices", vertices}, {"triangles", triangles}}},
                    {"footprint", {{"polygon", polygon}, {"z_min", o.footprint.z_min}, {"z_max", o.footprint.z_max}}}});
  }
  doc["obstacles"] = std::move(list);
  core::writeFileAtomically(path, [&](std::ostream& out) { out << doc.dump(1) << '\n'; });
}

std::vector<clustering::Obstacle> readObstaclesJson(const std::string& path, ObstaclesMeta* meta) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open");
  json doc;
  try {
    doc = json::parse(in);
  } catch (const json::parse_error& e) {
    throw Error(path + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
  }
  const Reader r{path};
  const json& format = r.field(doc, "format", "top level");
  if (!format.is_string() || format.get<std::string>() != kObstaclesFormat)
    r.fail("format", std::string("expected \"") + kObstaclesFormat + "\", got " + format.dump());
  if (meta) {
    const json& frame = r.field(doc, "frame", "top level");
    if (!frame.is_string()) r.fail("frame", "expected a string");
    meta->frame = frame.get<std::string>();
    meta->parameters = r.field(doc, "parameters", "top level");
  }
  std::vector<clustering::Obstacle> obstacles;
  const json& list = r.array(r.field(doc, "obstacles", "top level"), "obstacles");
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string at = "obstacles[" + std::to_string(k) + "]";
    const json& j = list[k];
    clustering::Obstacle o;
    const json& id = r.field(j, "id", at);
    if (!id.is_number_integer()) r.fail(at + ".id", "expected an integer");
    o.id = id.get<int>();
    o.voxel_count = r.count(r.field(j, "voxel_count", at), at + ".voxel_count");
    o.point_weight = r.count(r.field(j, "point_weight", at), at + ".point_weight");
    const json& aabb = r.field(j, "aabb", at);
    o.aabb_min = r.point3(r.field(aabb, "min", at + ".aabb"), at + ".aabb.min");
    o.aabb_max = r.point3(r.field(aabb, "max", at + ".aabb"), at + ".aabb.max");
    o.centroid = r.point3(r.field(j, "centroid", at), at + ".centroid");
    o.volume = r.number(r.field(j, "volume", at), at + ".volume");
    const json& hull = r.field(j, "hull", at);
    const json& vertices = r.array(r.field(hull, "vertices", at + ".hull"), at + ".hull.vertices");
    for (std::size_t i = 0; i < vertices.size(); ++i)
      o.hull.vertices.push_back(r.point3(vertices[i], at + ".hull.vertices[" + std::to_string(i) + "]"));
    const json& triangles = r.array(r.field(hull, "triangles", at + ".hull"), at + ".hull.triangles");
    for (std::size_t i = 0; i < triangles.size(); ++i) {
      const std::string where = at + ".hull.triangles[" + std::to_string(i) + "]";
      const json& t = triangles[i];
      if (!t.is_array() || t.size() != 3) r.fail(where, "expected [i, j, k]");
      std::array<int, 3> tri{};
      for (int c = 0; c < 3; ++c) {
        if (!t[c].is_number_integer() || t[c].get<std::int64_t>() < 0 ||
            t[c].get<std::int64_t>() >= std::int64_t(o.hull.vertices.size()))
          r.fail(where, "vertex index out of range (0.." + std::to_string(o.hull.vertices.size()) + ")");
        tri[c] = t[c].get<int>();
      }
      o.hull.triangles.push_back(tri);
    }
    if (o.hull.vertices.size() < 4 || o.hull.triangles.size() < 4)
      r.fail(at + ".hull", "a closed hull needs at least 4 vertices and 4 triangles");
    const json& footprint = r.field(j, "footprint", at);
    const json& polygon = r.array(r.field(footprint, "polygon", at + ".footprint"), at + ".footprint.polygon");
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const std::string where = at + ".footprint.polygon[" + std::to_string(i) + "]";
      if (!polygon[i].is_array() || polygon[i].size() != 2) r.fail(where, "expected [x, y]");
      o.footprint.polygon.emplace_back(r.number(polygon[i][0], where), r.number(polygon[i][1], where));
    }
    o.footprint.z_min = r.number(r.field(footprint, "z_min", at + ".footprint"), at + ".footprint.z_min");
    o.footprint.z_max = r.number(r.field(footprint, "z_max", at + ".footprint"), at + ".footprint.z_max");
    obstacles.push_back(std::move(o));
  }
  return obstacles;
}

void writeObstaclesObj(const std::string& path, const std::vector<clustering::Obstacle>& obstacles) {
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "# hullmap obstacles: convex hulls, z-up map frame\n";
    out << std::setprecision(std::numeric_limits<double>::max_digits10);
    std::size_t base = 1;
    for (const auto& o : obstacles) {
      out << "o obstacle_" << o.id << '\n';
      for (const auto& v : o.hull.vertices) out << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
      for (const auto& t : o.hull.triangles)
        out << "f " << base + t[0] << ' ' << base + t[1] << ' ' << base + t[2] << '\n';
      base += o.hull.vertices.size();
    }
  });
}

}  // namespace hullmap::pipeline
