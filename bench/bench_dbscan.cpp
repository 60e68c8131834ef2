// hullmap's DBSCAN on generated scenes of 10k .. 10M points: time, points/s, peak memory.
//
// usage: hullmap_bench_dbscan [--sizes 10000,100000,1000000,10000000] [--eps 0.1] [--min-pts 10]
//                             [--repeat 3] [--write-dir DIR] [--write-max 1000000]
//
// Scenes: generateScene's defaults (8 obstacles in a 10 m room, as `hullmap generate`) in the z-up map
// frame, at n points: the points lie densely on the obstacles' edges and faces (about 1,500 neighbours
// within 0.1 per point at 1M, the density at which the peer timings were taken) and eps 0.1 /
// minPts 10 gives meaningful clusters; the scene's uniform and gross outliers (hundreds of km away)
// are kept.
// For every size up to --write-max, the points and hullmap's labels are written to --write-dir
// for bench/dbscan_peers.py (Open3D, scikit-learn):
//   scene_<n>.f64     n x 3 float64, little-endian, row-major
//   hullmap_<n>.i32   n int32 labels (-1 noise)
//   hullmap_<n>.u8    n uint8 core flags
// One JSON object per size on stdout:
//   {"points":n,"seconds":best,"cpu_seconds":..,"points_per_second":..,"peak_bytes":..,"bytes_per_point":..,
//    "clusters":..,"noise":..,"core":..,"threads":..,"k_distance_seconds":..,"k_distance_cpu_seconds":..,
//    "median_seconds":..,"median_cpu_seconds":..,"k_distance_median_seconds":..,"k_distance_median_cpu_seconds":..}
// Time is the best of --repeat runs of dbscan() on points in memory (wall clock, and CPU time of all
// threads, which shows how much of the machine the run had when others share it). k_distance_*: what
// `hullmap cluster`'s eps suggestion adds to the run (kEpsSuggestionSamples core distances answered on
// the DBSCAN grid), best with it minus best without, runs taken in turns; median_* and
// k_distance_median_*: the median run without it, and the median over the turns of (with minus
// without), which a busy machine moves less than the best-of difference. Peak memory is the growth of the
// resident set during one run: the peak (VmHWM) is reset through /proc/self/clear_refs first, so it
// counts everything dbscan allocates and touches, the result included, and nothing else.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <malloc.h>
#include <sys/resource.h>
#include <tbb/info.h>

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/sim/sample_scene.hpp"

namespace {

using hullmap::clustering::DbscanParams;
using hullmap::clustering::DbscanResult;

// Resident set (VmRSS) or its peak (VmHWM) in bytes, from /proc/self/status.
long statusBytes(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(field, 0) == 0) return std::stol(line.substr(std::strlen(field) + 1)) * 1024;
  }
  return -1;
}

// CPU time of the whole process (all threads), user + system.
double cpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

bool resetPeak() {
  std::ofstream out("/proc/self/clear_refs");
  out << "5";
  out.flush();
  return static_cast<bool>(out);
}

template <typename T>
void writeRaw(const std::string& path, const T* data, std::size_t count) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(count * sizeof(T)));
  if (!out) throw hullmap::Error(path + ": cannot write");
}

std::vector<std::size_t> parseSizes(const std::string& text) {
  std::vector<std::size_t> sizes;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) sizes.push_back(std::stoul(item));
  return sizes;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::size_t> sizes{10000, 100000, 1000000, 10000000};
  DbscanParams params{0.1, 10, hullmap::clustering::Metric::kXyz};
  int repeat = 3;
  std::string write_dir;
  std::size_t write_max = 1000000;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw hullmap::Error(arg + ": missing value");
      return argv[++i];
    };
    if (arg == "--sizes") {
      sizes = parseSizes(value());
    } else if (arg == "--eps") {
      params.eps = std::stod(value());
    } else if (arg == "--min-pts") {
      params.min_pts = std::stoi(value());
    } else if (arg == "--repeat") {
      repeat = std::max(1, std::stoi(value()));
    } else if (arg == "--write-dir") {
      write_dir = value();
    } else if (arg == "--write-max") {
      write_max = std::stoul(value());
    } else {
      std::cerr << "unknown argument " << arg << "\n";
      return 2;
    }
  }

  for (std::size_t n : sizes) {
    hullmap::sim::SceneParams scene_params;
    scene_params.points = n;
    scene_params.orbslam_frame = false;
    const hullmap::sim::Scene scene = hullmap::sim::generateScene(scene_params);
    const auto& points = scene.points;

    // Peak memory of one run, after a run on a few points that starts TBB's worker threads (their
    // stacks and the scheduler's own memory are a fixed cost of the process, not of the algorithm).
    // Free heap memory goes back to the system first, so that what dbscan allocates shows up as
    // resident-set growth even when it reuses freed blocks.
    const std::vector<Eigen::Vector3d> few(points.begin(), points.begin() + std::min<std::size_t>(n, 5000));
    DbscanResult result = hullmap::clustering::dbscan(few, {}, params);
    result = DbscanResult{};
    malloc_trim(0);
    const bool peak_ok = resetPeak();
    const long before = statusBytes("VmRSS:");
    result = hullmap::clustering::dbscan(points, {}, params);
    const long peak = statusBytes("VmHWM:");
    const long grown = peak_ok && before >= 0 && peak >= 0 ? std::max(0L, peak - before) : -1;

    // Time: best of `repeat` (the first run above warmed up the thread pool), of dbscan() alone and,
    // in turns with it, of dbscan() with `hullmap cluster`'s eps-suggestion sample: the difference is
    // what the k-distance curve costs.
    const int runs = n >= 5000000 ? 1 : repeat;
    double best = 1e300, best_cpu = 1e300, best_k = 1e300, best_k_cpu = 1e300;
    std::vector<double> plain, plain_cpu, extra, extra_cpu;  // per turn: without, and with minus without
    const hullmap::clustering::KDistanceRequest request{hullmap::clustering::kEpsSuggestionSamples};
    for (int r = 0; r < runs; ++r) {
      for (const bool with_curve : {false, true}) {
        result = DbscanResult{};
        const double c0 = cpuSeconds();
        const auto t0 = std::chrono::steady_clock::now();
        result = with_curve ? hullmap::clustering::dbscan(points, {}, params, request)
                            : hullmap::clustering::dbscan(points, {}, params);
        const auto t1 = std::chrono::steady_clock::now();
        const double cpu = cpuSeconds() - c0, wall = std::chrono::duration<double>(t1 - t0).count();
        (with_curve ? best_k_cpu : best_cpu) = std::min(with_curve ? best_k_cpu : best_cpu, cpu);
        (with_curve ? best_k : best) = std::min(with_curve ? best_k : best, wall);
        if (with_curve) {
          extra.push_back(wall - plain.back());
          extra_cpu.push_back(cpu - plain_cpu.back());
        } else {
          plain.push_back(wall);
          plain_cpu.push_back(cpu);
        }
      }
    }
    const auto median = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
    };
    const std::size_t core = std::count(result.core.begin(), result.core.end(), std::uint8_t{1});

    if (!write_dir.empty() && n <= write_max) {
      const std::string stem = write_dir + "/";
      std::vector<double> xyz;
      xyz.reserve(3 * n);
      for (const auto& p : points) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
      writeRaw(stem + "scene_" + std::to_string(n) + ".f64", xyz.data(), xyz.size());
      writeRaw(stem + "hullmap_" + std::to_string(n) + ".i32", result.labels.data(), n);
      writeRaw(stem + "hullmap_" + std::to_string(n) + ".u8", result.core.data(), n);
    }
    std::printf(
        "{\"points\":%zu,\"seconds\":%.6f,\"cpu_seconds\":%.6f,\"points_per_second\":%.0f,\"peak_bytes\":%ld,\"bytes_"
        "per_point\":%.1f,"
        "\"clusters\":%zu,\"noise\":%zu,\"core\":%zu,\"threads\":%d,\"k_distance_seconds\":%.6f,"
        "\"k_distance_cpu_seconds\":%.6f,\"median_seconds\":%.6f,\"median_cpu_seconds\":%.6f,"
        "\"k_distance_median_seconds\":%.6f,\"k_distance_median_cpu_seconds\":%.6f}\n",
        n, best, best_cpu, double(n) / best, grown, grown >= 0 ? double(grown) / double(n) : -1.0,
        result.cluster_sizes.size(), result.noise, core, tbb::info::default_concurrency(), std::max(0.0, best_k - best),
        std::max(0.0, best_k_cpu - best_cpu), median(plain), median(plain_cpu), median(extra), median(extra_cpu));
    std::fflush(stdout);
  }
  return 0;
}
