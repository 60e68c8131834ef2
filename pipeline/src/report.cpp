// report.json: the parameters and what a build did, as JSON; and the frame's description.
#include "hullmap/pipeline/report.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "hullmap/core/constants.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "input_points.hpp"

namespace hullmap::pipeline {

namespace fs = std::filesystem;

std::string upAxisText(mapper::UpAxis up) {
  const std::string text = mapper::toString(up);
  return text[0] == '+' ? text.substr(1) : text;
}

std::string frameDescription(const mapper::FrameParams& frame) {
  std::ostringstream s;
  s << "z-up map frame: input axis " << upAxisText(frame.up) << " rotated to +z";
  if (frame.scale != 1.0) s << ", scaled by " << frame.scale;
  return s.str();
}

bool inputToOutputExact(const BuildReport& report) { return !(report.alignment && report.alignment->drift); }

std::string outputFrame(const BuildResult& result) {
  if (readsOctree(result.params)) {
    return "the octree's own frame (" + result.params.inputs.front().string() +
           " read as it is: no up axis or scale applied)";
  }
  std::ostringstream s;
  if (result.report.alignment && result.params.align) {
    const auto& a = *result.report.alignment;
    s << "the reference trajectory's frame (" << result.params.align->reference.string();
    if (a.drift) {
      const auto [low, high] = std::minmax_element(a.drift->scales.begin(), a.drift->scales.end());
      s << ": keyframes fitted with the scale drifting along the path, " << *low << " to " << *high << ")";
    } else {
      s << ": keyframes fitted by a similarity, scale " << a.transform.scale << ")";
    }
  } else {
    s << frameDescription(result.params.frame);
  }
  if (result.report.floor.levelled) {
    s << ", then levelled: the floor rotated level and moved to z = 0 (report.json \"levelling\")";
  }
  return s.str();
}

namespace {

nlohmann::json planeSettingJson(const mapper::PlaneSetting& setting) {
  switch (setting.mode) {
    case mapper::PlaneSetting::Mode::kAuto:
      return "auto";
    case mapper::PlaneSetting::Mode::kNone:
      return "none";
    case mapper::PlaneSetting::Mode::kHeight:
      break;
  }
  return setting.height;
}

nlohmann::json planeJson(const mapper::Plane& plane) {
  return {{"normal", {plane.normal.x(), plane.normal.y(), plane.normal.z()}}, {"offset", plane.offset}};
}

nlohmann::json planeReportJson(const PlaneReport& r) {
  using nlohmann::json;
  json out = {{"setting", planeSettingJson(r.setting)},
              {"found", r.plane.has_value()},
              {"plane", r.plane ? planeJson(*r.plane) : json(nullptr)},
              {"levelled", r.levelled},
              {"voxels", r.voxels}};
  if (r.ground_instead) out["ground_instead"] = true;
  if (r.setting.mode == mapper::PlaneSetting::Mode::kAuto) {
    out["search"] = {{"found", r.fit.found},
                     {"reason", r.fit.found ? json(nullptr) : json(r.fit.reason)},
                     {"candidate", planeJson(r.fit.plane)},
                     {"tilt_deg", r.fit.tilt_deg},
                     {"inliers", r.fit.inliers},
                     {"inlier_share", r.fit.inlier_share},
                     {"beyond_share", r.fit.beyond_share},
                     {"coverage", r.fit.coverage}};
  }
  return out;
}

/// The ground's entry: null when none was fitted or none explained the map.
nlohmann::json groundJson(const BuildParams& params, const std::optional<GroundReport>& ground) {
  using nlohmann::json;
  if (!ground) return nullptr;
  const GroundReport& g = *ground;
  const mapper::TerrainParams& t = params.terrain;
  return {{"grid",
           {{"origin", {g.origin.x(), g.origin.y()}},
            {"step", g.step},
            {"nx", g.nx},
            {"ny", g.ny},
            {"size", {g.step * double(g.nx), g.step * double(g.ny)}}}},
          {"cells", g.nx * g.ny},
          {"cells_with_points", g.cells_with_points},
          {"measured_cells", g.measured_cells},
          {"filled_cells", g.filled_cells},
          {"fill_above_support_max", g.fill_above_support_max},
          {"coverage", g.coverage},
          {"height_range", {g.lowest, g.highest}},
          {"raised_most", g.raised_most},
          {"lowered_under_keyframes", g.lowered},
          {"voxels", g.voxels},
          {"settings",
           {{"cell", t.cell},
            {"max_object", t.max_object},
            {"slope", t.slope},
            {"initial_threshold", t.initial_threshold},
            {"max_threshold", t.max_threshold},
            {"keyframe_clearance", t.keyframe_clearance},
            {"min_support", t.min_support}}}};
}

nlohmann::json matrixRows(const Eigen::Matrix3d& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) rows.push_back({m(r, 0), m(r, 1), m(r, 2)});
  return rows;
}

nlohmann::json alignmentJson(const mapper::Alignment& a, const std::map<std::string, std::size_t>& reference_dropped) {
  const auto& t = a.transform;
  nlohmann::json drift = nullptr;
  if (a.drift) {
    const auto& d = *a.drift;
    nlohmann::json anchors = nlohmann::json::array();
    for (std::size_t i = 0; i < d.anchors.size(); ++i) {
      const auto& p = d.anchors[i];
      const auto& c = d.translations[i];
      anchors.push_back({{"stamp", d.stamps[i]},
                         {"position", {p.x(), p.y(), p.z()}},
                         {"scale", d.scales[i]},
                         {"translation", {c.x(), c.y(), c.z()}}});
    }
    const auto [low, high] = std::minmax_element(d.scales.begin(), d.scales.end());
    drift = {{"half_window", d.half_window},
             {"holdout_rmse", d.holdout_rmse},
             {"scale_min", *low},
             {"scale_max", *high},
             {"anchors", anchors}};
  }
  return {{"model", a.drift ? "drift" : "similarity"},
          {"scale", t.scale},
          {"rotation", matrixRows(t.rotation)},
          {"translation", {t.translation.x(), t.translation.y(), t.translation.z()}},
          {"rmse", a.rmse},
          {"max_error", a.max_error},
          {"similarity_rmse", a.similarity_rmse},
          {"roll",
           {{"sigma_deg", a.roll_sigma * 180.0 / kPi},
            {"from", a.roll_from_cameras ? "cameras" : "reference"},
            {"turn_deg", a.roll_turn * 180.0 / kPi}}},
          {"matched", a.matched},
          {"unmatched", a.unmatched},
          {"reference_dropped", reference_dropped},
          {"drift", drift}};
}

}  // namespace

nlohmann::json parametersJson(const BuildParams& params) {
  using nlohmann::json;
  const auto numbers = [](std::initializer_list<double> values) {
    std::string text;
    for (double v : values) {
      char buffer[32];
      text += (text.empty() ? "" : ",") + std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
    }
    return text;
  };
  json origin = nullptr;
  if (params.origin) origin = numbers({params.origin->x(), params.origin->y(), params.origin->z()});
  json crop = nullptr;
  if (params.filters.crop) {
    const auto& box = *params.filters.crop;
    crop = numbers({box.min.x(), box.min.y(), box.min.z(), box.max.x(), box.max.y(), box.max.z()});
  }
  return {
      {"inputs", pathStrings(params.inputs)},
      {"trajectory", params.trajectory ? json(params.trajectory->string()) : json(nullptr)},
      {"origin", origin},
      {"up", upAxisText(params.frame.up)},
      {"scale", params.frame.scale},
      {"crop", crop},
      {"z_min", params.filters.z_min ? json(*params.filters.z_min) : json(nullptr)},
      {"z_max", params.filters.z_max ? json(*params.filters.z_max) : json(nullptr)},
      {"resolution", params.octree.resolution},
      {"hit", params.octree.sensor.hit},
      {"miss", params.octree.sensor.miss},
      {"clamp_min", params.octree.sensor.clamp_min},
      {"clamp_max", params.octree.sensor.clamp_max},
      {"occupancy_threshold", params.octree.sensor.occupancy_threshold},
      {"max_range", params.octree.max_range},
      {"align", params.align ? json(params.align->reference.string()) : json(nullptr)},
      {"align_format", params.align ? json(io::toString(params.align->format)) : json(nullptr)},
      {"align_tolerance", params.align ? json(params.align->params.stamp_tolerance) : json(nullptr)},
      {"align_model", params.align ? json(mapper::toString(params.align->params.model)) : json(nullptr)},
      {"floor", planeSettingJson(params.floor)},
      {"level", params.level == Level::kOn    ? "on"
                : params.level == Level::kOff ? "off"
                                              : "auto"},
      {"ceiling", planeSettingJson(params.ceiling)},
      {"eps", params.eps ? json(*params.eps) : json("auto")},
      {"min_pts", params.min_pts ? json(*params.min_pts) : json("auto")},
      {"metric", clustering::toString(params.metric)},
      {"concavity", !params.convex_parts                   ? json("none")
                    : params.convex_parts->concavity > 0.0 ? json(params.convex_parts->concavity)
                                                           : json("default")},
      {"flat_gap",
       !params.convex_parts || !params.convex_parts->flat_gap ? json("auto") : json(*params.convex_parts->flat_gap)},
      {"extension", !params.extension   ? "auto"
                    : *params.extension ? "on"
                                        : "off"},
      {"stray_parts", params.stray_part_voxels},
      {"sparse_edges", params.sparse_edges},
      {"ot", params.write_ot},
  };
}

namespace {

// report.json's "clustering": the DBSCAN parameters used, how they were chosen, and what the
// extension, outlier trim and coplanar merge did.
nlohmann::json clusteringJson(const ClusterParamsReport& cp) {
  using nlohmann::json;
  json clustering_params = {
      {"eps", cp.used.eps}, {"eps_auto", cp.eps_auto}, {"min_pts", cp.used.min_pts}, {"min_pts_auto", cp.min_pts_auto}};
  if (cp.chosen) {
    const auto& c = *cp.chosen;
    clustering_params["auto"] = {
        {"knn", std::isfinite(c.knn) ? json(c.knn) : json(nullptr)},
        {"eps_unclamped", std::isfinite(c.eps_unclamped) ? json(c.eps_unclamped) : json(nullptr)},
        {"sampled", c.sampled},
        {"structured", c.structured},
        {"eps", c.eps},
        {"min_pts", c.min_pts}};
  }
  clustering_params["extension"] = nullptr;
  if (cp.extension_params) {
    clustering_params["extension"] = {{"min_pts", cp.extension_params->min_pts},
                                      {"reach", cp.extension_params->reach},
                                      {"joined", cp.extension.joined},
                                      {"rounds", cp.extension.rounds}};
  }
  clustering_params["outlier_trim"] = nullptr;
  if (cp.trim_params)
    clustering_params["outlier_trim"] = {
        {"radius", cp.trim_params->radius}, {"reach", cp.trim_params->reach}, {"dropped", cp.trim.dropped}};
  clustering_params["coplanar_merge"] = nullptr;
  if (cp.coplanar_params) {
    clustering_params["coplanar_merge"] = {{"reach", cp.coplanar_params->reach},
                                           {"thickness", cp.coplanar_params->thickness},
                                           {"merged", cp.coplanar.merged},
                                           {"points", cp.coplanar.points}};
  }
  return clustering_params;
}

// report.json's "parts": the convex parts' figures; null without convex parts.
nlohmann::json partsJson(const BuildResult& result) {
  using nlohmann::json;
  const BuildReport& report = result.report;
  if (!report.parts) return nullptr;
  const auto& p = *report.parts;
  std::size_t split = 0, largest = 0;
  for (const auto& o : result.obstacles) {
    split += o.parts.size() > 1;
    largest = std::max(largest, o.parts.size());
  }
  return {{"count", p.parts},
          {"concavity", p.concavity},
          {"flat_gap", p.flat_gap},
          {"flat_gap_max", p.flat_gap_max},
          {"flat_parts", p.flat_parts},
          {"face_parts", p.face_parts},
          {"per_obstacle", result.obstacles.empty() ? 0.0 : double(p.parts) / double(result.obstacles.size())},
          {"obstacles_split", split},
          {"most_parts_of_one_obstacle", largest},
          {"hull_volume_before", p.hull_volume_before},
          {"hull_volume_after", p.hull_volume_after},
          {"voxel_volume", p.voxel_volume},
          {"free_voxels_inside", p.free_voxels_inside},
          {"free_voxels_off_surface", p.free_voxels_off_surface},
          {"stray_parts", p.stray_parts},
          {"stray_voxels", p.stray_voxels.size()},
          {"sparse_edge_parts", p.sparse_edge_parts},
          {"sparse_edge_growth_max", p.sparse_edge_growth_max},
          {"keyframes_inside_hulls", report.keyframes_inside_hulls},
          {"camera_voxels", report.camera_voxels}};
}

// A finished octree is read as it is: its parameters are what it holds, not ones that were not applied.
void octreeParameters(const octomap::OcTree& tree, double resolution, nlohmann::json& parameters) {
  for (const char* key : {"trajectory", "origin", "up", "scale", "crop", "z_min", "z_max", "max_range", "level"})
    parameters[key] = nullptr;
  parameters["resolution"] = resolution;
  parameters["hit"] = tree.getProbHit();
  parameters["miss"] = tree.getProbMiss();
  parameters["clamp_min"] = tree.getClampingThresMin();
  parameters["clamp_max"] = tree.getClampingThresMax();
  parameters["occupancy_threshold"] = tree.getOccupancyThres();
}

}  // namespace

nlohmann::json reportJson(const BuildResult& result, const ParameterSpelling& spell) {
  using nlohmann::json;
  const BuildReport& report = result.report;
  json warnings = json::array();
  for (const Warning& w : report.warnings) warnings.push_back(warningText(w, spell));
  json inputs = json::array();
  for (const auto& in : report.inputs) {
    inputs.push_back(
        {{"path", in.path}, {"format", in.format}, {"points_read", in.read}, {"points_dropped", in.dropped}});
  }
  json timings = json::object();
  double total = 0.0;
  for (const auto& [stage, ms] : report.timings_ms) {
    timings[stage] = ms;
    total += ms;
  }
  timings["total"] = total;
  json peak = json::object();
  for (const auto& [stage, mb] : report.peak_rss_mb) peak[stage] = mb;
  const auto info = mapper::describe(result.map.tree());
  std::vector<std::size_t> largest(result.clusters.cluster_sizes);
  std::sort(largest.rbegin(), largest.rend());
  if (largest.size() > 10) largest.resize(10);
  std::size_t core = 0;
  for (auto c : result.clusters.core) core += c;

  json parameters = parametersJson(result.params);
  const ClusterParamsReport& cp = report.cluster_params;
  parameters["eps"] = cp.used.eps;
  parameters["min_pts"] = cp.used.min_pts;
  parameters["eps_auto"] = cp.eps_auto;
  parameters["min_pts_auto"] = cp.min_pts_auto;
  if (readsOctree(result.params)) octreeParameters(result.map.tree(), info.resolution, parameters);
  const json clustering_params = clusteringJson(cp);
  const json parts = partsJson(result);
  return {
      {"hullmap_version", HULLMAP_VERSION},
      {"frame", outputFrame(result)},
      {"parameters", parameters},
      {"warnings", warnings},
      {"inputs", inputs},
      {"points", {{"read", report.points.read}, {"dropped", report.points.dropped}, {"used", report.points.used}}},
      {"keyframes", report.keyframes},
      {"alignment", report.alignment ? alignmentJson(*report.alignment, report.reference_dropped) : json(nullptr)},
      {"floor", readsOctree(result.params) ? json(nullptr) : planeReportJson(report.floor)},
      {"ceiling", readsOctree(result.params) ? json(nullptr) : planeReportJson(report.ceiling)},
      {"ground", groundJson(result.params, report.ground)},
      {"resolution", report.resolution ? json{{"given", report.resolution->given},
                                              {"spacing", report.resolution->spacing ? json(*report.resolution->spacing)
                                                                                     : json(nullptr)},
                                              {"used", report.resolution->used},
                                              {"adapted", report.resolution->used != report.resolution->given}}
                                       : json(nullptr)},
      {"levelling",
       {{"rotation", matrixRows(report.levelling.linear())},
        {"translation",
         {report.levelling.translation().x(), report.levelling.translation().y(),
          report.levelling.translation().z()}}}},
      {"input_to_output", similarityJson(report.input_to_output, inputToOutputExact(report))},
      {"octree",
       {{"resolution", info.resolution},
        {"bounds",
         {{"min", {info.min.x(), info.min.y(), info.min.z()}}, {"max", {info.max.x(), info.max.y(), info.max.z()}}}},
        {"occupied_leaves", info.occupied_leaves},
        {"free_leaves", info.free_leaves},
        {"nodes", info.nodes},
        {"memory_bytes", info.memory_bytes},
        {"occupied_voxels", result.voxels.size()}}},
      {"clusters",
       {{"count", result.clusters.cluster_sizes.size()},
        {"noise_voxels", result.clusters.noise},
        {"core_voxels", core},
        {"largest_voxel_counts", largest}}},
      {"clustering", clustering_params},
      {"obstacles", result.obstacles.size()},
      {"parts", parts},
      {"timings_ms", timings},
      {"peak_rss_mb", peak},
  };
}

nlohmann::json readReport(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot open (is this a hullmap build directory?)");
  nlohmann::json report;
  try {
    in >> report;
  } catch (const nlohmann::json::exception& e) {
    throw Error(path.string() + ": not valid JSON: " + e.what());
  }
  const auto params = report.find("parameters");
  if (params == report.end() || !params->is_object()) throw Error(path.string() + ": no \"parameters\" object");
  const auto resolution = params->find("resolution");
  if (resolution == params->end() || !resolution->is_number() || !(resolution->get<double>() > 0.0)) {
    throw Error(path.string() + ": parameters.resolution missing or not a positive number");
  }
  return report;
}

}  // namespace hullmap::pipeline
