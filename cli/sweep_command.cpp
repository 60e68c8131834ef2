#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/frame.hpp"
#include "hullmap/pipeline/output_dir.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/plot/svg_plot.hpp"
#include "option_checks.hpp"

namespace hullmap::cli {
namespace {

struct SweepOptions {
  std::vector<std::string> inputs;
  std::string eps_list = "0.05,0.1,0.13,0.3";
  std::string min_pts_list = "2,5,10,15,35";
  std::string metric = "xyz";
  std::string up = "z";
  double scale = 1.0;
  std::string output;
  std::string plot;  ///< small multiples, one panel per (eps, min_pts): .svg or .png
};

/// Every option of `hullmap sweep`, in one place (new options, e.g. a plot, go here).
void addSweepOptions(CLI::App& cmd, SweepOptions& o) {
  cmd.add_option("inputs", o.inputs, "Point files (ORB-SLAM dumps, text/xyz, PCD, PLY), unioned in order")->required();
  cmd.add_option("--eps", o.eps_list, "Comma-separated eps values, map units")->capture_default_str();
  cmd.add_option("--min-pts", o.min_pts_list, "Comma-separated min-pts values")->capture_default_str();
  cmd.add_option("--metric", o.metric, "xyz (3D distance) or xy (distance in the ground plane)")->capture_default_str();
  cmd.add_option("--up", o.up, "Input axis that points up: x, -x, y, -y, z, -z (ORB-SLAM: -y)")->capture_default_str();
  cmd.add_option("--scale", o.scale, "Scale applied to the input before the frame change")
      ->check(numberAbove(0))
      ->capture_default_str();
  cmd.add_option("-o,--output", o.output,
                 "CSV: eps,min_pts,clusters,noise,largest, one row per pair; - for standard output");
  cmd.add_option("--plot", o.plot,
                 "Picture, one top view per pair (clusters in colours, noise black): .svg, "
                 "or .png rendered by rsvg-convert (librsvg2-bin)");
}

/// The comma-separated items of `text` for `option`, each parsed whole by `parse`.
template <typename T, typename Parse>
std::vector<T> parseList(const std::string& option, const std::string& text, Parse parse) {
  std::vector<T> values;
  std::stringstream items(text);
  std::string item;
  while (std::getline(items, item, ',')) {
    const auto first = item.find_first_not_of(" \t");
    const auto last = item.find_last_not_of(" \t");
    const std::string trimmed = first == std::string::npos ? "" : item.substr(first, last - first + 1);
    std::size_t used = 0;
    T value{};
    try {
      value = parse(trimmed, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (trimmed.empty() || used != trimmed.size()) {
      throw Error(option + ": cannot parse '" + trimmed + "' in list '" + text + "'");
    }
    values.push_back(value);
  }
  if (values.empty() || (!text.empty() && text.back() == ',')) {
    throw Error(option + ": expected a comma-separated list, got '" + text + "'");
  }
  return values;
}

std::vector<double> parseEpsList(const std::string& text) {
  auto values =
      parseList<double>("--eps", text, [](const std::string& s, std::size_t* used) { return std::stod(s, used); });
  for (double eps : values) {
    if (!(eps > 0.0) || !std::isfinite(eps)) {
      char text[32];
      const auto end = std::to_chars(text, text + sizeof text, eps).ptr;
      throw Error("--eps: values must be > 0, got " + std::string(text, end));
    }
  }
  return values;
}

std::vector<int> parseMinPtsList(const std::string& text) {
  auto values =
      parseList<int>("--min-pts", text, [](const std::string& s, std::size_t* used) { return std::stoi(s, used); });
  for (int min_pts : values) {
    if (min_pts < 1) throw Error("--min-pts: values must be >= 1, got " + std::to_string(min_pts));
  }
  return values;
}

struct SweepRow {
  double eps = 0.0;
  int min_pts = 0;
  std::size_t clusters = 0;
  std::size_t noise = 0;
  std::size_t largest = 0;
};

void runSweep(const SweepOptions& o) {
  const std::vector<double> eps_values = parseEpsList(o.eps_list);
  const std::vector<int> min_pts_values = parseMinPtsList(o.min_pts_list);
  const clustering::Metric metric = clustering::parseMetric(o.metric);
  const mapper::FrameParams frame{mapper::parseUpAxis(o.up), o.scale};
  if (!o.output.empty()) {
    try {
      pipeline::checkOutputFile(o.output);
    } catch (const Error& e) {
      throw Error("-o " + std::string(e.what()));
    }
  }
  // Looked up before the runs, so a PNG without a converter fails before the work.
  const auto converter = plot::findPngConverter();
  if (!o.plot.empty()) plot::checkPictureOutput(plot::PictureOutput{o.plot, false, "--plot"}, converter);
  io::PointSet set = pipeline::readInputPoints(inputPaths(o.inputs));
  mapper::toMapFrame(frame, set.points);
  // With -o - the CSV is standard output: the table goes to standard error.
  std::FILE* const say = o.output == "-" ? stderr : stdout;

  std::vector<SweepRow> rows;
  std::vector<plot::SweepPanel> panels;
  std::fprintf(say, "points: %zu, metric %s\n", set.points.size(), clustering::toString(metric).c_str());
  std::fprintf(say, "%10s %8s %9s %9s %9s\n", "eps", "min_pts", "clusters", "noise", "largest");
  for (double eps : eps_values) {
    for (int min_pts : min_pts_values) {
      const clustering::DbscanResult r =
          clustering::dbscan(set.points, {}, clustering::DbscanParams{eps, min_pts, metric});
      SweepRow row{eps, min_pts, r.cluster_sizes.size(), r.noise, 0};
      if (!r.cluster_sizes.empty()) row.largest = *std::max_element(r.cluster_sizes.begin(), r.cluster_sizes.end());
      std::fprintf(say, "%10g %8d %9zu %9zu %9zu\n", row.eps, row.min_pts, row.clusters, row.noise, row.largest);
      rows.push_back(row);
      if (!o.plot.empty()) panels.push_back(plot::SweepPanel{eps, min_pts, r.labels});
    }
  }
  const auto writeCsv = [&](std::ostream& out) {
    out << "eps,min_pts,clusters,noise,largest\n";
    for (const SweepRow& row : rows) {
      char eps[32];
      const auto end = std::to_chars(eps, eps + sizeof eps, row.eps).ptr;  // shortest exact text
      out << std::string(eps, end) << ',' << row.min_pts << ',' << row.clusters << ',' << row.noise << ','
          << row.largest << '\n';
    }
  };
  if (o.output == "-") {
    std::fflush(say);
    writeCsv(std::cout);
    std::cout.flush();
  } else if (!o.output.empty()) {
    core::writeFileAtomically(o.output, writeCsv);
    std::fprintf(say, "wrote %s\n", o.output.c_str());
  }
  if (!o.plot.empty()) {
    const std::string svg = plot::renderSweepSvg(
        set.points, panels, 0.0,
        "hullmap sweep: " + std::to_string(set.points.size()) + " points, metric " + clustering::toString(metric));
    for (const auto& file : plot::writePicture(svg, plot::PictureOutput{o.plot, false, "--plot"}, converter)) {
      std::fprintf(say, "wrote %s\n", file.c_str());
    }
  }
  std::fflush(say);
}

}  // namespace

void addSweepCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<SweepOptions>();
  auto* cmd =
      app.add_subcommand("sweep", "DBSCAN over a grid of eps x min-pts: clusters, noise, largest cluster per pair");
  addSweepOptions(*cmd, *options);
  cmd->callback([options, &status] {
    runSweep(*options);
    status = 0;
  });
}

}  // namespace hullmap::cli
