// A user's program: `hullmap build` on a point file through the installed hullmap::pipeline, the
// output directory written, its obstacles read back and a segment checked among them, and the
// build's page of hullmap::view (when Debian's libjs-three is there to inline).
// Usage: consumer POINTS OUT_DIR; prints the obstacle count.
#include <cstdio>
#include <filesystem>
#include <string>

#include <hullmap/collision/path_check.hpp>
#include <hullmap/pipeline/map_obstacles.hpp>
#include <hullmap/pipeline/pipeline.hpp>
#include <hullmap/view/html_view.hpp>

int main(int argc, char** argv) {
  if (argc != 3) return 2;
  hullmap::pipeline::BuildParams params;
  params.inputs = {argv[1]};
  params.frame.up = hullmap::mapper::UpAxis::kNegY;
  hullmap::pipeline::write(hullmap::pipeline::build(params), argv[2]);
  // The obstacles and the floor and ceiling found: surfaces are obstacles for checks too.
  const auto map = hullmap::pipeline::readMapObstacles(argv[2]);
  const hullmap::collision::HullChecker checker(map.obstacles, map.surfaces);
  const auto hit = checker.check({Eigen::Vector3d(-4, 0, 1), Eigen::Vector3d(4, 0, 1)}, 0.3);
  const auto down = checker.check({Eigen::Vector3d(2, 2, 1), Eigen::Vector3d(2, 2, -1)}, 0.3);
  std::printf("%zu obstacles, segment %s, down %s\n", map.obstacles.size(), hit.collides ? "collides" : "clear",
              down.surface.empty() ? "misses the floor" : ("hits the " + down.surface).c_str());
  if (std::filesystem::exists(std::filesystem::path(hullmap::view::kThreeDir) / "three.min.js")) {
    const auto page = hullmap::view::writePage(hullmap::view::readScene(argv[2], {}), std::string(argv[2]) + ".html");
    std::printf("page of %zu voxels, %zu hulls\n", page.voxels, page.hulls);
  }
}
