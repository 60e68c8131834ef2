#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/planning/roadmap_json.hpp"
#include "hullmap/sim/ground_truth.hpp"
#include "hullmap/view/html_view.hpp"
#include "option_checks.hpp"
#include "path_file.hpp"

namespace hullmap::cli {
namespace {

namespace fs = std::filesystem;

struct ViewOptions {
  std::string dir;
  std::string output;
  std::vector<std::string> path_files;
  double radius = 0.0;
  std::string roadmap;
  std::string truth;
  std::string three_dir = view::kThreeDir;
  std::size_t max_instances = view::kDefaultMaxInstances;
};

// OUT.html beside the build directory: a file inside it would make the next `hullmap build -o OUT`
// refuse to replace the directory (it would hold a file hullmap did not write).
std::string defaultOutput(const std::string& dir) {
  fs::path p = fs::path(dir).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  if (p.empty() || p == "." || p == "..") p = fs::absolute(dir).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  return p.string() + ".html";
}

bool endsInHtml(const std::string& name) {
  std::string ext = fs::path(name).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".html" || ext == ".htm";
}

void runView(const ViewOptions& o) {
  if (!fs::is_directory(o.dir)) throw Error("view: " + o.dir + " is not a directory (a `hullmap build` output)");
  const std::string output = o.output.empty() ? defaultOutput(o.dir) : o.output;
  if (!endsInHtml(output)) throw Error("-o " + output + ": the page is HTML: give a name ending in .html");
  const fs::path parent = fs::absolute(output).parent_path();
  if (!fs::is_directory(parent)) throw Error("-o " + output + ": its directory " + parent.string() + " does not exist");

  view::ViewInputs inputs;
  if (!o.path_files.empty()) {
    checkRadius(o.radius);
    inputs.radius = o.radius;
    for (const auto& file : o.path_files)
      inputs.paths.push_back({fs::path(file).filename().string(), readPlainOrTimedPathFile(file)});
  }
  if (!o.roadmap.empty()) {
    const planning::Roadmap roadmap = planning::readRoadmapJson(o.roadmap);
    view::ViewRoadmap drawn;
    drawn.name = fs::path(o.roadmap).filename().string();
    for (const auto& n : roadmap.nodes) drawn.nodes.push_back(n.position);
    for (const auto& e : roadmap.edges) {
      drawn.edges.push_back(e.polyline);
      drawn.clearance.push_back(e.clearance);
    }
    // The middle of its flight band, when it has one.
    const double middle = (roadmap.z0 + roadmap.z1) / 2;
    drawn.z = std::isfinite(middle) && std::abs(middle) < 1e6 ? middle : 0.0;
    inputs.roadmap = std::move(drawn);
  }
  if (!o.truth.empty()) {
    inputs.truth = sim::readGroundTruth(o.truth);
    inputs.truth_name = fs::path(o.truth).filename().string();
  }
  view::ViewParams params;
  params.three_dir = o.three_dir;
  params.max_instances = o.max_instances;
  const view::ViewScene scene = view::readScene(o.dir, std::move(inputs));
  const view::ViewPage page = view::writePage(scene, output, params);

  std::cout << "view: " << page.voxels << " voxels, " << page.instances;
  if (page.merge_factor > 1) {
    std::cout << " cells of " << scene.resolution * page.merge_factor << " (" << page.merge_factor
              << " voxels a side: more than --max-instances " << o.max_instances << ") at the finest level";
  } else {
    std::cout << " cubes at the finest level";
  }
  if (page.levels.size() > 1) {
    std::cout << " (coarser: ";
    for (std::size_t k = 1; k < page.levels.size(); ++k) std::cout << (k > 1 ? ", " : "") << page.levels[k];
    std::cout << ")";
  }
  std::cout << ", " << scene.obstacles.size() << " obstacles in " << page.hulls << " hulls";
  if (!scene.keyframes.empty()) std::cout << ", " << scene.keyframes.size() << " keyframes";
  if (scene.roadmap) std::cout << ", roadmap of " << scene.roadmap->edges.size() << " edges";
  if (scene.truth) std::cout << ", " << scene.truth->shapes.size() << " true shapes";
  if (!scene.paths.empty()) {
    std::cout << ", " << scene.paths.size() << " path" << (scene.paths.size() > 1 ? "s" : "") << " ("
              << page.colliding_paths << " colliding)";
  }
  char size[32];
  std::snprintf(size, sizeof size, "%.1f MB", static_cast<double>(page.html.size()) / 1e6);
  std::cout << "\nwrote " << output << " (" << size << ")\n";
  for (const auto& p : scene.paths) {
    if (!p.check.first_colliding_segment) continue;
    std::cout << (scene.paths.size() > 1 ? p.path.name + ": " : std::string())
              << "path collides: first contact on segment " << *p.check.first_colliding_segment << "\n";
  }
}

}  // namespace

void addViewCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<ViewOptions>();
  auto* cmd = app.add_subcommand(
      "view",
      "Write a build directory as one self-contained HTML page that draws it in 3D (three.js from Debian's "
      "libjs-three, inlined): voxels, convex parts, floor, keyframes, checked paths, roadmap, ground truth");
  cmd->add_option("dir", options->dir, "Directory written by `hullmap build`")->required();
  cmd->add_option("-o,--output", options->output, "Page to write, ending in .html (default: DIR.html, beside DIR)");
  auto* path = cmd->add_option("--path", options->path_files,
                               "Path to check against the hulls and draw (repeat for several drones): a waypoint "
                               "\"x y z\" or \"t x y z\" (plan --robots) per line, map frame, at least two");
  cmd->add_option("--radius,-r", options->radius, "Drone radius for --path, map units")
      ->check(numberAbove(0, true))
      ->needs(path);
  path->needs(cmd->get_option("--radius"));
  cmd->add_option("--roadmap", options->roadmap, "roadmap.json (hullmap roadmap) to draw at its band's middle height");
  cmd->add_option("--truth", options->truth,
                  "Ground truth (JSON as maps/room/ground_truth.json, or OBJ) to draw as "
                  "wireframes");
  cmd->add_option("--three-dir", options->three_dir,
                  "Where three.js r111 is (three.min.js, examples/js/controls/OrbitControls.js)")
      ->capture_default_str();
  cmd->add_option("--max-instances", options->max_instances,
                  "Most voxel cubes the page holds at its finest detail; more voxels are merged into coarser cells")
      ->check(wholeNumberFrom(1))
      ->capture_default_str();
  cmd->callback([options, &status] {
    runView(*options);
    status = 0;
  });
}

}  // namespace hullmap::cli
