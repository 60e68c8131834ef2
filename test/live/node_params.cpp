// hullmap::live's node parameters: the table's defaults are `hullmap build`'s, each parameter lands in
// its field, and the ranges the table states (what ROS 2 declares) are the ones readSettings checks.
#include <cmath>
#include <functional>
#include <limits>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/live/node_params.hpp"
#include "hullmap/pipeline/report.hpp"

namespace hullmap::live {
namespace {

std::string errorOf(const ParameterValues& values, Checking checking, const std::string& prefix = "") {
  try {
    readSettings(values, checking, prefix);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(LiveNodeParams, EveryDefaultIsReadBackAsTheDefaults) {
  ParameterValues defaults;
  std::set<std::string> names;
  for (const auto& spec : nodeParameters()) {
    EXPECT_TRUE(names.insert(spec.name).second) << spec.name << " twice";
    EXPECT_FALSE(spec.description.empty()) << spec.name;
    EXPECT_FALSE(spec.constraints.empty()) << spec.name;
    defaults[spec.name] = spec.default_value;
  }
  const NodeSettings given = readSettings(defaults, Checking::kStrict);
  const NodeSettings none = readSettings({}, Checking::kStrict);
  const NodeSettings plain;
  for (const NodeSettings* s : {&given, &none}) {
    EXPECT_EQ(pipeline::parametersJson(s->build), pipeline::parametersJson(plain.build));
    EXPECT_EQ(s->build.extension, plain.build.extension);
    EXPECT_EQ(s->node.frame_id, plain.node.frame_id);
    EXPECT_EQ(s->node.min_interval, plain.node.min_interval);
    EXPECT_EQ(s->node.output_dir, plain.node.output_dir);
    EXPECT_EQ(s->node.radius, plain.node.radius);
    EXPECT_EQ(s->node.occupancy_min_z, plain.node.occupancy_min_z);
    EXPECT_EQ(s->node.occupancy_max_z, plain.node.occupancy_max_z);
  }
  EXPECT_EQ(findParameter("frame_id")->live, false);  // the one set at start only
}

TEST(LiveNodeParams, EachNumberLandsInItsField) {
  using Field = std::function<double(const NodeSettings&)>;
  const std::vector<std::tuple<std::string, ParameterValue, Field>> cases{
      {"resolution", 0.1, [](const NodeSettings& s) { return s.build.octree.resolution; }},
      {"max_range", 4.0, [](const NodeSettings& s) { return s.build.octree.max_range; }},
      {"hit", 0.8, [](const NodeSettings& s) { return s.build.octree.sensor.hit; }},
      {"miss", 0.3, [](const NodeSettings& s) { return s.build.octree.sensor.miss; }},
      {"clamp_min", 0.2, [](const NodeSettings& s) { return s.build.octree.sensor.clamp_min; }},
      {"clamp_max", 0.9, [](const NodeSettings& s) { return s.build.octree.sensor.clamp_max; }},
      {"occupancy_threshold", 0.6, [](const NodeSettings& s) { return s.build.octree.sensor.occupancy_threshold; }},
      {"scale", 2.5, [](const NodeSettings& s) { return s.build.frame.scale; }},
      {"eps", 0.12, [](const NodeSettings& s) { return *s.build.eps; }},
      {"eps", std::string("0.125"), [](const NodeSettings& s) { return *s.build.eps; }},
      {"min_pts", std::int64_t{7}, [](const NodeSettings& s) { return double(*s.build.min_pts); }},
      {"min_pts", 7.0, [](const NodeSettings& s) { return double(*s.build.min_pts); }},
      {"concavity", 0.3, [](const NodeSettings& s) { return s.build.convex_parts->concavity; }},
      {"flat_gap", 0.0, [](const NodeSettings& s) { return *s.build.convex_parts->flat_gap; }},
      {"stray_parts", std::int64_t{0}, [](const NodeSettings& s) { return double(s.build.stray_part_voxels); }},
      {"stray_parts", 5.0, [](const NodeSettings& s) { return double(s.build.stray_part_voxels); }},
      {"floor", 0.5, [](const NodeSettings& s) { return s.build.floor.height; }},
      {"ceiling", std::int64_t{3}, [](const NodeSettings& s) { return s.build.ceiling.height; }},
      {"z_min", -1.0, [](const NodeSettings& s) { return *s.build.filters.z_min; }},
      {"z_max", 2.0, [](const NodeSettings& s) { return *s.build.filters.z_max; }},
      {"min_interval", 0.5, [](const NodeSettings& s) { return s.node.min_interval; }},
      {"radius", std::int64_t{1}, [](const NodeSettings& s) { return s.node.radius; }},
      {"occupancy_min_z", 0.2, [](const NodeSettings& s) { return s.node.occupancy_min_z; }},
      {"occupancy_max_z", 1.8, [](const NodeSettings& s) { return s.node.occupancy_max_z; }},
  };
  const NodeSettings defaults;
  for (const auto& [name, value, field] : cases) {
    for (const Checking checking : {Checking::kParse, Checking::kStrict}) {
      const NodeSettings s = readSettings({{name, value}}, checking);
      double expected = 0.0;
      if (const auto* d = std::get_if<double>(&value)) expected = *d;
      if (const auto* i = std::get_if<std::int64_t>(&value)) expected = double(*i);
      if (const auto* t = std::get_if<std::string>(&value)) expected = std::stod(*t);
      EXPECT_EQ(field(s), expected) << name;
    }
  }
  const NodeSettings words = readSettings({{"floor", std::string("none")},
                                           {"ceiling", std::string("auto")},
                                           {"concavity", std::string("none")},
                                           {"extension", std::string("off")},
                                           {"sparse_edges", std::string("off")},
                                           {"metric", std::string("xy")},
                                           {"up", std::string("-y")},
                                           {"z_min", std::string("none")},
                                           {"frame_id", std::string("world")},
                                           {"output_dir", std::string("saved")}},
                                          Checking::kStrict);
  EXPECT_EQ(words.build.floor.mode, mapper::PlaneSetting::Mode::kNone);
  EXPECT_EQ(words.build.ceiling.mode, mapper::PlaneSetting::Mode::kAuto);
  EXPECT_FALSE(words.build.convex_parts.has_value());
  EXPECT_EQ(words.build.extension, std::optional<bool>(false));
  EXPECT_FALSE(words.build.sparse_edges);
  EXPECT_TRUE(NodeSettings{}.build.sparse_edges);
  EXPECT_EQ(words.build.metric, clustering::Metric::kXy);
  EXPECT_EQ(words.build.frame.up, mapper::UpAxis::kNegY);
  EXPECT_FALSE(words.build.filters.z_min.has_value());
  EXPECT_EQ(words.node.frame_id, "world");
  EXPECT_EQ(words.node.output_dir, "saved");
  // ROS 2's YAML reads `extension: off` as false.
  EXPECT_EQ(readSettings({{"extension", false}}, Checking::kStrict).build.extension, std::optional<bool>(false));
  EXPECT_EQ(readSettings({{"extension", true}}, Checking::kStrict).build.extension, std::optional<bool>(true));
  EXPECT_FALSE(readSettings({{"sparse_edges", false}}, Checking::kStrict).build.sparse_edges);
}

TEST(LiveNodeParams, TheTablesRangesAreWhatStrictReadingChecks) {
  // Every number parameter with a bound: the bound itself passes unless open, a step beyond fails,
  // both named by the parameter.
  for (const auto& spec : nodeParameters()) {
    for (const auto& [bound, open, direction] :
         {std::tuple{spec.min, spec.min_open, -1.0}, std::tuple{spec.max, spec.max_open, 1.0}}) {
      if (!std::isfinite(bound)) continue;
      const double beyond = bound + direction * std::max(1e-6, std::abs(bound) * 1e-6);
      ParameterValues at{{spec.name, bound}}, past{{spec.name, beyond}};
      if (spec.name == "clamp_min" || spec.name == "clamp_max") continue;  // checked against each other below
      const std::string at_error = errorOf(at, Checking::kStrict);
      if (open) {
        EXPECT_EQ(at_error.rfind(spec.name + ": ", 0), 0u) << spec.name << " at " << bound << ": " << at_error;
      } else {
        EXPECT_EQ(at_error, "") << spec.name << " at " << bound;
      }
      const std::string past_error = errorOf(past, Checking::kStrict);
      EXPECT_EQ(past_error.rfind(spec.name + ": ", 0), 0u) << spec.name << " at " << beyond << ": " << past_error;
    }
  }
  EXPECT_EQ(errorOf({{"clamp_min", 0.9}, {"clamp_max", 0.8}}, Checking::kStrict).rfind("clamp_min: ", 0), 0u);
  EXPECT_EQ(errorOf({{"min_pts", 2.5}}, Checking::kStrict).rfind("min_pts: ", 0), 0u);
  // eps, concavity and flat_gap: at most kMaxEpsVoxels resolutions, the resolution as given.
  for (const std::string name : {"eps", "concavity", "flat_gap"}) {
    EXPECT_EQ(errorOf({{name, 0.05 * kMaxEpsVoxels}}, Checking::kStrict), "") << name;
    EXPECT_EQ(errorOf({{name, 0.05 * kMaxEpsVoxels * 1.001}}, Checking::kStrict).rfind(name + ": ", 0), 0u) << name;
    EXPECT_EQ(errorOf({{name, 1.5}, {"resolution", 0.1}}, Checking::kStrict), "") << name;
    EXPECT_EQ(errorOf({{name, 1000.0}}, Checking::kParse), "") << name;  // ROS 1: the build's numbers as given
  }
  EXPECT_EQ(
      errorOf({{"resolution", std::numeric_limits<double>::quiet_NaN()}}, Checking::kStrict).rfind("resolution: ", 0),
      0u);
  EXPECT_EQ(errorOf({{"occupancy_max_z", std::numeric_limits<double>::infinity()}}, Checking::kStrict), "");
}

TEST(LiveNodeParams, ParseCheckingLeavesTheBuildsNumbersToTheBuildAsTheRos1NodeDid) {
  // kParse (ROS 1): a build number the build refuses passes here and fails each rebuild; the node's
  // own numbers and every word are checked at once; errors carry the front end's prefix.
  EXPECT_EQ(errorOf({{"eps", 0.0}}, Checking::kParse), "");
  EXPECT_EQ(errorOf({{"resolution", -1.0}}, Checking::kParse), "");
  EXPECT_EQ(errorOf({{"eps", 0.0}}, Checking::kStrict).rfind("eps: ", 0), 0u);
  EXPECT_EQ(errorOf({{"resolution", -1.0}}, Checking::kStrict).rfind("resolution: ", 0), 0u);
  const std::vector<ParameterValues> bad{
      {{"min_interval", -1.0}},
      {{"radius", 0.0}},
      {{"eps", std::string("x")}},
      {{"min_pts", std::int64_t{0}}},
      {{"floor", std::string("up")}},
      {{"concavity", std::string("x")}},
      {{"flat_gap", -1.0}},
      {{"flat_gap", 0.2}, {"concavity", std::string("none")}},
      {{"extension", std::int64_t{1}}},
      {{"extension", std::string("Auto")}},
      {{"stray_parts", -1.0}},
      {{"stray_parts", 1.5}},
      {{"sparse_edges", std::string("auto")}},
      {{"sparse_edges", std::int64_t{1}}},
      {{"up", std::string("w")}},
      {{"metric", std::string("zz")}},
      {{"eps", true}},
  };
  for (const auto& values : bad) {
    for (const Checking checking : {Checking::kParse, Checking::kStrict}) {
      const std::string error = errorOf(values, checking, "~");
      const std::string name = values.count("flat_gap") ? "flat_gap" : values.begin()->first;
      EXPECT_EQ(error.rfind("~" + name + ": ", 0), 0u) << name << ": " << error;
    }
  }
  // Types: text where a number is due, and a number where text is due (strict only; ROS 1 never
  // hands them over).
  EXPECT_EQ(errorOf({{"radius", std::string("big")}}, Checking::kStrict), "radius: expected a number, got 'big'");
  EXPECT_EQ(errorOf({{"frame_id", 3.0}}, Checking::kStrict).rfind("frame_id: ", 0), 0u);
  EXPECT_EQ(errorOf({{"z_min", std::string("low")}}, Checking::kStrict).rfind("z_min: ", 0), 0u);
}

TEST(LiveNodeParams, ValueTextIsExact) {
  EXPECT_EQ(valueText(0.1), "0.10000000000000001");
  EXPECT_EQ(std::stod(valueText(0.1)), 0.1);
  EXPECT_EQ(valueText(std::int64_t{-3}), "-3");
  EXPECT_EQ(valueText(true), "true");
  EXPECT_EQ(valueText(std::string("auto")), "auto");
}

}  // namespace
}  // namespace hullmap::live
