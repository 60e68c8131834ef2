#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <sstream>
#include <tuple>

#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/frame.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "octree_oracle.hpp"
#include "test_support.hpp"

namespace hullmap::mapper {
namespace {

using namespace hullmap::io;
using namespace hullmap::sim;

using test::sameTree;

octomap::OcTree oracleTree(const OctreeParams& p) {
  octomap::OcTree tree(p.resolution);
  tree.setProbHit(p.sensor.hit);
  tree.setProbMiss(p.sensor.miss);
  tree.setClampingThresMin(p.sensor.clamp_min);
  tree.setClampingThresMax(p.sensor.clamp_max);
  tree.setOccupancyThres(p.sensor.occupancy_threshold);
  return tree;
}

// Points with many duplicates per voxel (up to 30: beyond the clamp), a filled 4x4x4 block
// (pruned), and two gross outliers.
Points denseCloud() {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Points points;
  for (int i = 0; i < 3000; ++i) {
    const Point base(std::floor(u(rng) * 20) * 0.1 + 0.05, std::floor(u(rng) * 20) * 0.1 + 0.05,
                     std::floor(u(rng) * 5) * 0.1 + 0.05);
    const int copies = 1 + static_cast<int>(u(rng) * 30);
    for (int c = 0; c < copies; ++c) points.push_back(base + Point(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * 0.08);
  }
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 4; ++y)
      for (int z = 0; z < 4; ++z)
        for (int c = 0; c < 12; ++c) points.push_back(Point(3.25 + 0.1 * x, 3.25 + 0.1 * y, 3.25 + 0.1 * z));
  points.push_back(Point(4e5, 1.0, 2.0));
  points.push_back(Point(-1.0, -9e5, 2.0));
  return points;
}

// octomap's own insertion: updateNode(point, true) once per point it can address, the points per
// leaf key, and how many points it could not address.
struct UpdateNodeOracle {
  explicit UpdateNodeOracle(const OctreeParams& params) : tree(oracleTree(params)) {}
  octomap::OcTree tree;
  std::map<std::tuple<int, int, int>, std::uint32_t> counts;
  std::size_t out = 0;
};

UpdateNodeOracle updateNodePerPoint(const Points& points, const OctreeParams& params) {
  UpdateNodeOracle oracle(params);
  for (const Point& p : points) {
    octomap::OcTreeKey key;
    if (!oracle.tree.coordToKeyChecked(test::toPoint3d(p), key)) {
      ++oracle.out;
      continue;
    }
    oracle.tree.updateNode(key, true);
    ++oracle.counts[{key[0], key[1], key[2]}];
  }
  return oracle;
}

::testing::AssertionResult sameCounts(const UpdateNodeOracle& oracle, const OccupancyMap& map) {
  if (map.pointCounts().size() != oracle.counts.size()) {
    return ::testing::AssertionFailure() << map.pointCounts().size() << " counted keys, expected "
                                         << oracle.counts.size();
  }
  for (const auto& [key, n] : map.pointCounts()) {
    const auto it = oracle.counts.find({key[0], key[1], key[2]});
    if (it == oracle.counts.end() || it->second != n) {
      return ::testing::AssertionFailure() << "key " << key[0] << " " << key[1] << " " << key[2] << ": " << n
                                           << " points, expected " << (it == oracle.counts.end() ? 0 : it->second);
    }
  }
  return ::testing::AssertionSuccess();
}

TEST(MapperOctree, PointsOnlyIsUpdateNodePerPoint) {
  OctreeParams params;
  params.resolution = 0.1;
  const Points points = denseCloud();
  InputStats stats;
  const OccupancyMap map = buildFromPoints(points, params, stats);
  const UpdateNodeOracle expected = updateNodePerPoint(points, params);
  EXPECT_EQ(expected.out, 2u);
  EXPECT_EQ(stats.dropped.at("out_of_octree"), 2u);
  EXPECT_TRUE(sameTree(expected.tree, map.tree()));
  EXPECT_TRUE(sameCounts(expected, map));
}

// The batched builder against the same oracle: batches of one point, batches that cut a voxel's
// consecutive points apart (denseCloud puts up to 30 points of a voxel one after another), batches
// of many voxels, one batch; the ~48k points make the builder merge its pending keys several times.
TEST(MapperOctree, PointsOnlyInBatchesIsUpdateNodePerPoint) {
  OctreeParams params;
  params.resolution = 0.1;
  const Points points = denseCloud();
  const UpdateNodeOracle expected = updateNodePerPoint(points, params);
  const octomap::OcTree& keys = expected.tree;
  for (const std::size_t batch : {std::size_t{1}, std::size_t{2}, std::size_t{7}, std::size_t{1000}, std::size_t{4096},
                                  std::size_t{20000}, points.size()}) {
    SCOPED_TRACE("batches of " + std::to_string(batch));
    std::size_t split_voxels = 0;  // a voxel's points on both sides of a batch boundary
    for (std::size_t i = batch; i < points.size(); i += batch) {
      split_voxels += keys.coordToKey(test::toPoint3d(points[i - 1])) == keys.coordToKey(test::toPoint3d(points[i]));
    }
    if (batch < 1000) {
      EXPECT_GT(split_voxels, 0u) << "no batch boundary cuts a voxel's points";
    }
    PointMapBuilder builder(params);
    InputStats stats;
    for (std::size_t first = 0; first < points.size(); first += batch) {
      const Points slice(points.begin() + static_cast<std::ptrdiff_t>(first),
                         points.begin() + static_cast<std::ptrdiff_t>(std::min(points.size(), first + batch)));
      builder.add(slice, stats);
    }
    const OccupancyMap map = builder.finish();
    EXPECT_EQ(stats.dropped.at("out_of_octree"), 2u);
    EXPECT_TRUE(sameTree(expected.tree, map.tree()));
    EXPECT_TRUE(sameCounts(expected, map));
  }
}

TEST(MapperOctree, PointMapBuilderStartsOverAfterFinishAndIgnoresOrder) {
  OctreeParams params;
  params.resolution = 0.1;
  Points points = denseCloud();
  PointMapBuilder builder(params);
  InputStats stats;
  builder.add(points, stats);
  EXPECT_GT(builder.finish().tree().size(), 0u);
  const OccupancyMap empty = builder.finish();
  EXPECT_EQ(empty.tree().size(), 0u);
  EXPECT_TRUE(empty.pointCounts().empty());
  EXPECT_DOUBLE_EQ(empty.resolution(), 0.1);
  std::reverse(points.begin(), points.end());
  builder.add(points, stats);
  const OccupancyMap reversed = builder.finish();
  const UpdateNodeOracle expected = updateNodePerPoint(denseCloud(), params);
  EXPECT_TRUE(sameTree(expected.tree, reversed.tree()));
  EXPECT_TRUE(sameCounts(expected, reversed));
  EXPECT_EQ(stats.dropped.at("out_of_octree"), 4u);
  params.sensor.clamp_min = 0.99;
  EXPECT_THROW(PointMapBuilder{params}, Error);
}

// The streaming readers into the batched builder give the map of the whole-file readers into
// buildFromPoints: the same tree, point counts and voxels.
TEST(MapperOctree, StreamedFilesBuildTheMapOfWholeFiles) {
  const auto dir = test::freshDir("mapper_octree_streamed");
  SceneParams scene_params;
  scene_params.points = 30000;
  const Scene scene = generateScene(scene_params);
  std::ofstream a(dir / "a.txt");
  std::ofstream b(dir / "b.txt");
  a.precision(17);
  b.precision(17);
  for (std::size_t i = 0; i < scene.points.size(); ++i) {
    std::ofstream& out = i < scene.points.size() / 3 ? a : b;
    out << scene.points[i].x() << ' ' << scene.points[i].y() << ' ' << scene.points[i].z() << '\n';
    if (i % 1000 == 0) out << "nan 0 0\n";
  }
  a.close();
  b.close();
  const std::vector<std::string> files = {(dir / "a.txt").string(), (dir / "b.txt").string()};
  const FrameParams frame{UpAxis::kNegY, 1.5};
  FilterParams filters;
  filters.z_min = -0.5;
  OctreeParams params;
  params.resolution = 0.08;

  PointSet set = readPointFiles(files);
  toMapFrame(frame, set.points);
  InputStats whole_stats;
  applyFilters(filters, set.points, whole_stats);
  const OccupancyMap whole = buildFromPoints(set.points, params, whole_stats);

  PointMapBuilder builder(params);
  InputStats streamed_stats;
  PointStreamParams stream;
  stream.batch_points = 4096;
  const std::vector<InputStats> inputs = streamPointFiles(files, stream, [&](Points& batch) {
    toMapFrame(frame, batch);
    applyFilters(filters, batch, streamed_stats);
    builder.add(batch, streamed_stats);
  });
  const OccupancyMap streamed = builder.finish();

  ASSERT_EQ(inputs.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(inputs[i].read, set.inputs[i].read);
    EXPECT_EQ(inputs[i].dropped, set.inputs[i].dropped);
  }
  EXPECT_GT(inputs[1].dropped.at("non_finite"), 0u);
  EXPECT_GT(whole_stats.dropped.at("below_z_min"), 0u);
  EXPECT_EQ(streamed_stats.dropped, whole_stats.dropped);
  EXPECT_TRUE(sameTree(whole.tree(), streamed.tree()));
  EXPECT_EQ(whole.pointCounts(), streamed.pointCounts());
  const auto want = whole.occupiedVoxels();
  const auto got = streamed.occupiedVoxels();
  ASSERT_EQ(want.size(), got.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(want[i].center, got[i].center) << i;
    EXPECT_EQ(want[i].weight, got[i].weight) << i;
    EXPECT_EQ(want[i].log_odds, got[i].log_odds) << i;
  }
}

TEST(MapperOctree, SensorModelReachesTheTree) {
  OctreeParams params;
  params.resolution = 0.2;
  params.sensor = {0.9, 0.3, 0.2, 0.8, 0.6};
  InputStats stats;
  const OccupancyMap map = buildFromPoints(denseCloud(), params, stats);
  EXPECT_DOUBLE_EQ(map.resolution(), 0.2);
  EXPECT_NEAR(map.tree().getProbHit(), 0.9, 1e-6);
  EXPECT_NEAR(map.tree().getProbMiss(), 0.3, 1e-6);
  EXPECT_NEAR(map.tree().getClampingThresMin(), 0.2, 1e-6);
  EXPECT_NEAR(map.tree().getClampingThresMax(), 0.8, 1e-6);
  EXPECT_NEAR(map.tree().getOccupancyThres(), 0.6, 1e-6);
  octomap::OcTree expected = oracleTree(params);
  for (const Point& p : denseCloud()) expected.updateNode(test::toPoint3d(p), true);
  EXPECT_TRUE(sameTree(expected, map.tree()));
}

TEST(MapperOctree, RejectsBadParameters) {
  OctreeParams p;
  p.resolution = 0.0;
  EXPECT_THROW(OccupancyMap{p}, Error);
  p = OctreeParams{};
  p.sensor.hit = 1.0;
  EXPECT_THROW(OccupancyMap{p}, Error);
  p = OctreeParams{};
  p.sensor.clamp_min = 0.99;
  EXPECT_THROW(OccupancyMap{p}, Error);
}

TEST(MapperOctree, OccupiedVoxelsExpandPrunedLeavesSortedWithCounts) {
  OctreeParams params;
  params.resolution = 0.1;
  InputStats stats;
  const OccupancyMap map = buildFromPoints(denseCloud(), params, stats);
  // The filled block is pruned in the tree.
  bool pruned = false;
  for (auto it = map.tree().begin_leafs(); it != map.tree().end_leafs(); ++it) pruned |= it.getDepth() < 16;
  ASSERT_TRUE(pruned);

  octomap::OcTree expanded(map.tree());
  expanded.expand();
  std::vector<std::tuple<int, int, int, float>> expected;
  for (auto it = expanded.begin_leafs(); it != expanded.end_leafs(); ++it) {
    ASSERT_EQ(it.getDepth(), 16u);
    if (expanded.isNodeOccupied(*it))
      expected.emplace_back(it.getKey()[0], it.getKey()[1], it.getKey()[2], it->getLogOdds());
  }
  std::sort(expected.begin(), expected.end());
  const auto voxels = map.occupiedVoxels();
  ASSERT_EQ(voxels.size(), expected.size());
  for (std::size_t i = 0; i < voxels.size(); ++i) {
    const auto [k0, k1, k2, log_odds] = expected[i];
    const octomap::OcTreeKey key = map.tree().coordToKey(octomap::point3d(static_cast<float>(voxels[i].center.x()),
                                                                          static_cast<float>(voxels[i].center.y()),
                                                                          static_cast<float>(voxels[i].center.z())));
    ASSERT_EQ(std::make_tuple(int(key[0]), int(key[1]), int(key[2])), std::make_tuple(k0, k1, k2)) << i;
    EXPECT_FLOAT_EQ(voxels[i].log_odds, log_odds);
    EXPECT_EQ(voxels[i].weight, map.pointCounts().at(key));
  }
}

// Brute-force keyframe rule of buildWithTrajectory's documentation.
std::size_t keyframeFor(const Point& p, const std::vector<Keyframe>& keyframes) {
  std::size_t facing = keyframes.size(), nearest = 0;
  double facing_d2 = 1e300, nearest_d2 = 1e300;
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    const Eigen::Vector3d d = p - keyframes[k].position;
    const double d2 = d.squaredNorm();
    if (d2 < nearest_d2) nearest_d2 = d2, nearest = k;
    if ((keyframes[k].orientation * Eigen::Vector3d::UnitZ()).dot(d) > 0.0 && d2 < facing_d2)
      facing_d2 = d2, facing = k;
  }
  return facing < keyframes.size() ? facing : nearest;
}

TEST(MapperOctree, TrajectoryIsInsertPointCloudPerKeyframeGroup) {
  SceneParams scene_params;
  scene_params.points = 20000;
  scene_params.keyframes = 40;
  scene_params.orbslam_frame = false;
  const Scene scene = generateScene(scene_params);
  // Some keyframes facing away from everything exercise the fallback.
  std::vector<Keyframe> keyframes = scene.keyframes;
  for (std::size_t k = 0; k < keyframes.size(); k += 9) {
    keyframes[k].orientation = keyframes[k].orientation * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY());
  }
  for (double max_range : {-1.0, 3.0}) {
    OctreeParams params;
    params.resolution = 0.1;
    params.max_range = max_range;
    InputStats stats;
    const OccupancyMap map = buildWithTrajectory(scene.points, keyframes, params, stats);
    EXPECT_EQ(stats.dropped.at("out_of_octree"), scene_params.gross_outliers);

    std::vector<octomap::Pointcloud> groups(keyframes.size());
    for (const Point& p : scene.points) {
      octomap::OcTreeKey key;
      if (!map.tree().coordToKeyChecked(test::toPoint3d(p), key)) continue;
      const auto& q = test::toPoint3d(p);
      groups[keyframeFor(p, keyframes)].push_back(q);
    }
    octomap::OcTree expected = oracleTree(params);
    for (std::size_t k = 0; k < keyframes.size(); ++k) {
      if (groups[k].size() > 0) expected.insertPointCloud(groups[k], test::toPoint3d(keyframes[k].position), max_range);
    }
    EXPECT_TRUE(sameTree(expected, map.tree())) << "max_range " << max_range;
  }
}

TEST(MapperOctree, WritesAndReadsBtAndOt) {
  OctreeParams params;
  params.resolution = 0.1;
  InputStats stats;
  const OccupancyMap map = buildFromPoints(denseCloud(), params, stats);
  const auto dir = test::freshDir("mapper_octree_io");

  const std::string ot = (dir / "map.ot").string();
  writeMap(map, ot);
  const OccupancyMap full = readMap(ot);
  EXPECT_TRUE(sameTree(map.tree(), full.tree()));

  const std::string bt = (dir / "map.bt").string();
  writeMap(map, bt);
  octomap::OcTree expected(0.1);
  ASSERT_TRUE(expected.readBinary(bt));
  const OccupancyMap binary = readMap(bt);
  EXPECT_TRUE(sameTree(expected, binary.tree()));
  const auto voxels = binary.occupiedVoxels();
  ASSERT_EQ(voxels.size(), map.occupiedVoxels().size());
  for (const auto& v : voxels) EXPECT_EQ(v.weight, 1u);

  EXPECT_THROW(writeMap(map, (dir / "map.txt").string()), Error);
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().filename().string().rfind(".", 0), std::string::npos) << "temporary file left";
  }
}

TEST(MapperOctree, BtIsOctomapsWriteBinaryConstByteForByteAndStderrIsUntouched) {
  // writeMap writes the .bt header itself (octomap's writeBinaryConst prints progress on stderr in
  // Debian's build): the bytes must be octomap's own, for an empty tree and a full one.
  OctreeParams params;
  params.resolution = 0.1;
  InputStats stats;
  const auto dir = test::freshDir("mapper_octree_bt_bytes");
  for (const bool empty : {true, false}) {
    const OccupancyMap map = empty ? OccupancyMap(params) : buildFromPoints(denseCloud(), params, stats);
    const std::string bt = (dir / (empty ? "empty.bt" : "full.bt")).string();
    testing::internal::CaptureStderr();
    writeMap(map, bt);
    const OccupancyMap back = readMap(bt);
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "") << "writeMap/readMap printed on stderr";
    std::ostringstream octomap_bytes;
    testing::internal::CaptureStderr();  // octomap's own chatter, not ours
    ASSERT_TRUE(map.tree().writeBinaryConst(octomap_bytes));
    testing::internal::GetCapturedStderr();
    std::ifstream in(bt, std::ios::binary);
    const std::string ours((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(ours, octomap_bytes.str()) << (empty ? "empty" : "full") << " tree";
    EXPECT_EQ(back.tree().size(), map.tree().size());
  }
}

TEST(MapperOctree, CorruptFilesAreErrorsNamingThem) {
  OctreeParams params;
  params.resolution = 0.1;
  InputStats stats;
  const OccupancyMap map = buildFromPoints(denseCloud(), params, stats);
  const auto dir = test::freshDir("mapper_octree_corrupt");
  for (const std::string name : {"map.bt", "map.ot"}) {
    const std::string good = (dir / name).string();
    writeMap(map, good);
    const std::string bytes = test::slurp(good);
    for (std::size_t keep : {bytes.size() - 1, bytes.size() / 2, std::size_t{30}}) {
      const std::string cut = (dir / ("cut_" + std::to_string(keep) + "_" + name)).string();
      std::ofstream(cut, std::ios::binary) << bytes.substr(0, keep);
      try {
        readMap(cut);
        ADD_FAILURE() << cut << " read without error";
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(cut), std::string::npos) << e.what();
      }
    }
  }
  const std::string text = (dir / "points.bt").string();
  std::ofstream(text) << "1 2 3\n4 5 6\n";
  EXPECT_THROW(readMap(text), Error);
  EXPECT_THROW(readMap((dir / "missing.bt").string()), Error);
}

TEST(MapperOctree, ReadsOctomapsOwnBinaryMap) {
  HULLMAP_REQUIRE_REAL_DATA(path, "octomap_geb079.bt");
  octomap::OcTree expected(0.1);
  ASSERT_TRUE(expected.readBinary(path));
  const OccupancyMap map = readMap(path);
  EXPECT_TRUE(sameTree(expected, map.tree()));
  const MapInfo info = describe(map.tree());
  EXPECT_DOUBLE_EQ(info.resolution, expected.getResolution());
  EXPECT_EQ(info.nodes, expected.size());
  EXPECT_EQ(info.memory_bytes, expected.memoryUsage());
  std::size_t occupied = 0, free = 0;
  for (auto it = expected.begin_leafs(); it != expected.end_leafs(); ++it)
    (expected.isNodeOccupied(*it) ? occupied : free)++;
  EXPECT_EQ(info.occupied_leaves, occupied);
  EXPECT_EQ(info.free_leaves, free);
  double x, y, z;
  expected.getMetricMin(x, y, z);
  EXPECT_DOUBLE_EQ(info.min.x(), x);
  expected.getMetricMax(x, y, z);
  EXPECT_DOUBLE_EQ(info.max.z(), z);
  EXPECT_GT(occupied, 0u);
}

}  // namespace
}  // namespace hullmap::mapper
