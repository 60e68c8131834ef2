// octomap_server's per-message work on the same map a ROS latency run sends hullmap_node: octomap's
// insertPointCloud of every point from one origin (a keyframe), into an empty tree, as octomap_server
// re-inserts the whole cloud on each message. Prints one JSON line:
//   {"points": N, "resolution": r, "octomap_insert_ms": median, "leaves": L}
//
// usage: hullmap_bench_octomap_cloud POINTS.xyz RESOLUTION OX OY OZ [repeats]   (`x y z` lines)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <octomap/OcTree.h>

int main(int argc, char** argv) {
  if (argc < 6) {
    std::fprintf(stderr, "usage: %s POINTS.xyz RESOLUTION OX OY OZ [repeats]\n", argv[0]);
    return 2;
  }
  std::ifstream in(argv[1]);
  if (!in) {
    std::fprintf(stderr, "%s: cannot open %s\n", argv[0], argv[1]);
    return 2;
  }
  octomap::Pointcloud cloud;
  double x, y, z;
  while (in >> x >> y >> z) cloud.push_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
  const double resolution = std::stod(argv[2]);
  const octomap::point3d origin(std::stof(argv[3]), std::stof(argv[4]), std::stof(argv[5]));
  const int repeats = argc > 6 ? std::stoi(argv[6]) : 3;
  std::vector<double> ms;
  std::size_t leaves = 0;
  for (int r = 0; r < repeats; ++r) {
    octomap::OcTree tree(resolution);
    const auto start = std::chrono::steady_clock::now();
    tree.insertPointCloud(cloud, origin);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    leaves = tree.getNumLeafNodes();
  }
  std::sort(ms.begin(), ms.end());
  std::printf("{\"points\": %zu, \"resolution\": %g, \"octomap_insert_ms\": %.3f, \"leaves\": %zu}\n", cloud.size(),
              resolution, ms[ms.size() / 2], leaves);
  return 0;
}
