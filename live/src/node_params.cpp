#include "hullmap/live/node_params.hpp"
#include "hullmap/pipeline/report.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "hullmap/core/constants.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::live {
namespace {

ParameterSpec number(std::string name, double fallback, std::string description, std::string constraints, double min,
                     double max, bool min_open = false, bool max_open = false) {
  ParameterSpec s;
  s.name = std::move(name);
  s.kind = ParameterKind::kNumber;
  s.default_value = fallback;
  s.description = std::move(description);
  s.constraints = std::move(constraints);
  s.min = min;
  s.max = max;
  s.min_open = min_open;
  s.max_open = max_open;
  return s;
}

ParameterSpec words(std::string name, ParameterKind kind, std::string fallback, std::vector<std::string> accepted,
                    std::string description, std::string constraints) {
  ParameterSpec s;
  s.name = std::move(name);
  s.kind = kind;
  s.default_value = std::move(fallback);
  s.words = std::move(accepted);
  s.description = std::move(description);
  s.constraints = std::move(constraints);
  return s;
}

std::vector<ParameterSpec> makeParameters() {
  const NodeSettings d;  // the defaults: BuildParams' (hullmap build's) and NodeParams'
  const auto& octree = d.build.octree;
  const std::string probability = "a probability in (0, 1)";
  std::vector<ParameterSpec> specs;
  specs.push_back(
      number("resolution", octree.resolution, "octree leaf size, map units", "from 0.0001 to 1000", 1e-4, 1e3));
  auto eps = words("eps", ParameterKind::kWordOrNumber, "auto", {"auto"},
                   "DBSCAN radius, map units; auto: chosen from the map",
                   "a number > 0 and at most " + std::to_string(kMaxEpsVoxels) + " times resolution, or auto");
  eps.min = 0.0;
  eps.min_open = true;
  specs.push_back(eps);
  auto min_pts =
      words("min_pts", ParameterKind::kWordOrNumber, "auto", {"auto"},
            "DBSCAN core threshold in map points; auto: chosen from the map", "a whole number >= 1, or auto");
  min_pts.min = 1.0;
  min_pts.max = 1e9;
  min_pts.whole = true;
  specs.push_back(min_pts);
  specs.push_back(words("floor", ParameterKind::kWordOrNumber, "auto", {"auto", "none"},
                        "the floor: auto (found), none, or its height in the map frame; an obstacle for path checks",
                        "auto, none, or a height"));
  specs.push_back(words("level", ParameterKind::kWord, "auto", {"auto", "on", "off"},
                        "level a found floor (rotate it level, move it to z = 0); auto: for a camera's frame only "
                        "(ORB-SLAM's map markers, up other than z)",
                        "auto, on or off"));
  specs.push_back(words("ceiling", ParameterKind::kWordOrNumber, "none", {"auto", "none"},
                        "the ceiling: none, auto, or its height in the map frame", "auto, none, or a height"));
  auto concavity =
      words("concavity", ParameterKind::kWordOrNumber, "default", {"default", "none"},
            "convex parts no farther than this from their voxels, map units; default: 3 voxels; none: "
            "one hull per cluster",
            "a number > 0 and at most " + std::to_string(kMaxEpsVoxels) + " times resolution, default, or none");
  concavity.min = 0.0;
  concavity.min_open = true;
  specs.push_back(concavity);
  auto flat_gap = words(
      "flat_gap", ParameterKind::kWordOrNumber, "auto", {"auto"},
      "gap a flat convex part may span, map units; auto: the eps used; 0: off",
      "a number from 0 to " + std::to_string(kMaxEpsVoxels) + " times resolution, or auto; not with concavity none");
  flat_gap.min = 0.0;
  specs.push_back(flat_gap);
  specs.push_back(words("extension", ParameterKind::kWord, "auto", {"auto", "on", "off"},
                        "the cluster extension after DBSCAN; auto: on when min_pts is auto", "auto, on or off"));
  auto strays = number("stray_parts", double(d.build.stray_part_voxels),
                       "with the extension: drop convex parts of at most this many voxels, at most one core, away "
                       "from the floor (stray map points); 0: keep every part",
                       "a whole number >= 0", 0.0, 1e9);
  strays.whole = true;
  specs.push_back(strays);
  specs.push_back(words("sparse_edges", ParameterKind::kWord, d.build.sparse_edges ? "on" : "off", {"on", "off"},
                        "grow each sparse convex part in its own plane to the edges its last map points stop short of",
                        "on or off"));
  specs.push_back(words("metric", ParameterKind::kText, clustering::toString(d.build.metric), {"xyz", "xy"},
                        "DBSCAN distance: xyz, or xy (top view)", "xyz or xy"));
  specs.push_back(words("up", ParameterKind::kText, pipeline::upAxisText(d.build.frame.up),
                        {"x", "-x", "y", "-y", "z", "-z"},
                        "the input axis that points up (ORB-SLAM's camera frame: -y)", "x, -x, y, -y, z or -z"));
  specs.push_back(
      number("scale", d.build.frame.scale, "input units to map units", "from 0.000001 to 1000000", 1e-6, 1e6));
  for (const auto& [bound, side] : {std::pair{"z_min", "below"}, std::pair{"z_max", "above"}}) {
    ParameterSpec s = number(bound, 0.0, std::string("drop points ") + side + " this height, map frame; none: keep all",
                             "a finite number, or none; z_min below z_max", -kInf, kInf, true, true);
    s.kind = ParameterKind::kOptionalNumber;
    s.default_value = std::string("none");
    s.words = {"none"};
    specs.push_back(s);
  }
  specs.push_back(number("hit", octree.sensor.hit, "octomap's P(hit)", probability, 0.0, 1.0, true, true));
  specs.push_back(number("miss", octree.sensor.miss, "octomap's P(miss)", probability, 0.0, 1.0, true, true));
  specs.push_back(number("clamp_min", octree.sensor.clamp_min, "octomap's lower clamping probability",
                         probability + ", below clamp_max", 0.0, 1.0, true, true));
  specs.push_back(number("clamp_max", octree.sensor.clamp_max, "octomap's upper clamping probability",
                         probability + ", above clamp_min", 0.0, 1.0, true, true));
  specs.push_back(number("occupancy_threshold", octree.sensor.occupancy_threshold, "octomap's occupancy threshold",
                         probability, 0.0, 1.0, true, true));
  specs.push_back(number("max_range", octree.max_range,
                         "bound on the rays free space is cast along, map units; < 0: unbounded", "a finite number",
                         -kInf, kInf, true, true));
  auto frame_id = words("frame_id", ParameterKind::kText, d.node.frame_id, {},
                        "frame of everything published (hullmap's z-up map frame)", "a frame name");
  frame_id.live = false;  // markers already shown in the old frame would stay there
  specs.push_back(frame_id);
  specs.push_back(number("min_interval", d.node.min_interval, "seconds between the starts of two rebuilds",
                         "from 0 to 3600", 0.0, 3600.0));
  specs.push_back(words("output_dir", ParameterKind::kText, d.node.output_dir, {},
                        "where save writes the map (as hullmap build -o); relative to the node's working directory",
                        "a directory"));
  specs.push_back(
      number("radius", d.node.radius, "drone radius for path checks, map units", "> 0 and <= 1000", 0.0, 1e3, true));
  specs.push_back(number("occupancy_min_z", d.node.occupancy_min_z,
                         "lower end of the projected map's height band, map frame", "a number (-inf: none)", -kInf,
                         kInf));
  specs.push_back(number("occupancy_max_z", d.node.occupancy_max_z,
                         "upper end of the projected map's height band, map frame", "a number (inf: none)", -kInf,
                         kInf));
  return specs;
}

/// Reads values by the rules of their specs; errors name prefix + the parameter.
class Reader {
 public:
  Reader(const ParameterValues& values, Checking checking, const std::string& prefix)
      : values_(values), strict_(checking == Checking::kStrict), prefix_(prefix) {}

  Error bad(const std::string& name, const std::string& detail) const {
    return Error::inParameter(prefix_ + name, detail);
  }

  const ParameterValue* given(const std::string& name) const {
    const auto it = values_.find(name);
    return it == values_.end() ? nullptr : &it->second;
  }

  /// A number parameter; under kStrict checked against its range.
  double number(const std::string& name, double fallback) const {
    const ParameterValue* v = given(name);
    if (!v) return fallback;
    double value = 0.0;
    if (const auto* d = std::get_if<double>(v)) {
      value = *d;
    } else if (const auto* i = std::get_if<std::int64_t>(v)) {
      value = double(*i);
    } else {
      throw bad(name, "expected a number, got '" + valueText(*v) + "'");
    }
    if (strict_) checkRange(name, value, valueText(*v));
    return value;
  }

  /// The text of a word or number parameter (a number as exact text), or `fallback`.
  std::string wordOrNumber(const std::string& name, const std::string& fallback) const {
    const ParameterValue* v = given(name);
    if (!v) return fallback;
    if (std::holds_alternative<bool>(*v)) throw bad(name, "expected a number or a word such as auto");
    return valueText(*v);
  }

  std::string text(const std::string& name, const std::string& fallback) const {
    const ParameterValue* v = given(name);
    if (!v) return fallback;
    if (const auto* s = std::get_if<std::string>(v)) return *s;
    if (strict_) throw bad(name, "expected text, got " + valueText(*v));
    return valueText(*v);
  }

  /// A number written as text (a word-or-number parameter's), checked as number() checks.
  double numberText(const std::string& name, const std::string& text) const {
    std::size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != text.size() || !std::isfinite(value)) throw bad(name, "expected a number, got '" + text + "'");
    if (strict_) checkRange(name, value, text);
    return value;
  }

  /// A length that the build's work grows with (in voxels: `value / resolution`): at most kMaxEpsVoxels.
  void checkVoxels(const std::string& name, double value, double resolution) const {
    const double most = kMaxEpsVoxels * resolution;
    if (value <= most) return;
    throw bad(name, "must be at most " + std::to_string(kMaxEpsVoxels) + " times resolution (" + valueText(most) +
                        " at resolution " + valueText(resolution) + "), got " + valueText(value) +
                        ": the rebuild's work grows with the cube of a length in voxels");
  }

  /// Rethrows a parser's hullmap::Error as about prefix + name.
  template <typename Parse>
  auto parsed(const std::string& name, const std::string& text, Parse&& parse) const {
    try {
      return parse(text);
    } catch (const Error& e) {
      throw bad(name, e.parameter().empty() ? std::string(e.what()) : e.detail());
    }
  }

 private:
  void checkRange(const std::string& name, double value, const std::string& text) const {
    const ParameterSpec* spec = findParameter(name);
    if (!spec) return;
    const bool below = value < spec->min || (spec->min_open && value == spec->min);
    const bool above = value > spec->max || (spec->max_open && value == spec->max);
    if (std::isnan(value) || below || above || (spec->whole && value != std::floor(value))) {
      throw bad(name, "expected " + spec->constraints + ", got " + text);
    }
  }

  const ParameterValues& values_;
  bool strict_;
  std::string prefix_;
};

}  // namespace

const std::vector<ParameterSpec>& nodeParameters() {
  static const std::vector<ParameterSpec> specs = makeParameters();
  return specs;
}

const ParameterSpec* findParameter(const std::string& name) {
  for (const auto& spec : nodeParameters()) {
    if (spec.name == name) return &spec;
  }
  return nullptr;
}

std::string valueText(const ParameterValue& value) {
  if (const auto* s = std::get_if<std::string>(&value)) return *s;
  if (const auto* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
  if (const auto* i = std::get_if<std::int64_t>(&value)) return std::to_string(*i);
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", std::get<double>(value));  // exact: read back by std::stod
  return text;
}

NodeSettings readSettings(const ParameterValues& values, Checking checking, const std::string& prefix) {
  const Reader r(values, checking, prefix);
  NodeSettings settings;
  pipeline::BuildParams& p = settings.build;  // `hullmap build`'s defaults
  p.octree.resolution = r.number("resolution", p.octree.resolution);
  // A live map grows from a few points: its resolution stays the parameter's, not its spacing's.
  p.adapt_resolution = false;
  p.octree.max_range = r.number("max_range", p.octree.max_range);
  p.octree.sensor.hit = r.number("hit", p.octree.sensor.hit);
  p.octree.sensor.miss = r.number("miss", p.octree.sensor.miss);
  p.octree.sensor.clamp_min = r.number("clamp_min", p.octree.sensor.clamp_min);
  p.octree.sensor.clamp_max = r.number("clamp_max", p.octree.sensor.clamp_max);
  p.octree.sensor.occupancy_threshold = r.number("occupancy_threshold", p.octree.sensor.occupancy_threshold);
  if (checking == Checking::kStrict && !(p.octree.sensor.clamp_min < p.octree.sensor.clamp_max)) {
    throw r.bad("clamp_min", "must be below clamp_max (" + valueText(p.octree.sensor.clamp_max) + "), got " +
                                 valueText(p.octree.sensor.clamp_min));
  }
  // eps and min_pts: a number, or "auto" (the default: chosen from the map, as hullmap build).
  const std::string eps = r.wordOrNumber("eps", "auto");
  if (eps != "auto") p.eps = r.numberText("eps", eps);
  if (checking == Checking::kStrict && p.eps) r.checkVoxels("eps", *p.eps, p.octree.resolution);
  const std::string min_pts = r.wordOrNumber("min_pts", "auto");
  if (min_pts != "auto") {
    std::size_t used = 0;
    double n = 0.0;
    try {
      n = std::stod(min_pts, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != min_pts.size() || !std::isfinite(n)) throw r.bad("min_pts", "expected a number, got '" + min_pts + "'");
    if (n != std::floor(n) || n < 1 || n > 1e9) throw r.bad("min_pts", "expected a whole number >= 1 or auto");
    p.min_pts = int(n);
  }
  // floor / ceiling: auto, none or a height; concavity: default, none or a length (map units).
  p.floor = mapper::parsePlaneSetting(prefix + "floor", r.wordOrNumber("floor", "auto"));
  p.ceiling = mapper::parsePlaneSetting(prefix + "ceiling", r.wordOrNumber("ceiling", "none"));
  // level: auto (a camera's frame: ORB-SLAM's map markers, or up other than z), on or off. ROS 2's
  // YAML reads on and off as true and false.
  const ParameterValue* level_value = r.given("level");
  const bool* level_bool = level_value ? std::get_if<bool>(level_value) : nullptr;
  const std::string level = level_bool ? (*level_bool ? "on" : "off") : r.wordOrNumber("level", "auto");
  if (level == "on" || level == "off") {
    p.level = level == "on" ? pipeline::Level::kOn : pipeline::Level::kOff;
  } else if (level != "auto") {
    throw r.bad("level", "expected auto, on or off, got '" + level + "'");
  }
  const std::string concavity = r.wordOrNumber("concavity", "default");
  if (concavity == "none") {
    p.convex_parts.reset();
  } else if (concavity != "default") {
    const double t = r.numberText("concavity", concavity);
    if (!(t > 0.0)) throw r.bad("concavity", "must be > 0, default or none");
    if (checking == Checking::kStrict) r.checkVoxels("concavity", t, p.octree.resolution);
    p.convex_parts->concavity = t;
  }
  // flat_gap: auto (the eps used), 0 (off) or a length; a number cannot apply without convex parts.
  const std::string flat_gap = r.wordOrNumber("flat_gap", "auto");
  if (flat_gap != "auto") {
    const double g = r.numberText("flat_gap", flat_gap);
    if (!(g >= 0.0)) throw r.bad("flat_gap", "must be >= 0 (0: off) or auto, got " + flat_gap);
    if (!p.convex_parts) {
      throw r.bad("flat_gap", "applies only to convex parts, and " + prefix +
                                  "concavity none makes one hull per cluster; leave it auto");
    }
    if (checking == Checking::kStrict) r.checkVoxels("flat_gap", g, p.octree.resolution);
    p.convex_parts->flat_gap = g;
  }
  // extension: auto (on when min_pts is auto), on or off, as `hullmap build --extension`. ROS 2's
  // YAML reads on and off as true and false (ROS 1 never hands a bool here).
  const ParameterValue* extension_value = r.given("extension");
  const bool* extension_bool = extension_value ? std::get_if<bool>(extension_value) : nullptr;
  const std::string extension = extension_bool ? (*extension_bool ? "on" : "off") : r.wordOrNumber("extension", "auto");
  if (extension == "on" || extension == "off") {
    p.extension = extension == "on";
  } else if (extension != "auto") {
    throw r.bad("extension", "expected auto, on or off, got '" + extension + "'");
  }
  // stray_parts: a whole number >= 0, checked here in either mode (a negative count has no size_t).
  const double strays = r.number("stray_parts", double(p.stray_part_voxels));
  if (!(strays >= 0.0 && strays <= 1e9) || strays != std::floor(strays))
    throw r.bad("stray_parts", "expected a whole number >= 0, got " + std::to_string(strays));
  p.stray_part_voxels = static_cast<std::size_t>(strays);
  // sparse_edges: on or off, as `hullmap build --sparse-edges` (ROS 2's YAML: true or false).
  const ParameterValue* edges_value = r.given("sparse_edges");
  const bool* edges_bool = edges_value ? std::get_if<bool>(edges_value) : nullptr;
  const std::string edges =
      edges_bool ? (*edges_bool ? "on" : "off") : r.wordOrNumber("sparse_edges", p.sparse_edges ? "on" : "off");
  if (edges != "on" && edges != "off") throw r.bad("sparse_edges", "expected on or off, got '" + edges + "'");
  p.sparse_edges = edges == "on";
  p.frame.up = r.parsed("up", r.text("up", pipeline::upAxisText(p.frame.up)), mapper::parseUpAxis);
  p.frame.scale = r.number("scale", p.frame.scale);
  p.metric = r.parsed("metric", r.text("metric", clustering::toString(p.metric)), clustering::parseMetric);
  for (auto [name, bound] : {std::pair{"z_min", &p.filters.z_min}, std::pair{"z_max", &p.filters.z_max}}) {
    const ParameterValue* v = r.given(name);
    if (!v) continue;
    if (const auto* s = std::get_if<std::string>(v); s && *s == "none") {
      bound->reset();
    } else {
      *bound = r.number(name, 0.0);
    }
  }

  if (checking == Checking::kStrict && p.filters.z_min && p.filters.z_max && !(*p.filters.z_min < *p.filters.z_max)) {
    throw r.bad("z_min",
                "must be below z_max (" + valueText(*p.filters.z_max) + "), got " + valueText(*p.filters.z_min));
  }

  NodeParams& n = settings.node;
  n.frame_id = r.text("frame_id", n.frame_id);
  n.min_interval = r.number("min_interval", n.min_interval);
  n.output_dir = r.text("output_dir", n.output_dir);
  n.radius = r.number("radius", n.radius);
  n.occupancy_min_z = r.number("occupancy_min_z", n.occupancy_min_z);
  n.occupancy_max_z = r.number("occupancy_max_z", n.occupancy_max_z);
  if (!(n.min_interval >= 0.0) || !std::isfinite(n.min_interval)) {
    throw r.bad("min_interval", "must be finite and >= 0 seconds, got " + std::to_string(n.min_interval));
  }
  if (!(n.radius > 0.0) || !std::isfinite(n.radius)) {
    throw r.bad("radius", "must be finite and > 0, got " + std::to_string(n.radius));
  }
  if (checking == Checking::kStrict && n.frame_id.empty()) throw r.bad("frame_id", "must not be empty");
  if (checking == Checking::kStrict && n.output_dir.empty()) throw r.bad("output_dir", "must not be empty");
  return settings;
}

std::string nodeParameterSpelling(std::string_view field, std::string_view value) {
  std::string out(field);
  if (!value.empty()) out.append(":=").append(value);
  return out;
}

}  // namespace hullmap::live
