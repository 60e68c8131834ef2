// Uses each installed library once: a two-blob DBSCAN, an octree, a hull, a path check and the
// hulls as FCL objects, and a path round an obstacle.
#include <cstdio>
#include <memory>
#include <vector>

#include <fcl/geometry/shape/sphere.h>
#include <hullmap/clustering/dbscan.hpp>
#include <hullmap/clustering/obstacles.hpp>
#include <hullmap/collision/fcl_obstacles.hpp>
#include <hullmap/collision/path_check.hpp>
#include <hullmap/mapper/occupancy_map.hpp>
#include <hullmap/planning/path_planner.hpp>

int main() {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 20; ++i) points.emplace_back(0.01 * i, 0.0, 1.0);
  for (int i = 0; i < 20; ++i) points.emplace_back(5.0 + 0.01 * i, 0.0, 1.0);
  hullmap::clustering::DbscanParams params;
  params.eps = 0.05;
  params.min_pts = 5;
  const auto result = hullmap::clustering::dbscan(points, {}, params);

  hullmap::mapper::InputStats stats;
  const auto map = hullmap::mapper::buildFromPoints(points, hullmap::mapper::OctreeParams{}, stats);
  const auto voxels = map.occupiedVoxels();
  std::vector<Eigen::Vector3d> centers;
  std::vector<std::uint32_t> weights;
  for (const auto& v : voxels) {
    centers.push_back(v.center);
    weights.push_back(v.weight);
  }
  hullmap::clustering::DbscanParams voxel_params;
  voxel_params.eps = 0.1;
  voxel_params.min_pts = 2;
  const auto labels = hullmap::clustering::dbscan(centers, weights, voxel_params).labels;
  const auto obstacles = hullmap::clustering::buildObstacles(centers, weights, labels, map.resolution());
  const hullmap::collision::HullChecker checker(obstacles);
  const auto hit = checker.check({Eigen::Vector3d(0.1, -1.0, 1.0), Eigen::Vector3d(0.1, 1.0, 1.0)}, 0.1);
  // The same obstacles as FCL objects: a sphere at the first blob collides with one of them.
  const hullmap::collision::FclObstacles fcl(obstacles);
  fcl::CollisionObjectd sphere(std::make_shared<fcl::Sphered>(0.1), fcl::Transform3d(Eigen::Translation3d(0.1, 0, 1)));
  struct Hit {
    std::size_t index = 99;
  } first;
  fcl.manager().collide(&sphere, &first, [](fcl::CollisionObjectd* o, fcl::CollisionObjectd*, void* data) {
    static_cast<Hit*>(data)->index = hullmap::collision::FclObstacles::indexOf(*o);
    return true;
  });
  // A path from one side of the first blob to the other, round it.
  hullmap::planning::PlanRequest request;
  request.start = Eigen::Vector3d(0.1, -1.0, 1.0);
  request.goal = Eigen::Vector3d(0.1, 1.0, 1.0);
  request.radius = 0.1;
  const auto plan = hullmap::planning::planPath(obstacles, request);
  std::printf("clusters %zu obstacles %zu collides %d fcl hit %zu path %d\n", result.cluster_sizes.size(),
              obstacles.size(), int(hit.collides), first.index, int(plan.path.has_value()));
  return result.cluster_sizes.size() == 2 && obstacles.size() == 2 && hit.collides && first.index == 0 && plan.path
             ? 0
             : 1;
}
