// roadmap.json: writing it (roadmapJson, writeRoadmapJson) and reading it back.
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/planning/roadmap.hpp"
#include "hullmap/planning/roadmap_json.hpp"

namespace hullmap::planning {

std::string roadmapJson(const Roadmap& roadmap) {
  using nlohmann::json;
  auto xy = [](const Eigen::Vector2d& p) { return json::array({p.x(), p.y()}); };
  auto site = [&](const SiteRef& s) {
    json j{{"obstacle", s.obstacle >= 0 ? json(s.obstacle) : json(nullptr)}};
    if (s.is_point)
      j["point"] = xy(s.a);
    else
      j["segment"] = json::array({xy(s.a), xy(s.b)});
    return j;
  };
  json j;
  j["format"] = "hullmap-roadmap/1";
  j["frame"] = "z-up map";
  j["bounds"] = {roadmap.bounds.x0, roadmap.bounds.y0, roadmap.bounds.x1, roadmap.bounds.y1};
  j["band"] = {roadmap.z0, roadmap.z1};
  j["min_clearance"] = roadmap.min_clearance;
  j["tolerance"] = roadmap.tolerance;
  j["obstacles"] = json::array();
  for (std::size_t i = 0; i < roadmap.footprints.size(); ++i) {
    json o{{"ids", roadmap.obstacle_groups[i]}, {"footprint", json::array()}};
    for (const auto& p : roadmap.footprints[i]) o["footprint"].push_back(xy(p));
    if (i < roadmap.holes.size() && !roadmap.holes[i].empty()) {
      o["holes"] = json::array();
      for (const auto& hole : roadmap.holes[i]) {
        json h = json::array();
        for (const auto& p : hole) h.push_back(xy(p));
        o["holes"].push_back(std::move(h));
      }
    }
    j["obstacles"].push_back(std::move(o));
  }
  j["nodes"] = json::array();
  for (const auto& n : roadmap.nodes) j["nodes"].push_back(xy(n.position));
  j["edges"] = json::array();
  for (const auto& e : roadmap.edges) {
    json je{{"from", e.from}, {"to", e.to}, {"length", e.length}, {"clearance", e.clearance}};
    je["sites"] = json::array({site(e.site_a), site(e.site_b)});
    je["polyline"] = json::array();
    for (const auto& p : e.polyline) je["polyline"].push_back(xy(p));
    j["edges"].push_back(std::move(je));
  }
  return j.dump(1) + "\n";
}

void writeRoadmapJson(const std::string& path, const Roadmap& roadmap) {
  const std::string text = roadmapJson(roadmap);
  core::writeFileAtomically(path, [&](std::ostream& out) { out << text; });
}

Roadmap readRoadmapJson(const std::string& path) {
  using nlohmann::json;
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    throw Error(path + ": not JSON: " + e.what());
  }
  if (!j.is_object() || j.value("format", std::string()) != "hullmap-roadmap/1")
    throw Error(path + ": not a hullmap roadmap (format \"hullmap-roadmap/1\")");
  Roadmap map;
  try {
    auto xy = [](const json& p) {
      if (!p.is_array() || p.size() != 2) throw Error("a point is not [x, y]");
      return Eigen::Vector2d(p.at(0).get<double>(), p.at(1).get<double>());
    };
    const auto& b = j.at("bounds");
    map.bounds = {b.at(0).get<double>(), b.at(1).get<double>(), b.at(2).get<double>(), b.at(3).get<double>()};
    map.z0 = j.at("band").at(0).get<double>();
    map.z1 = j.at("band").at(1).get<double>();
    map.min_clearance = j.at("min_clearance").get<double>();
    map.tolerance = j.at("tolerance").get<double>();
    for (const auto& o : j.at("obstacles")) {
      map.obstacle_groups.push_back(o.at("ids").get<std::vector<int>>());
      map.footprints.emplace_back();
      for (const auto& p : o.at("footprint")) map.footprints.back().push_back(xy(p));
      map.holes.emplace_back();
      if (o.contains("holes"))
        for (const auto& h : o.at("holes")) {
          map.holes.back().emplace_back();
          for (const auto& p : h) map.holes.back().back().push_back(xy(p));
        }
    }
    for (const auto& n : j.at("nodes")) map.nodes.push_back({xy(n)});
    const int nodes = static_cast<int>(map.nodes.size());
    auto site = [&](const json& s) {
      SiteRef r;
      r.obstacle = s.at("obstacle").is_null() ? -1 : s.at("obstacle").get<int>();
      r.is_point = s.contains("point");
      r.a = xy(r.is_point ? s.at("point") : s.at("segment").at(0));
      r.b = r.is_point ? r.a : xy(s.at("segment").at(1));
      return r;
    };
    for (const auto& je : j.at("edges")) {
      RoadmapEdge e;
      e.from = je.at("from").get<int>();
      e.to = je.at("to").get<int>();
      if (e.from < 0 || e.from >= nodes || e.to < 0 || e.to >= nodes)
        throw Error("edge " + std::to_string(map.edges.size()) + " names a node out of range");
      e.length = je.at("length").get<double>();
      e.clearance = je.at("clearance").get<double>();
      e.site_a = site(je.at("sites").at(0));
      e.site_b = site(je.at("sites").at(1));
      for (const auto& p : je.at("polyline")) e.polyline.push_back(xy(p));
      if (e.polyline.size() < 2)
        throw Error("edge " + std::to_string(map.edges.size()) + " has a polyline of fewer than 2 points");
      map.edges.push_back(std::move(e));
    }
  } catch (const json::exception& e) {
    throw Error(path + ": " + e.what());
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
  return map;
}

}  // namespace hullmap::planning
