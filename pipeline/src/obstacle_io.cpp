#include "hullmap/pipeline/obstacle_io.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>

#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"
#include "obstacle_text.hpp"

namespace hullmap::pipeline {
namespace {

using nlohmann::json;

json vec3(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

json hullJson(const hulls::ConvexHull& hull) {
  json vertices = json::array();
  for (const auto& v : hull.vertices) vertices.push_back(vec3(v));
  json triangles = json::array();
  for (const auto& t : hull.triangles) triangles.push_back({t[0], t[1], t[2]});
  return {{"vertices", vertices}, {"triangles", triangles}};
}

json footprintJson(const hulls::Footprint& footprint) {
  json polygon = json::array();
  for (const auto& p : footprint.polygon) polygon.push_back({p.x(), p.y()});
  return {{"polygon", polygon}, {"z_min", footprint.z_min}, {"z_max", footprint.z_max}};
}

/// Reading side: every access names the source and the JSON path that is wrong.
struct Reader {
  const std::string& source;

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw Error(source + ": " + where + ": " + what);
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
  hulls::ConvexHull hull(const json& j, const std::string& at) const {
    hulls::ConvexHull out;
    const json& vertices = array(field(j, "vertices", at), at + ".vertices");
    for (std::size_t i = 0; i < vertices.size(); ++i)
      out.vertices.push_back(point3(vertices[i], at + ".vertices[" + std::to_string(i) + "]"));
    const json& triangles = array(field(j, "triangles", at), at + ".triangles");
    for (std::size_t i = 0; i < triangles.size(); ++i) {
      const std::string where = at + ".triangles[" + std::to_string(i) + "]";
      const json& t = triangles[i];
      if (!t.is_array() || t.size() != 3) fail(where, "expected [i, j, k]");
      std::array<int, 3> tri{};
      for (int c = 0; c < 3; ++c) {
        if (!t[c].is_number_integer() || t[c].get<std::int64_t>() < 0 ||
            t[c].get<std::int64_t>() >= std::int64_t(out.vertices.size()))
          fail(where, "vertex index out of range (0.." + std::to_string(out.vertices.size()) + ")");
        tri[std::size_t(c)] = t[c].get<int>();
      }
      out.triangles.push_back(tri);
    }
    if (out.vertices.size() < 4 || out.triangles.size() < 4)
      fail(at, "a closed hull needs at least 4 vertices and 4 triangles");
    return out;
  }
  hulls::Footprint footprint(const json& j, const std::string& at) const {
    hulls::Footprint out;
    const json& polygon = array(field(j, "polygon", at), at + ".polygon");
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const std::string where = at + ".polygon[" + std::to_string(i) + "]";
      if (!polygon[i].is_array() || polygon[i].size() != 2) fail(where, "expected [x, y]");
      out.polygon.emplace_back(number(polygon[i][0], where), number(polygon[i][1], where));
    }
    out.z_min = number(field(j, "z_min", at), at + ".z_min");
    out.z_max = number(field(j, "z_max", at), at + ".z_max");
    return out;
  }
  /// The fields a whole obstacle and a part share.
  template <class T>
  void common(const json& j, const std::string& at, T& o) const {
    o.voxel_count = count(field(j, "voxel_count", at), at + ".voxel_count");
    o.point_weight = count(field(j, "point_weight", at), at + ".point_weight");
    const json& aabb = field(j, "aabb", at);
    o.aabb_min = point3(field(aabb, "min", at + ".aabb"), at + ".aabb.min");
    o.aabb_max = point3(field(aabb, "max", at + ".aabb"), at + ".aabb.max");
    o.centroid = point3(field(j, "centroid", at), at + ".centroid");
    o.volume = number(field(j, "volume", at), at + ".volume");
    o.hull = hull(field(j, "hull", at), at + ".hull");
    o.footprint = footprint(field(j, "footprint", at), at + ".footprint");
  }
};

template <class T>
json commonJson(const T& o) {
  return {{"voxel_count", o.voxel_count},
          {"point_weight", o.point_weight},
          {"aabb", {{"min", vec3(o.aabb_min)}, {"max", vec3(o.aabb_max)}}},
          {"centroid", vec3(o.centroid)},
          {"volume", o.volume},
          {"hull", hullJson(o.hull)},
          {"footprint", footprintJson(o.footprint)}};
}

json surfacesJson(const std::vector<collision::Surface>& surfaces) {
  json list = json::array();
  for (const auto& h : surfaces) {
    if (!h.field) {
      list.push_back({{"name", h.name}, {"normal", vec3(h.normal)}, {"offset", h.offset}});
      continue;
    }
    const HeightField& f = *h.field;
    list.push_back({{"name", h.name},
                    {"kind", "heightfield"},
                    {"origin", {f.origin.x(), f.origin.y()}},
                    {"step", f.step},
                    {"nx", f.nx},
                    {"ny", f.ny},
                    {"heights", f.heights}});
  }
  return list;
}

/// A surfaces[] entry of kind "heightfield".
HeightField heightFieldFromJson(const Reader& r, const json& entry, const std::string& at) {
  HeightField f;
  const json& origin = r.array(r.field(entry, "origin", at), at + ".origin");
  if (origin.size() != 2) r.fail(at + ".origin", "expected [x, y]");
  f.origin = {r.number(origin[0], at + ".origin"), r.number(origin[1], at + ".origin")};
  f.step = r.number(r.field(entry, "step", at), at + ".step");
  f.nx = std::size_t(r.count(r.field(entry, "nx", at), at + ".nx"));
  f.ny = std::size_t(r.count(r.field(entry, "ny", at), at + ".ny"));
  const json& heights = r.array(r.field(entry, "heights", at), at + ".heights");
  if (f.nx == 0 || f.ny == 0 || heights.size() / f.nx != f.ny || heights.size() % f.nx != 0)
    r.fail(at + ".heights", "expected nx * ny >= 1 heights");
  f.heights.reserve(heights.size());
  for (const json& z : heights) f.heights.push_back(r.number(z, at + ".heights"));
  if (!f.valid()) r.fail(at, "expected a finite origin, a finite step > 0 and finite heights");
  return f;
}

std::vector<collision::Surface> surfacesFromJson(const Reader& r, const json& list) {
  std::vector<collision::Surface> surfaces;
  r.array(list, "surfaces");
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string at = "surfaces[" + std::to_string(k) + "]";
    collision::Surface h;
    const json& name = r.field(list[k], "name", at);
    if (!name.is_string()) r.fail(at + ".name", "expected a string");
    h.name = name.get<std::string>();
    std::string kind = "plane";
    if (const auto found = list[k].find("kind"); found != list[k].end()) {
      if (!found->is_string()) r.fail(at + ".kind", "expected a string");
      kind = found->get<std::string>();
    }
    if (kind == "heightfield") {
      surfaces.push_back(collision::Surface::heightField(h.name, heightFieldFromJson(r, list[k], at)));
      continue;
    }
    if (kind != "plane") r.fail(at + ".kind", "expected \"plane\" or \"heightfield\", got \"" + kind + "\"");
    h.normal = r.point3(r.field(list[k], "normal", at), at + ".normal");
    if (!(std::abs(h.normal.norm() - 1.0) <= 1e-6)) r.fail(at + ".normal", "expected a unit vector");
    h.normal.normalize();
    h.offset = r.number(r.field(list[k], "offset", at), at + ".offset");
    surfaces.push_back(std::move(h));
  }
  return surfaces;
}

}  // namespace

json similarityJson(const mapper::Similarity& s, bool exact) {
  json rotation = json::array();
  for (int i = 0; i < 3; ++i) rotation.push_back({s.rotation(i, 0), s.rotation(i, 1), s.rotation(i, 2)});
  const Eigen::Matrix4d m = mapper::toMatrix(s);
  json matrix = json::array();
  for (int i = 0; i < 4; ++i) matrix.push_back({m(i, 0), m(i, 1), m(i, 2), m(i, 3)});
  return {{"scale", s.scale},
          {"rotation", rotation},
          {"translation", vec3(s.translation)},
          {"matrix", matrix},
          {"exact", exact}};
}

mapper::Similarity similarityFromJson(const json& j, const std::string& source, const std::string& where) {
  const Reader r{source};
  mapper::Similarity s;
  s.scale = r.number(r.field(j, "scale", where), where + ".scale");
  if (!(s.scale > 0.0) || !std::isfinite(s.scale)) r.fail(where + ".scale", "expected a number > 0");
  const json& rows = r.array(r.field(j, "rotation", where), where + ".rotation");
  if (rows.size() != 3) r.fail(where + ".rotation", "expected 3 rows of 3 numbers");
  for (int i = 0; i < 3; ++i) s.rotation.row(i) = r.point3(rows[std::size_t(i)], where + ".rotation").transpose();
  if (!((s.rotation * s.rotation.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-6) ||
      !(s.rotation.determinant() > 0.0))
    r.fail(where + ".rotation", "expected a proper rotation matrix");
  s.translation = r.point3(r.field(j, "translation", where), where + ".translation");
  return s;
}

namespace {

/// One entry of obstacles.json's "obstacles".
json obstacleJson(const hulls::Obstacle& o) {
  json entry = commonJson(o);
  entry["id"] = o.id;
  json parts = json::array();
  for (const auto& p : o.parts) {
    json part = commonJson(p);
    part["concavity_bound"] = p.concavity_bound;
    part["free_voxels_inside"] = p.free_voxels_inside;
    part["free_voxels_off_surface"] = p.free_voxels_off_surface;
    part["flat"] = p.flat;
    part["filled"] = p.filled;
    part["faces"] = p.faces;
    parts.push_back(std::move(part));
  }
  entry["parts"] = std::move(parts);
  return entry;
}

/// Everything of obstacles.json but the obstacles ("obstacles" an empty array).
json obstaclesHead(const ObstaclesMeta& meta) {
  json doc;
  doc["format"] = kObstaclesFormatV2;
  doc["frame"] = meta.frame;
  doc["parameters"] = meta.parameters;
  doc["surfaces"] = surfacesJson(meta.surfaces);
  if (meta.input_to_output) doc["input_to_output"] = similarityJson(*meta.input_to_output, meta.input_to_output_exact);
  doc["obstacles"] = json::array();
  return doc;
}

}  // namespace

json obstaclesToJson(const std::vector<hulls::Obstacle>& obstacles, const ObstaclesMeta& meta) {
  json doc = obstaclesHead(meta);
  json& list = doc["obstacles"];
  for (const auto& o : obstacles) list.push_back(obstacleJson(o));
  return doc;
}

std::vector<hulls::Obstacle> obstaclesFromJson(const json& doc, const std::string& source, ObstaclesMeta* meta) {
  const Reader r{source};
  const json& format = r.field(doc, "format", "top level");
  const bool v1 = format.is_string() && format.get<std::string>() == kObstaclesFormatV1;
  const bool v2 = format.is_string() && format.get<std::string>() == kObstaclesFormatV2;
  if (!v1 && !v2)
    r.fail("format", std::string("expected \"") + kObstaclesFormatV2 + "\" or \"" + kObstaclesFormatV1 + "\", got " +
                         format.dump());
  if (meta) {
    meta->format = format.get<std::string>();
    const json& frame = r.field(doc, "frame", "top level");
    if (!frame.is_string()) r.fail("frame", "expected a string");
    meta->frame = frame.get<std::string>();
    meta->parameters = r.field(doc, "parameters", "top level");
    // Written since surfaces became obstacles for path checks; absent in older files: none.
    if (const auto surfaces = doc.find("surfaces"); surfaces != doc.end())
      meta->surfaces = surfacesFromJson(r, *surfaces);
    if (const auto frame_change = doc.find("input_to_output"); frame_change != doc.end()) {
      meta->input_to_output = similarityFromJson(*frame_change, source, "input_to_output");
      if (const auto exact = frame_change->find("exact"); exact != frame_change->end()) {
        if (!exact->is_boolean()) r.fail("input_to_output.exact", "expected true or false");
        meta->input_to_output_exact = exact->get<bool>();
      }
    }
  }
  std::vector<hulls::Obstacle> obstacles;
  const json& list = r.array(r.field(doc, "obstacles", "top level"), "obstacles");
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string at = "obstacles[" + std::to_string(k) + "]";
    const json& j = list[k];
    hulls::Obstacle o;
    const json& id = r.field(j, "id", at);
    if (!id.is_number_integer()) r.fail(at + ".id", "expected an integer");
    o.id = id.get<int>();
    r.common(j, at, o);
    if (v2) {
      const json& parts = r.array(r.field(j, "parts", at), at + ".parts");
      for (std::size_t p = 0; p < parts.size(); ++p) {
        const std::string where = at + ".parts[" + std::to_string(p) + "]";
        hulls::ObstaclePart part;
        r.common(parts[p], where, part);
        part.concavity_bound = r.number(r.field(parts[p], "concavity_bound", where), where + ".concavity_bound");
        part.free_voxels_inside =
            r.count(r.field(parts[p], "free_voxels_inside", where), where + ".free_voxels_inside");
        // Written since the surface band came in; absent in older /2 files: 0.
        if (const auto off = parts[p].find("free_voxels_off_surface"); off != parts[p].end()) {
          part.free_voxels_off_surface = r.count(*off, where + ".free_voxels_off_surface");
        }
        // Written since the flat gap came in; absent in older /2 files: not flat.
        if (const auto flat = parts[p].find("flat"); flat != parts[p].end()) {
          if (!flat->is_boolean()) r.fail(where + ".flat", "expected true or false");
          part.flat = flat->get<bool>();
        }
        if (const auto filled = parts[p].find("filled"); filled != parts[p].end()) {
          if (!filled->is_boolean()) r.fail(where + ".filled", "expected true or false");
          part.filled = filled->get<bool>();
        }
        // Written since the face-hole rule came in; absent in older /2 files: false.
        if (const auto faces = parts[p].find("faces"); faces != parts[p].end()) {
          if (!faces->is_boolean()) r.fail(where + ".faces", "expected true or false");
          part.faces = faces->get<bool>();
        }
        o.parts.push_back(std::move(part));
      }
    }
    obstacles.push_back(std::move(o));
  }
  return obstacles;
}

void writeObstaclesJson(const std::string& path, const std::vector<hulls::Obstacle>& obstacles,
                        const ObstaclesMeta& meta) {
  // The bytes of obstaclesToJson(obstacles, meta).dump(1): the head dumped from its document, the
  // obstacles (most of the file) written straight to text in parallel at their depth in the
  // document (2, as elements of a top-level array), put in the place of the head's empty list.
  std::string text = obstaclesHead(meta).dump(1);
  if (!obstacles.empty()) {
    std::vector<std::string> entries(obstacles.size());
    tbb::parallel_for(std::size_t(0), obstacles.size(), [&](std::size_t k) {
      entries[k] = "  ";
      dumpObstacleText(entries[k], obstacles[k], 2);
    });
    std::string list = "[\n";
    for (std::size_t k = 0; k < entries.size(); ++k) {
      list += entries[k];
      list += k + 1 < entries.size() ? ",\n" : "\n";
    }
    list += " ]";
    const std::string empty = "\n \"obstacles\": []";
    const std::size_t at = text.find(empty);
    if (at == std::string::npos) throw Error(path + ": internal error: no obstacles list to fill");
    text.replace(at + empty.size() - 2, 2, list);
  }
  core::writeFileAtomically(path, [&](std::ostream& out) { out << text << '\n'; });
}

std::vector<hulls::Obstacle> readObstaclesJson(const std::string& path, ObstaclesMeta* meta) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open");
  json doc;
  try {
    doc = json::parse(in);
  } catch (const json::parse_error& e) {
    throw Error(path + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
  }
  return obstaclesFromJson(doc, path, meta);
}

}  // namespace hullmap::pipeline
