#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "hullmap/collision/path_check.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/map_obstacles.hpp"
#include "hullmap/pipeline/path_checker.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/pipeline/report.hpp"
#include "hullmap/pipeline/trajectory_file.hpp"
#include "hullmap/pipeline/voxels_csv.hpp"
#include "hullmap/planning/roadmap_json.hpp"
#include "hullmap/plot/svg_plot.hpp"
#include "option_checks.hpp"
#include "path_file.hpp"

namespace hullmap::cli {
namespace {

namespace fs = std::filesystem;

struct PlotOptions {
  std::string dir;
  std::string output;
  std::vector<std::string> path_files;
  std::string roadmap;
  double radius = 0.0;
  bool side = false;
  bool png = false;
};

std::string scalarText(const nlohmann::json& value) {
  if (value.is_string()) return value.get<std::string>();
  return value.dump();
}

// The build's parameters for the caption, and the voxel size.
void readReport(const std::string& path, plot::MapPlot& plot) {
  const nlohmann::json report = pipeline::readReport(path);
  const auto params = report.find("parameters");
  const auto resolution = params->find("resolution");
  plot.voxel_size = resolution->get<double>();
  std::string line;
  const auto add = [&](const char* key, const char* name) {
    const auto it = params->find(key);
    if (it == params->end() || it->is_null() || it->is_object() || it->is_array()) return;
    line += (line.empty() ? "" : ", ") + std::string(name) + " = " + scalarText(*it);
  };
  add("eps", "eps");
  add("min_pts", "minPts");
  add("metric", "metric");
  add("resolution", "resolution");
  if (!line.empty()) plot.caption.push_back(line);
  const auto frame = report.find("frame");
  if (frame != report.end() && !frame->is_null()) plot.caption.push_back("frame: " + scalarText(*frame));
  // The ground's height field: its voxels are drawn as the floor's, its coverage captioned.
  plot.floor_label = pipeline::kFloorLabel;
  const auto ground = report.find("ground");
  if (ground != report.end() && ground->is_object()) {
    plot.floor_label = pipeline::kGroundLabel;
    const auto& grid = ground->at("grid");
    std::ostringstream text;
    text << "ground: " << grid.at("nx").get<std::size_t>() << " x " << grid.at("ny").get<std::size_t>() << " cells of "
         << grid.at("step").get<double>() << ", " << std::fixed << std::setprecision(0)
         << 100.0 * ground->at("coverage").get<double>() << " % measured, " << ground->at("voxels").get<std::size_t>()
         << " voxels";
    plot.caption.push_back(text.str());
  }
}

void runPlot(const PlotOptions& o) {
  if (!fs::is_directory(o.dir)) throw Error("plot: " + o.dir + " is not a directory");
  const auto converter = plot::findPngConverter();
  const plot::PictureOutput output{o.output, o.png, "-o"};
  plot::checkPictureOutput(output, converter);
  plot::MapPlot plot;
  plot.view = o.side ? plot::PlotView::kSide : plot::PlotView::kTop;
  readReport((fs::path(o.dir) / "report.json").string(), plot);
  for (const auto& row : pipeline::readVoxelsCsv(fs::path(o.dir) / "voxels.csv")) {
    plot.centers.push_back(row.center);
    plot.labels.push_back(row.label);
  }
  const pipeline::MapObstacles map = pipeline::readMapObstacles(fs::path(o.dir) / "obstacles.json");
  plot.obstacles = map.obstacles;
  if (const auto keyframes = pipeline::readBuildTrajectory(o.dir))
    for (const auto& k : *keyframes) plot.keyframes.push_back(k.position);
  if (!o.roadmap.empty()) {
    const planning::Roadmap roadmap = planning::readRoadmapJson(o.roadmap);
    plot::PlotRoadmap drawn;
    for (const auto& n : roadmap.nodes) drawn.nodes.push_back(n.position);
    for (const auto& e : roadmap.edges) {
      drawn.edges.push_back(e.polyline);
      drawn.clearance.push_back(e.clearance);
    }
    plot.roadmap = std::move(drawn);
  }
  if (!o.path_files.empty()) {
    checkRadius(o.radius);
    const collision::HullChecker checker = pipeline::pathChecker(map);
    for (const auto& file : o.path_files) {
      plot::PlotPath path;
      path.name = fs::path(file).filename().string();
      path.waypoints = readPlainOrTimedPathFile(file);
      path.radius = o.radius;
      path.check = checker.checkPath(path.waypoints, o.radius);
      plot.paths.push_back(std::move(path));
    }
  }
  const plot::SvgPicture picture = plot::renderMapSvg(plot);
  const auto written = plot::writePicture(picture.svg, output, converter);
  std::cout << "plot: " << (o.side ? "side view (x-z)" : "top view (x-y)") << ", " << plot.centers.size()
            << " voxels drawn as " << picture.cells << " cells, " << plot.obstacles.size() << " obstacles";
  if (picture.hidden_voxels > 0) std::cout << ", " << picture.hidden_voxels << " far noise voxels not drawn";
  if (!plot.keyframes.empty()) std::cout << ", " << plot.keyframes.size() << " keyframes";
  if (plot.roadmap) std::cout << ", roadmap of " << plot.roadmap->edges.size() << " edges";
  if (!plot.paths.empty()) std::cout << ", " << plot.paths.size() << " path" << (plot.paths.size() > 1 ? "s" : "");
  std::cout << "\n";
  for (const auto& file : written) {
    std::cout << "wrote " << file;
    if (fs::path(file).extension() == ".png" || fs::path(file).extension() == ".PNG") {
      std::cout << " (rendered by " << *converter << ", Debian package " << plot::kPngConverterPackage << ")";
    }
    std::cout << "\n";
  }
  for (const auto& path : plot.paths) {
    if (!path.check.first_colliding_segment) continue;
    std::cout << (plot.paths.size() > 1 ? path.name + ": " : std::string())
              << "path collides: first contact on segment " << *path.check.first_colliding_segment << "\n";
  }
}

}  // namespace

void addPlotCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<PlotOptions>();
  auto* cmd = app.add_subcommand(
      "plot", "Draw a build directory as SVG (or PNG): voxels by cluster, noise black, obstacles numbered");
  cmd->add_option("dir", options->dir,
                  "Directory written by `hullmap build` (voxels.csv, report.json, "
                  "obstacles.json)")
      ->required();
  cmd->add_option("-o,--output", options->output, "Picture to write: .svg, or .png (rendered by rsvg-convert)")
      ->required();
  cmd->add_flag("--side", options->side, "Side view (x-z, seen from -y) instead of the top view (x-y)");
  auto* path = cmd->add_option("--path", options->path_files,
                               "Path to check and draw, one colour each (repeat for several drones): a waypoint "
                               "\"x y z\" or \"t x y z\" (plan --robots) per line, map frame, at least two");
  cmd->add_option("--roadmap", options->roadmap, "roadmap.json (hullmap roadmap) to draw under the paths, top view");
  cmd->add_option("--radius,-r", options->radius, "Drone radius for --path, map units")
      ->check(numberAbove(0, true))
      ->needs(path);
  path->needs(cmd->get_option("--radius"));
  cmd->add_flag("--png", options->png, "Also write a PNG beside the SVG (needs rsvg-convert, librsvg2-bin)");
  cmd->callback([options, &status] {
    runPlot(*options);
    status = 0;
  });
}

}  // namespace hullmap::cli
