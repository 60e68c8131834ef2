#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>

#include "commands.hpp"
#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/atomic_file.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/core/huge_pages.hpp"
#include "hullmap/core/number_text.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/frame.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "hullmap/pipeline/output_dir.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "option_checks.hpp"

namespace hullmap::cli {
namespace {

struct ClusterOptions {
  std::vector<std::string> inputs;
  double eps = 0.1;
  int min_pts = 10;
  std::string metric = "xyz";
  std::string up = "z";
  double scale = 1.0;
  std::string output;
  double resolution = mapper::OctreeParams{}.resolution;  ///< the build resolution the eps suggestion is judged against
};

// The inputs' points, unioned in order, in the z-up map frame.
io::Points loadMapPoints(const ClusterOptions& o) {
  const mapper::FrameParams frame{mapper::parseUpAxis(o.up), o.scale};
  io::PointSet set = pipeline::readInputPoints(inputPaths(o.inputs));
  mapper::toMapFrame(frame, set.points);
  return std::move(set.points);
}

// Shortest text that reads back to the same double.
void appendNumber(std::string& line, double value) {
  char buffer[core::kShortestTextMax];
  char* const end = core::writeShortest(buffer, value);
  line.append(buffer, end);
}

/// One labels.csv row per point, in input order. Rows are formatted in parallel, a block of points at
/// a time (shortest round-trip text for each coordinate, core::writeShortest, is most of the time), and written
/// in order; memory stays at one block of text. The block's text goes into one buffer that asks for huge
/// pages (core::adviseHugePages): its 8 MB for 257,000 points otherwise cost 2,000 first-touch page faults.
/// Chunk c of the block writes into its slice of the buffer, room for kSliceRow bytes a row (a row of
/// three 6-decimal numbers is about 32); rows that do not fit go on in the chunk's overflow string.
void writeLabelsTo(std::ostream& out, const io::Points& points, const clustering::DbscanResult& result) {
  out << "x,y,z,label,core\n";
  constexpr std::size_t kChunk = 8192;
  constexpr std::size_t kBlock = 64 * kChunk;
  constexpr std::size_t kRowMax = 3 * (core::kShortestTextMax + 1) + 24;  // three numbers, a label, the core flag
  constexpr std::size_t kSliceRow = 48;
  constexpr std::size_t kSlice = kChunk * kSliceRow;
  const std::size_t chunks_per_block = (std::min(points.size(), kBlock) + kChunk - 1) / kChunk;
  const std::unique_ptr<char[]> text(new char[std::max<std::size_t>(1, chunks_per_block * kSlice)]);  // not zeroed
  core::adviseHugePages(text.get(), chunks_per_block * kSlice);
  std::vector<std::size_t> used(chunks_per_block);
  std::vector<std::string> overflow(chunks_per_block);
  for (std::size_t block = 0; block < points.size(); block += kBlock) {
    const std::size_t block_end = std::min(points.size(), block + kBlock);
    const std::size_t count = (block_end - block + kChunk - 1) / kChunk;
    tbb::parallel_for(std::size_t{0}, count, [&](std::size_t c) {
      char* const slice = text.get() + c * kSlice;
      char* at = slice;
      std::string& rest = overflow[c];
      rest.clear();
      const std::size_t end = std::min(block_end, block + (c + 1) * kChunk);
      int decimals = 0;  // the decimals of the number before: a point file's numbers mostly share them
      for (std::size_t i = block + c * kChunk; i < end; ++i) {
        char row[kRowMax];
        const bool fits = rest.empty() && std::size_t(slice + kSlice - at) >= kRowMax;
        char* const start = fits ? at : row;
        char* o = start;
        for (int k = 0; k < 3; ++k) {
          o = core::writeShortest(o, points[i][k], decimals);
          *o++ = ',';
        }
        o = std::to_chars(o, o + 20, result.labels[i]).ptr;
        *o++ = ',';
        *o++ = result.core[i] ? '1' : '0';
        *o++ = '\n';
        if (fits) {
          at = o;
        } else {
          rest.append(row, o);
        }
      }
      used[c] = std::size_t(at - slice);
    });
    for (std::size_t c = 0; c < count; ++c) {
      out.write(text.get() + c * kSlice, std::streamsize(used[c]));
      out << overflow[c];
    }
  }
}

void writeLabels(const std::string& path, const io::Points& points, const clustering::DbscanResult& result) {
  core::writeFileAtomically(path, [&](std::ostream& out) { writeLabelsTo(out, points, result); });
}

std::string numberText(double value) {
  std::string text;
  appendNumber(text, value);
  return text;
}

void runCluster(const ClusterOptions& o) {
  if (!(o.eps > 0.0) || !std::isfinite(o.eps)) throw Error("--eps: must be > 0, got " + numberText(o.eps));
  if (o.min_pts < 1) throw Error("--min-pts: must be >= 1, got " + std::to_string(o.min_pts));
  const clustering::DbscanParams params{o.eps, o.min_pts, clustering::parseMetric(o.metric)};
  if (!o.output.empty()) {
    try {
      pipeline::checkOutputFile(o.output);
    } catch (const Error& e) {
      throw Error("-o " + std::string(e.what()));
    }
  }
  // With -o - the labels are standard output: the summary goes to standard error.
  std::FILE* const say = o.output == "-" ? stderr : stdout;
  const io::Points points = loadMapPoints(o);
  // The eps suggestion's k-distances come from DBSCAN's own grid, on a sample of the points.
  const clustering::DbscanResult result =
      clustering::dbscan(points, {}, params, clustering::KDistanceRequest{clustering::kEpsSuggestionSamples});

  std::vector<std::size_t> sizes = result.cluster_sizes;
  std::sort(sizes.rbegin(), sizes.rend());
  const std::size_t core = std::count(result.core.begin(), result.core.end(), std::uint8_t{1});
  std::fprintf(say, "points: %zu\n", points.size());
  std::fprintf(say, "DBSCAN: eps %g, min-pts %d, metric %s\n", o.eps, o.min_pts,
               clustering::toString(params.metric).c_str());
  std::fprintf(say, "clusters: %zu\n", sizes.size());
  std::fprintf(say, "core points: %zu\n", core);
  std::fprintf(say, "noise points: %zu (%.1f%%)\n", result.noise, 100.0 * double(result.noise) / double(points.size()));
  std::string largest;
  for (std::size_t i = 0; i < std::min<std::size_t>(sizes.size(), 10); ++i) {
    largest += (i ? ", " : "") + std::to_string(sizes[i]);
  }
  std::fprintf(say, "largest clusters: %s\n", largest.empty() ? "none" : largest.c_str());
  const std::vector<double>& curve = result.k_distance_curve;
  if (curve.empty()) {
    std::fprintf(say, "eps suggestion: none (fewer than min-pts points)\n");
  } else {
    const double suggestion = clustering::suggestEps(curve);
    std::fprintf(say, "eps suggestion: %g (knee of the %d-distance curve, min-pts %d)\n", suggestion, o.min_pts - 1,
                 o.min_pts);
    if (suggestion < o.resolution) {
      std::fprintf(say,
                   "  not usable for build at --resolution %g: build clusters voxels, whose centres are %g apart, "
                   "so an eps below it leaves every voxel alone; use --eps >= %g, or build at --resolution <= %g\n",
                   o.resolution, o.resolution, o.resolution, suggestion);
    }
  }
  if (o.output == "-") {
    writeLabelsTo(std::cout, points, result);
    std::cout.flush();
    std::fprintf(
        say,
        "wrote standard output: one row per input point, in input order, in the map frame (after --up, --scale)\n");
  } else if (!o.output.empty()) {
    writeLabels(o.output, points, result);
    std::fprintf(say, "wrote %s: one row per input point, in input order, in the map frame (after --up, --scale)\n",
                 o.output.c_str());
  }
  std::fflush(say);
}

}  // namespace

void addClusterCommand(CLI::App& app, int& status) {
  auto options = std::make_shared<ClusterOptions>();
  auto* cmd =
      app.add_subcommand("cluster", "Exact DBSCAN of map points: labels per point, cluster sizes, eps suggestion");
  cmd->add_option("inputs", options->inputs, "Point files (ORB-SLAM dumps, text/xyz, PCD, PLY), unioned in order")
      ->required();
  cmd->add_option("--eps", options->eps, "Neighbourhood radius, map units (points at exactly eps are neighbours)")
      ->check(numberAbove(0))
      ->capture_default_str();
  cmd->add_option("--min-pts", options->min_pts,
                  "Core when the eps-neighbourhood, the point included, has this many points")
      ->check(wholeNumberFrom(1))
      ->capture_default_str();
  cmd->add_option("--metric", options->metric, "xyz (3D distance) or xy (distance in the ground plane)")
      ->capture_default_str();
  cmd->add_option("--up", options->up, "Input axis that points up: x, -x, y, -y, z, -z (ORB-SLAM: -y)")
      ->capture_default_str();
  cmd->add_option("--scale", options->scale, "Scale applied to the input before the frame change")
      ->check(numberAbove(0))
      ->capture_default_str();
  cmd->add_option("--resolution", options->resolution,
                  "Octree resolution of the build you plan: the eps suggestion says when it is below it")
      ->check(numberAbove(0))
      ->capture_default_str();
  cmd->add_option("-o,--output", options->output,
                  "labels.csv: x,y,z,label,core per input point in input order, in the map frame (after --up); "
                  "- for standard output");
  cmd->callback([options, &status] {
    runCluster(*options);
    status = 0;
  });
}

}  // namespace hullmap::cli
