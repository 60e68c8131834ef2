// io::readNumberTable (path and segment files): the point reader's text rules, exact errors.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "hullmap/io/number_table.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using hullmap::test::errorOf;

namespace {

std::string fileWith(const std::string& text) {
  const auto path = hullmap::test::freshDir("table") / "t.txt";
  std::ofstream(path) << text;
  return path.string();
}

}  // namespace

TEST(NumberTable, SpacesCommasCommentsAndAHeaderReadAlike) {
  const std::vector<std::vector<double>> want{{0, -4, 0.5}, {1, 2, 3}};
  EXPECT_EQ(hullmap::io::readNumberTable(fileWith("0 -4 0.5\n1 2 3\n"), 3, "x y z"), want);
  EXPECT_EQ(hullmap::io::readNumberTable(fileWith("x,y,z\r\n0,-4,0.5\r\n\n# c\n1, 2,\t3 # end\n"), 3, "x y z"), want);
  EXPECT_EQ(hullmap::io::readNumberTable(fileWith("pos_x pos_y pos_z\n0 -4 +0.5\n1 2 3\n"), 3, "x y z"), want);
}

TEST(NumberTable, ErrorsNameTheFileAndLine) {
  const auto read = [](const std::string& text, std::size_t columns = 3) {
    const std::string path = fileWith(text);
    std::string message = errorOf([&] { hullmap::io::readNumberTable(path, columns, "x y z"); });
    return message.substr(path.size());  // the path is the message's start
  };
  EXPECT_EQ(read("0 0 0\n1 2\n"), ":2: expected 3 numbers (x y z), got 2");
  EXPECT_EQ(read("0 0 0\n1 2 x3\n"), ":2: 'x3' is not a number");
  EXPECT_EQ(read("0,,0\n"), ":1: empty field");
  EXPECT_EQ(read("0 0 0\n0 nan 1\n"), ":2: non-finite coordinate");
  EXPECT_EQ(read("x y z\n"), ": no coordinates");
  EXPECT_EQ(read("1 2 3 4\n"), ":1: expected 3 numbers (x y z), got 4");
  EXPECT_EQ(read("0 0 0\nx y z\n"), ":2: 'x' is not a number") << "a header only opens the file";
  const std::string missing = (hullmap::test::freshDir("table_missing") / "nope.txt").string();
  EXPECT_EQ(errorOf([&] { hullmap::io::readNumberTable(missing, 3, "x y z"); }),
            missing + ": cannot open: No such file or directory");
}
