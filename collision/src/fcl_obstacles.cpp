#include "hullmap/collision/fcl_obstacles.hpp"

#include <exception>
#include <string>

#include "hullmap/collision/convex_distance.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::collision {

FclObstacles::FclObstacles(const std::vector<hulls::Obstacle>& obstacles)
    : manager_(std::make_unique<fcl::DynamicAABBTreeCollisionManagerd>()) {
  std::vector<fcl::CollisionObjectd*> registered;
  std::vector<std::size_t> owner;  // per object: index of its obstacle in `obstacles`
  for (std::size_t o = 0; o < obstacles.size(); ++o) {
    for (int p = obstacles[o].parts.empty() ? -1 : 0; p < int(obstacles[o].parts.size()); ++p) {
      sources_.push_back({obstacles[o].id, p});
      owner.push_back(o);
    }
  }
  for (std::size_t i = 0; i < sources_.size(); ++i) {
    const hulls::Obstacle& obstacle = obstacles[owner[i]];
    const int part = sources_[i].part;
    const hulls::ConvexHull& hull = part < 0 ? obstacle.hull : obstacle.parts[std::size_t(part)].hull;
    const std::string what =
        "obstacle " + std::to_string(obstacle.id) + (part < 0 ? "" : " part " + std::to_string(part));
    polytopes_.push_back(ConvexPolytope::fromHull(hull, what));  // FCL checks none of this
    auto vertices = std::make_shared<const std::vector<Eigen::Vector3d>>(hull.vertices);
    auto faces = std::make_shared<std::vector<int>>();
    faces->reserve(4 * hull.triangles.size());
    for (const auto& t : hull.triangles) faces->insert(faces->end(), {3, t[0], t[1], t[2]});
    std::shared_ptr<fcl::Convexd> convex;
    try {
      convex = std::make_shared<fcl::Convexd>(vertices, int(hull.triangles.size()), std::move(faces), true);
    } catch (const std::exception& e) {
      throw Error(what + ": FCL rejects the hull: " + e.what());
    }
    convex->computeLocalAABB();
    auto object = std::make_unique<fcl::CollisionObjectd>(convex);
    object->setUserData(reinterpret_cast<void*>(i));
    object->computeAABB();
    registered.push_back(object.get());
    objects_.push_back(std::move(object));
  }
  manager_->registerObjects(registered);
  manager_->setup();
}

FclObstacles::~FclObstacles() = default;
FclObstacles::FclObstacles(FclObstacles&&) noexcept = default;
FclObstacles& FclObstacles::operator=(FclObstacles&&) noexcept = default;

}  // namespace hullmap::collision
