#include "check_warnings.hpp"

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli_main.hpp"
#include "hullmap/clustering/build_warnings.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::cli {

std::vector<std::string> hullCheckWarnings(const std::string& obstacles_json, std::size_t obstacles) {
  namespace fs = std::filesystem;
  clustering::ClusteringOutcome outcome;
  outcome.obstacles = obstacles;
  const fs::path report_path = fs::path(obstacles_json).parent_path() / "report.json";
  std::ifstream in(report_path);
  if (in) {
    // A report that cannot be read only costs the voxel numbers: the check itself needs none of it.
    const nlohmann::json report = nlohmann::json::parse(in, nullptr, false);
    if (report.is_object()) {
      const auto number = [&](const char* section, const char* key) -> std::size_t {
        const auto s = report.find(section);
        if (s == report.end() || !s->is_object()) return 0;
        const auto v = s->find(key);
        return v != s->end() && v->is_number_unsigned() ? v->get<std::size_t>() : 0;
      };
      outcome.occupied_voxels = number("octree", "occupied_voxels");
      outcome.noise_voxels = number("clusters", "noise_voxels");
    }
  }
  std::vector<std::string> lines;
  for (const Warning& w : clustering::hullCheckWarnings(outcome)) lines.push_back(warningText(w, optionSpelling));
  return lines;
}

void refuseOctreeAsHulls(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  std::ifstream in(path, std::ios::binary);
  std::string head(16, '\0');
  in.read(head.data(), head.size());
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (ext == ".bt" || ext == ".ot" || head.rfind("# Octomap", 0) == 0) {
    throw Error(path +
                ": an octree, not obstacles; check it with --against octree, or give a `hullmap build` "
                "directory or its obstacles.json");
  }
}

}  // namespace hullmap::cli
