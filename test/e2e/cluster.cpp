#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "dbscan_fixtures.hpp"
#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/error.hpp"
#include "metric_distance.hpp"
#include "run_hullmap.hpp"

namespace hullmap::clustering {
namespace {

// ---- scikit-learn on real SLAM maps ----

// ---- hullmap cluster / hullmap sweep ----

/// Writes `points` as `x y z` text (exact: 17 significant digits).
std::string writeXyz(const std::filesystem::path& path, const Points& points) {
  std::ofstream out(path);
  out.precision(17);
  for (const auto& p : points) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  return path.string();
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream s(text);
  std::string line;
  while (std::getline(s, line)) out.push_back(line);
  return out;
}

/// labels.csv's rows after its header: point i's coordinates read back exactly, its label and core flag.
void expectLabelRows(const std::vector<std::string>& rows, const Points& points, const DbscanResult& expected) {
  ASSERT_EQ(rows.size(), points.size() + 1);
  EXPECT_EQ(rows[0], "x,y,z,label,core");
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::istringstream row(rows[i + 1]);
    double v[3];
    int label = 0, core = 0;
    char comma;
    ASSERT_TRUE(row >> v[0] >> comma >> v[1] >> comma >> v[2] >> comma >> label >> comma >> core) << rows[i + 1];
    ASSERT_EQ(Eigen::Vector3d(v[0], v[1], v[2]), points[i]) << "row " << i + 1;
    ASSERT_EQ(label, expected.labels[i]) << "row " << i + 1;
    ASSERT_EQ(core, int(expected.core[i])) << "row " << i + 1;
  }
}

TEST(ClusterCommand, WritesLabelsOfEveryPointInInputOrder) {
  const auto dir = test::freshDir("cluster_command");
  const Points points = blobs(91, 2000, 2.0, 6, 0.05);
  const std::string input = writeXyz(dir / "points.xyz", points);
  const std::string output = (dir / "labels.csv").string();
  const auto r = test::runHullmap("cluster '" + input + "' --eps 0.1 --min-pts 10 --up -y -o '" + output + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  // The same points in the map frame: --up -y maps (x, y, z) to (x, z, -y).
  Points map;
  for (const auto& p : points) map.emplace_back(p.x(), p.z(), -p.y());
  const DbscanResult expected = dbscan(map, {}, DbscanParams{0.1, 10, Metric::kXyz});
  expectLabelRows(lines(test::slurp(output)), map, expected);
  EXPECT_NE(r.out.find("clusters: " + std::to_string(expected.cluster_sizes.size()) + "\n"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("noise points: " + std::to_string(expected.noise) + " "), std::string::npos) << r.out;
  std::vector<std::size_t> sizes = expected.cluster_sizes;
  std::sort(sizes.rbegin(), sizes.rend());
  EXPECT_NE(r.out.find("largest clusters: " + std::to_string(sizes[0]) + ", " + std::to_string(sizes[1])),
            std::string::npos)
      << r.out;
  std::ostringstream knee;
  knee << "eps suggestion: " << suggestEps(kDistanceCurve(map, 10, Metric::kXyz));
  EXPECT_NE(r.out.find(knee.str()), std::string::npos) << r.out;
}

// labels.csv's rows are formatted a chunk of 8192 at a time into slices of 48 bytes a row, and a chunk
// whose rows are longer on average goes on in an overflow string: 17-digit coordinates (rows of about
// 60 bytes) over 20,000 points take that path in every full chunk; every row is still there, in order.
TEST(ClusterCommand, RowsLongerThanTheirSliceStayInOrder) {
  const auto dir = test::freshDir("cluster_long_rows");
  Points points = blobs(7, 20000, 3.0, 4, 0.05);
  for (auto& p : points) p += Eigen::Vector3d(1.0 / 3.0, -2.0 / 7.0, 5.0 / 11.0);  // no short decimals
  const std::string input = writeXyz(dir / "points.xyz", points);
  const std::string output = (dir / "labels.csv").string();
  const auto r = test::runHullmap("cluster '" + input + "' --eps 0.1 --min-pts 10 -o '" + output + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const DbscanResult expected = dbscan(points, {}, DbscanParams{0.1, 10, Metric::kXyz});
  const auto rows = lines(test::slurp(output));
  ASSERT_EQ(rows.size(), points.size() + 1);
  expectLabelRows(rows, points, expected);
  std::size_t long_rows = 0;
  for (std::size_t i = 0; i < points.size(); ++i) long_rows += rows[i + 1].size() > 48;
  EXPECT_GT(long_rows, points.size() / 2) << "the rows should mostly be longer than a slice's share";
}

// `hullmap` runs cluster and build itself and loads only the shared libraries they use (CLI.md): a
// change that links the other commands' code into it (a unity batch, a new call) brings OMPL, FCL,
// ROS and Python back into every cluster and build run's start (about 25 ms: a quarter of a 0.1 s
// cluster run at 257,000 points, a tenth of a build of octomap_scan.dat). GMP is build's (CGAL's hulls).
TEST(ClusterCommand, TheFrontLoadsNoLibraryOfTheOtherCommands) {
  const auto r = test::runShell(std::string("ldd '") + HULLMAP_BINARY + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  ASSERT_NE(r.out.find("libc.so"), std::string::npos) << r.out;
  for (const char* lib : {"libompl", "libfcl", "libccd", "librosbag", "libpython", "libmpfr", "libboost"})
    EXPECT_EQ(r.out.find(lib), std::string::npos) << lib << " in\n" << r.out;
}

TEST(ClusterCommand, RejectsBadValuesAndEmptyInput) {
  const auto dir = test::freshDir("cluster_command_errors");
  const std::string input = writeXyz(dir / "points.xyz", blobs(92, 100, 1.0, 2, 0.05));
  const std::string empty = (dir / "empty.xyz").string();
  std::ofstream(empty).close();
  const std::string output = (dir / "labels.csv").string();
  for (const auto& [args, needle] : std::vector<std::pair<std::string, std::string>>{
           {"cluster '" + input + "' --eps 0", "--eps"},
           {"cluster '" + input + "' --eps -0.5", "--eps"},
           {"cluster '" + input + "' --min-pts 0", "--min-pts"},
           {"cluster '" + input + "' --metric z", "--metric"},
           {"cluster '" + input + "' --up w", "--up"},
           {"cluster '" + empty + "' -o '" + output + "'", empty + ": no points"},
           {"sweep '" + input + "' --eps 0.1,abc", "--eps"},
           {"sweep '" + input + "' --eps 0.1,0", "--eps"},
           {"sweep '" + input + "' --eps ''", "--eps"},
           {"sweep '" + input + "' --min-pts 5,1.5", "--min-pts"},
           {"sweep '" + input + "' --min-pts 0,5", "--min-pts"},
           {"sweep '" + empty + "'", empty + ": no points"}}) {
    const auto r = test::runHullmap(args);
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_NE(r.err.find("hullmap: error: "), std::string::npos) << args << ": " << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << args << ": " << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(output)) << "a failed run left an output behind";
}

TEST(SweepCommand, OneRowPerPair) {
  const auto dir = test::freshDir("sweep_command");
  const Points points = blobs(93, 1500, 2.0, 5, 0.05);
  const std::string input = writeXyz(dir / "points.xyz", points);
  const std::string output = (dir / "sweep.csv").string();
  const auto r =
      test::runHullmap("sweep '" + input + "' --eps 0.05,0.1 --min-pts 3,10,20 --metric xy -o '" + output + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto rows = lines(test::slurp(output));
  ASSERT_EQ(rows.size(), 7u);
  EXPECT_EQ(rows[0], "eps,min_pts,clusters,noise,largest");
  std::size_t row = 1;
  for (double eps : {0.05, 0.1}) {
    for (int min_pts : {3, 10, 20}) {
      const DbscanResult d = dbscan(points, {}, DbscanParams{eps, min_pts, Metric::kXy});
      const std::size_t largest =
          d.cluster_sizes.empty() ? 0 : *std::max_element(d.cluster_sizes.begin(), d.cluster_sizes.end());
      std::ostringstream want;
      want << eps << ',' << min_pts << ',' << d.cluster_sizes.size() << ',' << d.noise << ',' << largest;
      EXPECT_EQ(rows[row++], want.str());
      // The printed table has the same row, space-aligned.
      std::string printed = want.str();
      std::replace(printed.begin(), printed.end(), ',', ' ');
      bool found = false;
      for (const std::string& line : lines(r.out)) {
        std::istringstream tokens(line);
        std::string token, joined;
        while (tokens >> token) joined += (joined.empty() ? "" : " ") + token;
        found = found || joined == printed;
      }
      EXPECT_TRUE(found) << "no row '" << printed << "' in\n" << r.out;
    }
  }
}

}  // namespace
}  // namespace hullmap::clustering
