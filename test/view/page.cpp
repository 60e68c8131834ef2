// hullmap::view: the page's data decoded back (base64 typed arrays) and compared with what it was
// made from; voxel merging against a brute-force oracle; three.js inlined; errors. The page in a real
// browser is test/view/browser_test.py.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/map_obstacles.hpp"
#include "hullmap/pipeline/path_checker.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/pipeline/voxels_csv.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "hullmap/view/html_view.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
namespace view = hullmap::view;
namespace pipeline = hullmap::pipeline;
namespace mapper = hullmap::mapper;
using nlohmann::json;

bool haveThree() { return fs::exists(fs::path(view::kThreeDir) / "three.min.js"); }

#define HULLMAP_REQUIRE_THREE()                                                                 \
  if (!haveThree()) {                                                                           \
    GTEST_SKIP() << view::kThreeDir << "/three.min.js not found: install Debian's libjs-three " \
                 << "(./setup.sh test does)";                                                   \
  }

// ---------------------------------------------------------------- decoding, as the page does

std::string decodeBase64(const std::string& text) {
  std::string out;
  std::uint32_t bits = 0;
  int count = 0;
  for (char c : text) {
    int v;
    if (c >= 'A' && c <= 'Z')
      v = c - 'A';
    else if (c >= 'a' && c <= 'z')
      v = c - 'a' + 26;
    else if (c >= '0' && c <= '9')
      v = c - '0' + 52;
    else if (c == '+')
      v = 62;
    else if (c == '/')
      v = 63;
    else
      break;  // '='
    bits = bits << 6 | static_cast<std::uint32_t>(v);
    count += 6;
    if (count >= 8) {
      count -= 8;
      out.push_back(static_cast<char>(bits >> count & 0xff));
    }
  }
  return out;
}

template <typename T>
std::vector<T> typed(const std::string& base64) {
  const std::string bytes = decodeBase64(base64);
  EXPECT_EQ(bytes.size() % sizeof(T), 0u);
  std::vector<T> out(bytes.size() / sizeof(T));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));  // little-endian, as the page reads them
  return out;
}

// The page's data block.
json pageData(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"hullmap-data\">";
  const auto start = html.find(open);
  EXPECT_NE(start, std::string::npos);
  const auto end = html.find("</script>", start);
  return json::parse(html.substr(start + open.size(), end - start - open.size()));
}

// ---------------------------------------------------------------- a small build

struct Build {
  fs::path dir;
  pipeline::BuildResult result;
};

Build smallBuild(const std::string& name) {
  hullmap::sim::SceneParams params;
  params.points = 6000;
  params.obstacles = 5;
  params.seed = 11;
  Build b;
  b.dir = hullmap::test::freshDir(name);
  hullmap::sim::writeScene(hullmap::sim::generateScene(params), params, b.dir.string());
  pipeline::BuildParams build;
  build.inputs = {b.dir / "map_points.txt"};
  build.trajectory = b.dir / "KeyFrameTrajectory.txt";
  build.frame.up = mapper::UpAxis::kNegY;
  build.eps = 0.12;
  build.min_pts = 5;
  b.result = pipeline::build(build);
  pipeline::write(b.result, b.dir / "out");
  return b;
}

const Build& sharedBuild() {
  static const Build b = smallBuild("view_shared");
  return b;
}

// A segment through the middle of the largest obstacle's box and out the other side.
view::ViewPath pathThrough(const hullmap::hulls::Obstacle& o) {
  const Eigen::Vector3d c = (o.aabb_min + o.aabb_max) / 2;
  const double reach = (o.aabb_max - o.aabb_min).norm() + 1.0;
  return {"through.txt", {c - Eigen::Vector3d(reach, 0.1, 0), c + Eigen::Vector3d(reach, -0.1, 0)}};
}

const hullmap::hulls::Obstacle& largest(const std::vector<hullmap::hulls::Obstacle>& obstacles) {
  return *std::max_element(obstacles.begin(), obstacles.end(),
                           [](const auto& a, const auto& b) { return a.voxel_count < b.voxel_count; });
}

// ---------------------------------------------------------------- merging: brute-force oracle

struct Voxel {
  std::array<long, 3> k;
  std::int32_t label;
};

int rankOf(std::int32_t l) { return l >= 0 ? 0 : -l; }

// Per cell of factor f: label by the documented priority, voxel count.
std::map<std::array<long, 3>, std::pair<std::int32_t, std::size_t>> oracleCells(const std::vector<Voxel>& voxels,
                                                                                long f, const std::array<long, 3>& lo) {
  std::map<std::array<long, 3>, std::vector<std::int32_t>> members;
  for (const auto& v : voxels) {
    std::array<long, 3> m;
    for (int a = 0; a < 3; ++a) m[a] = (v.k[a] - lo[a]) / f;
    members[m].push_back(v.label);
  }
  std::map<std::array<long, 3>, std::pair<std::int32_t, std::size_t>> out;
  for (const auto& [m, labels] : members) {
    int best_rank = 99;
    for (auto l : labels) best_rank = std::min(best_rank, rankOf(l));
    std::map<std::int32_t, std::size_t> counts;
    for (auto l : labels)
      if (rankOf(l) == best_rank) ++counts[l];
    std::int32_t best = 0;
    std::size_t most = 0;
    for (const auto& [l, c] : counts)  // ascending labels: ties go to the smaller
      if (c > most) {
        most = c;
        best = l;
      }
    out[m] = {best, labels.size()};
  }
  return out;
}

}  // namespace

TEST(ViewVoxelCells, MergesAsTheOracleAtTheSmallestFactorThatFits) {
  std::mt19937_64 rng(5);
  const double r = 0.05;
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<Voxel> voxels;
    std::set<std::array<long, 3>> taken;
    const long span = 4 + static_cast<long>(rng() % 40);
    const std::size_t n = 1 + rng() % std::min<std::size_t>(600, span * span * (span / 2 + 1) / 2);
    const long offset = static_cast<long>(rng() % 200) - 100;
    while (voxels.size() < n) {
      std::array<long, 3> k = {offset + static_cast<long>(rng() % span), static_cast<long>(rng() % span) - 7,
                               static_cast<long>(rng() % (span / 2 + 1))};
      if (!taken.insert(k).second) continue;
      const int kind = static_cast<int>(rng() % 10);
      const std::int32_t label = kind < 5 ? static_cast<std::int32_t>(rng() % 4) : kind < 8 ? -1 : kind < 9 ? -2 : -3;
      voxels.push_back({k, label});
    }
    std::vector<Eigen::Vector3d> centers;
    std::vector<std::int32_t> labels;
    std::array<long, 3> lo = voxels.front().k;
    for (const auto& v : voxels) {
      centers.emplace_back((v.k[0] + 0.5) * r, (v.k[1] + 0.5) * r, (v.k[2] + 0.5) * r);
      labels.push_back(v.label);
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], v.k[a]);
    }
    const std::size_t budget = 1 + rng() % n;
    const view::VoxelCells cells = view::mergeVoxelCells(centers, labels, r, budget);
    long f = 1;
    while (oracleCells(voxels, f, lo).size() > budget) f *= 2;
    ASSERT_EQ(cells.factor, f) << "trial " << trial << ", budget " << budget;
    EXPECT_DOUBLE_EQ(cells.cell, r * static_cast<double>(f));
    const auto expected = oracleCells(voxels, f, lo);
    ASSERT_EQ(cells.centers.size(), expected.size());
    std::size_t total = 0;
    for (std::size_t i = 0; i < cells.centers.size(); ++i) {
      std::array<long, 3> m;
      for (int a = 0; a < 3; ++a) {
        const double index = (cells.centers[i][a] / r - static_cast<double>(lo[a]) - f / 2.0) / static_cast<double>(f);
        m[a] = std::lround(index);
        EXPECT_NEAR(index, static_cast<double>(m[a]), 1e-6) << "a cell centre is the middle of its voxels";
      }
      const auto it = expected.find(m);
      ASSERT_NE(it, expected.end());
      EXPECT_EQ(cells.labels[i], it->second.first) << "trial " << trial;
      EXPECT_EQ(cells.voxels[i], it->second.second);
      total += cells.voxels[i];
      if (i > 0) {
        EXPECT_LE(cells.labels[i - 1], cells.labels[i]) << "sorted by label";
      }
    }
    EXPECT_EQ(total, voxels.size());
  }
}

TEST(ViewVoxelCells, FactorOneGivesEveryVoxelBackAndBadInputIsAnError) {
  const std::vector<Eigen::Vector3d> centers = {{0.025, 0.025, 0.025}, {-1.975, 3.025, 0.125}, {0.075, 0.025, 0.025}};
  const std::vector<std::int32_t> labels = {2, -2, 0};
  const view::VoxelCells cells = view::mergeVoxelCells(centers, labels, 0.05, 3);
  ASSERT_EQ(cells.factor, 1);
  std::multiset<std::tuple<std::int32_t, long, long, long>> got, want;
  for (std::size_t i = 0; i < 3; ++i) {
    got.insert({cells.labels[i], std::lround(cells.centers[i].x() * 1e6), std::lround(cells.centers[i].y() * 1e6),
                std::lround(cells.centers[i].z() * 1e6)});
    want.insert({labels[i], std::lround(centers[i].x() * 1e6), std::lround(centers[i].y() * 1e6),
                 std::lround(centers[i].z() * 1e6)});
  }
  EXPECT_EQ(got, want);
  EXPECT_THROW(view::mergeVoxelCells(centers, labels, 0.05, 0), hullmap::Error);
  EXPECT_THROW(view::mergeVoxelCells(centers, labels, 0.0, 3), hullmap::Error);
  EXPECT_THROW(view::mergeVoxelCells(centers, {1, 2}, 0.05, 3), hullmap::Error);
  // More than an octree's 65,536 voxels along x.
  EXPECT_THROW(view::mergeVoxelCells({{0.025, 0, 0}, {0.025 + 0.05 * 70000, 0, 0}}, {0, 0}, 0.05, 3), hullmap::Error);
}

TEST(ViewPage, DataDecodesToTheBuildsVoxelsHullsKeyframesAndChecks) {
  HULLMAP_REQUIRE_THREE();
  const Build& b = sharedBuild();
  view::ViewInputs inputs;
  inputs.radius = 0.2;
  inputs.paths = {pathThrough(largest(b.result.obstacles)), {"clear.txt", {{0, 0, 2.9}, {0.5, 0.5, 2.9}}}};
  const view::ViewScene scene = view::readScene(b.dir / "out", inputs);
  const view::ViewPage page = view::renderPage(scene);
  const json data = pageData(page.html);
  EXPECT_EQ(data["format"], "hullmap-view/1");
  EXPECT_EQ(data["title"], "out");
  const json report = json::parse(hullmap::test::slurp(b.dir / "out" / "report.json"));
  EXPECT_EQ(data["frame"], report["frame"]);
  EXPECT_EQ(data["parameters"], report["parameters"]);

  // Voxels: every voxel of voxels.csv, with its label, from the 16-bit cells.
  EXPECT_EQ(data["voxels"]["total"], b.result.voxels.size());
  const json& vx = data["voxels"]["levels"][0];
  EXPECT_EQ(vx["factor"], 1);
  const auto cells = typed<std::uint16_t>(vx["cells"]);
  ASSERT_EQ(cells.size(), 3 * b.result.voxels.size());
  std::multiset<std::tuple<std::int32_t, long, long, long>> got, want;
  std::size_t i = 0;
  for (const auto& g : vx["groups"]) {
    for (std::size_t k = 0; k < g["count"].get<std::size_t>(); ++k, ++i) {
      long q[3];
      for (int a = 0; a < 3; ++a) {
        const double c = vx["origin"][a].get<double>() + cells[3 * i + a] * vx["cell"].get<double>();
        q[a] = std::lround(c * 1e4);
      }
      got.insert({g["label"].get<std::int32_t>(), q[0], q[1], q[2]});
    }
  }
  for (const auto& row : pipeline::readVoxelsCsv(b.dir / "out" / "voxels.csv")) {
    want.insert({row.label, std::lround(row.center.x() * 1e4), std::lround(row.center.y() * 1e4),
                 std::lround(row.center.z() * 1e4)});
  }
  EXPECT_EQ(got, want);
  EXPECT_EQ(data["voxels"]["noise"], report["clusters"]["noise_voxels"]);
  EXPECT_EQ(data["voxels"]["floor"], report["floor"]["voxels"]);

  // Hulls: one per convex part, vertices (float32, relative to the shift) and triangles as written.
  const json& hulls = data["hulls"];
  const auto vertices = typed<float>(hulls["vertices"]);
  const auto triangles = typed<std::uint32_t>(hulls["triangles"]);
  const Eigen::Vector3d shift(data["shift"][0], data["shift"][1], data["shift"][2]);
  std::size_t h = 0, vo = 0, to = 0;
  for (const auto& o : b.result.obstacles) {
    ASSERT_FALSE(o.parts.empty());
    for (std::size_t k = 0; k < o.parts.size(); ++k, ++h) {
      const auto& part = o.parts[k];
      const json& item = hulls["items"][h];
      EXPECT_EQ(item["obstacle"], o.id);
      EXPECT_EQ(item["part"], k);
      EXPECT_EQ(item["voxels"], part.voxel_count);
      EXPECT_DOUBLE_EQ(item["volume"].get<double>(), part.volume);
      ASSERT_EQ(hulls["vertex_counts"][h], part.hull.vertices.size());
      ASSERT_EQ(hulls["triangle_counts"][h], part.hull.triangles.size());
      for (const auto& v : part.hull.vertices) {
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(vertices[3 * vo + a] + shift[a], v[a], 1e-5);
        ++vo;
      }
      for (const auto& t : part.hull.triangles) {
        for (int a = 0; a < 3; ++a) EXPECT_EQ(triangles[3 * to + a], static_cast<std::uint32_t>(t[a]));
        ++to;
      }
    }
  }
  EXPECT_EQ(hulls["items"].size(), page.hulls);
  EXPECT_EQ(vo * 3, vertices.size());

  // Keyframes: trajectory.txt's positions.
  ASSERT_FALSE(data["keyframes"].is_null());
  const auto positions = typed<float>(data["keyframes"]["positions"]);
  ASSERT_EQ(positions.size(), 3 * b.result.keyframes.size());
  for (std::size_t k = 0; k < b.result.keyframes.size(); ++k)
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(positions[3 * k + a] + shift[a], b.result.keyframes[k].position[a], 1e-5);

  // Paths: pipeline::pathChecker's answer, segment by segment; one collides, one is clear.
  ASSERT_EQ(data["paths"].size(), 2u);
  const auto checker = pipeline::pathChecker(pipeline::readMapObstacles(b.dir / "out" / "obstacles.json"));
  for (std::size_t p = 0; p < 2; ++p) {
    const auto expected = checker.checkPath(inputs.paths[p].waypoints, 0.2);
    const json& path = data["paths"][p];
    ASSERT_EQ(path["segments"].size(), expected.segments.size());
    for (std::size_t s = 0; s < expected.segments.size(); ++s) {
      EXPECT_EQ(path["segments"][s]["collides"], expected.segments[s].collides);
      if (expected.segments[s].collides) {
        EXPECT_EQ(path["segments"][s]["obstacle"], expected.segments[s].obstacle);
        EXPECT_EQ(path["segments"][s]["part"], expected.segments[s].part);
        EXPECT_EQ(path["segments"][s]["t"], expected.segments[s].t);
      }
    }
    EXPECT_EQ(path["first_colliding_segment"].is_null(), !expected.first_colliding_segment.has_value());
  }
  EXPECT_FALSE(data["paths"][0]["first_contact"].is_null());
  EXPECT_TRUE(data["paths"][1]["first_contact"].is_null());
  EXPECT_EQ(page.colliding_paths, 1u);
}

TEST(ViewPage, ThreeJsIsInlinedAndNothingEndsAScriptEarly) {
  HULLMAP_REQUIRE_THREE();
  const Build& b = sharedBuild();
  view::ViewScene scene = view::readScene(b.dir / "out", {});
  scene.title = "a </script> <b>title</b>";  // an output directory may be called anything
  const std::string html = view::renderPage(scene).html;
  // Each <script> element ends where it should: as many closing tags as opening ones.
  std::size_t opens = 0, closes = 0;
  for (auto at = html.find("<script"); at != std::string::npos; at = html.find("<script", at + 1)) ++opens;
  for (auto at = html.find("</script>"); at != std::string::npos; at = html.find("</script>", at + 1)) ++closes;
  EXPECT_EQ(opens, 5u);  // error hook, three.js, OrbitControls, data, viewer
  EXPECT_EQ(closes, opens);
  EXPECT_NE(html.find("<title>hullmap view: a &lt;/script&gt; &lt;b&gt;title&lt;/b&gt;</title>"), std::string::npos);
  EXPECT_EQ(pageData(html)["title"], scene.title);
  // three.js itself, read from libjs-three, not a copy of our own, and no reference to the network.
  EXPECT_NE(html.find("REVISION=\"111\""), std::string::npos);
  EXPECT_NE(html.find("OrbitControls"), std::string::npos);
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
}

TEST(ViewPage, MoreVoxelsThanTheBudgetAreMergedAndTheDataSaysSo) {
  HULLMAP_REQUIRE_THREE();
  const Build& b = sharedBuild();
  const view::ViewScene scene = view::readScene(b.dir / "out", {});
  view::ViewParams params;
  params.max_instances = 500;
  const view::ViewPage page = view::renderPage(scene, params);
  EXPECT_GT(page.merge_factor, 1);
  EXPECT_LE(page.instances, 500u);
  EXPECT_EQ(page.voxels, b.result.voxels.size());
  const json data = pageData(page.html);
  const json& finest = data["voxels"]["levels"][0];
  EXPECT_EQ(finest["factor"], page.merge_factor);
  EXPECT_EQ(data["voxels"]["max_instances"], 500);
  EXPECT_EQ(data["voxels"]["total"], b.result.voxels.size()) << "the build's counts stay";
  std::size_t drawn = 0;
  for (const auto& g : finest["groups"]) drawn += g["count"].get<std::size_t>();
  EXPECT_EQ(drawn, page.instances);
  EXPECT_EQ(finest["instances"], page.instances);
  EXPECT_EQ(typed<std::uint16_t>(finest["cells"]).size(), 3 * page.instances);
}

TEST(ViewVoxelCells, LevelsHalveTheirDetailDownToTheCoarsest) {
  const Build& b = sharedBuild();
  std::vector<Eigen::Vector3d> centers;
  std::vector<std::int32_t> labels;
  for (std::size_t i = 0; i < b.result.voxels.size(); ++i) {
    centers.push_back(b.result.voxels[i].center);
    labels.push_back(b.result.clusters.labels[i]);
  }
  const double r = b.result.map.resolution();
  const auto levels = view::voxelLevels(centers, labels, r, 5000, 300);
  const auto finest = view::mergeVoxelCells(centers, labels, r, 5000);
  ASSERT_GE(levels.size(), 3u);
  EXPECT_EQ(levels[0].factor, finest.factor);
  EXPECT_EQ(levels[0].labels, finest.labels);
  for (std::size_t k = 1; k < levels.size(); ++k) {
    EXPECT_EQ(levels[k].factor, 2 * levels[k - 1].factor);
    EXPECT_GT(levels[k - 1].centers.size(), 300u) << "a level is added only while the last holds more than 300";
    // Each level is the merge of the voxels at its factor: the smallest budget that gives it back.
    const auto same = view::mergeVoxelCells(centers, labels, r, levels[k].centers.size());
    EXPECT_EQ(same.factor, levels[k].factor);
    EXPECT_EQ(same.labels, levels[k].labels);
    EXPECT_EQ(same.centers, levels[k].centers);
  }
  EXPECT_LE(levels.back().centers.size(), 300u);
  // A page of few voxels holds one level.
  EXPECT_EQ(view::voxelLevels(centers, labels, r, 1000000, centers.size()).size(), 1u);
}

TEST(ViewPage, TruthShapesAreWireframes) {
  HULLMAP_REQUIRE_THREE();
  const Build& b = sharedBuild();
  const fs::path truth_file = b.dir / "truth.json";
  hullmap::test::writeText(truth_file, R"({"obstacles": [
      {"shape": "box", "center": [1, 2, 0.5], "size": [2, 1, 1], "yaw": 0.5},
      {"shape": "cylinder", "center": [-1, 0, 1], "size": [0.4, 0.4, 2]},
      {"kind": "floor", "shape": "box", "center": [0, 0, -0.05], "size": [10, 10, 0.1]},
      {"kind": "ground", "shape": "heightfield", "origin": [0, 0], "step": 1, "size": [3, 2],
       "heights": [0, 0, 0, 1, 1, 1]}]})");
  view::ViewInputs inputs;
  inputs.truth = hullmap::sim::readGroundTruth(truth_file.string());
  inputs.truth_name = "truth.json";
  const json data = pageData(view::renderPage(view::readScene(b.dir / "out", inputs)).html);
  const json& truth = data["truth"];
  ASSERT_EQ(truth["shapes"].size(), 4u);
  EXPECT_EQ(truth["shapes"][0]["segments"], 12);  // a box's edges
  EXPECT_EQ(truth["shapes"][2]["surface"], true);
  EXPECT_EQ(truth["shapes"][3]["segments"], 7);  // a 3 x 2 grid's lines: 2 rows of 2, 3 columns of 1
  EXPECT_EQ(truth["shapes"][3]["surface"], true);
  const auto segments = typed<float>(truth["segments"]);
  const Eigen::Vector3d shift(data["shift"][0], data["shift"][1], data["shift"][2]);
  // Every end of the box's edges is one of its 8 corners (yawed by 0.5 rad about z).
  for (std::size_t e = 0; e < 24; ++e) {
    const Eigen::Vector3d p(segments[3 * e] + shift.x(), segments[3 * e + 1] + shift.y(),
                            segments[3 * e + 2] + shift.z());
    const Eigen::Vector3d q = p - Eigen::Vector3d(1, 2, 0.5);
    const double c = std::cos(-0.5), s = std::sin(-0.5);
    const Eigen::Vector3d local(c * q.x() - s * q.y(), s * q.x() + c * q.y(), q.z());
    EXPECT_NEAR(std::abs(local.x()), 1.0, 1e-5);
    EXPECT_NEAR(std::abs(local.y()), 0.5, 1e-5);
    EXPECT_NEAR(std::abs(local.z()), 0.5, 1e-5);
  }
}

TEST(ViewPage, ErrorsNameTheirCause) {
  const Build& b = sharedBuild();
  view::ViewParams params;
  params.three_dir = b.dir / "no_three_here";
  const view::ViewScene scene = view::readScene(b.dir / "out", {});
  try {
    view::renderPage(scene, params);
    FAIL() << "expected an error";
  } catch (const hullmap::Error& e) {
    EXPECT_EQ(e.parameter(), "three_dir");
    EXPECT_NE(std::string(e.what()).find("libjs-three"), std::string::npos) << e.what();
  }
  // Nothing is written when the page cannot be made.
  EXPECT_THROW(view::writePage(scene, b.dir / "page.html", params), hullmap::Error);
  EXPECT_FALSE(fs::exists(b.dir / "page.html"));
  view::ViewInputs inputs;
  inputs.paths = {{"one.txt", {{0, 0, 1}}}};
  inputs.radius = 0.2;
  try {
    view::readScene(b.dir / "out", inputs);
    FAIL() << "expected an error";
  } catch (const hullmap::Error& e) {
    EXPECT_EQ(e.parameter(), "paths");
  }
  inputs.paths = {{"two.txt", {{0, 0, 1}, {1, 0, 1}}}};
  inputs.radius = -1;
  try {
    view::readScene(b.dir / "out", inputs);
    FAIL() << "expected an error";
  } catch (const hullmap::Error& e) {
    EXPECT_EQ(e.parameter(), "radius");
  }
  EXPECT_THROW(view::readScene(b.dir / "missing", {}), hullmap::Error);
  fs::create_directories(b.dir / "broken");
  fs::copy_file(b.dir / "out" / "report.json", b.dir / "broken" / "report.json", fs::copy_options::overwrite_existing);
  hullmap::test::writeText(b.dir / "broken" / "voxels.csv", "x,y,z,weight,label,core\n1,2,3,1,0,1\n1,2\n");
  try {
    view::readScene(b.dir / "broken", {});
    FAIL() << "expected an error";
  } catch (const hullmap::Error& e) {
    EXPECT_NE(std::string(e.what()).find("voxels.csv:3"), std::string::npos) << e.what();
  }
}
