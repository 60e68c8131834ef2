// hullmap plot: SVG renderer (palette, cell merging, footprints, path marks), PNG output via
// rsvg-convert, the sweep's small multiples, and the `plot` subcommand on a build directory.
#include <array>
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

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "hullmap/plot/svg_plot.hpp"
#include "plot_fixtures.hpp"
#include "test_support.hpp"

namespace {

// ---------------------------------------------------------------- helpers

// Decodes a PNG with the Python standard library only (zlib + the five PNG filters) and prints
// "width height non_white count_of_each_colour..." for the colours given as rrggbb arguments.
constexpr const char* kPngCount = R"PY(
import sys, zlib, struct
data = open(sys.argv[1], 'rb').read()
assert data[:8] == b'\x89PNG\r\n\x1a\n'
pos, idat = 8, b''
while pos < len(data):
    n, kind = struct.unpack('>I4s', data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + n]
    if kind == b'IHDR':
        w, h, depth, ctype = struct.unpack('>IIBB', body[:10])
    elif kind == b'IDAT':
        idat += body
    pos += 12 + n
assert depth == 8 and ctype in (2, 6), (depth, ctype)
bpp = 3 if ctype == 2 else 4
raw = zlib.decompress(idat)
stride = w * bpp
prev = bytearray(stride)
rows = []
for y in range(h):
    f = raw[y * (stride + 1)]
    line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for i in range(stride):
        a = line[i - bpp] if i >= bpp else 0
        b = prev[i]
        c = prev[i - bpp] if i >= bpp else 0
        if f == 1: line[i] = (line[i] + a) & 255
        elif f == 2: line[i] = (line[i] + b) & 255
        elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
        elif f == 4:
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    rows.append(line)
    prev = line
targets = [tuple(int(t[i:i + 2], 16) for i in (0, 2, 4)) for t in sys.argv[2:]]
counts = [0] * len(targets)
non_white = 0
for line in rows:
    for x in range(w):
        px = tuple(line[x * bpp:x * bpp + 3])
        if bpp == 4 and line[x * bpp + 3] == 0:
            continue
        if px != (255, 255, 255):
            non_white += 1
        for k, t in enumerate(targets):
            if px == t:
                counts[k] += 1
print(w, h, non_white, *counts)
)PY";

// ---------------------------------------------------------------- palette

// ---------------------------------------------------------------- map rendering

// ---------------------------------------------------------------- sweep

// ---------------------------------------------------------------- output files

TEST(PlotOutput, PngIsRenderedAndNotBlank) {
  const auto converter = hullmap::plot::findPngConverter();
  if (!converter) GTEST_SKIP() << "rsvg-convert not on PATH (Debian package librsvg2-bin)";
  if (!havePython()) GTEST_SKIP() << "no PNG decoder: " << HULLMAP_PYTHON3 << " not found";
  Scene s = makeScene(4, 0.05, 9);
  const auto dir = hullmap::test::freshDir("plot_png");
  const auto svg = hullmap::plot::renderMapSvg(s.plot).svg;
  const auto written = hullmap::plot::writePicture(svg, {(dir / "map.svg").string(), true, "-o"}, converter);
  ASSERT_EQ(written.size(), 2u);
  EXPECT_TRUE(fs::exists(dir / "map.svg"));
  ASSERT_TRUE(fs::exists(dir / "map.png"));
  int status = 0;
  const std::string out = runPython(kPngCount, "'" + (dir / "map.png").string() + "' 000000 f3c300 875692", status);
  ASSERT_EQ(status, 0) << out;
  std::istringstream fields(out);
  long w = 0, h = 0, non_white = 0, black = 0, first = 0, second = 0;
  fields >> w >> h >> non_white >> black >> first >> second;
  EXPECT_GT(w, 300);
  EXPECT_GT(h, 300);
  EXPECT_GT(non_white, w * h / 50) << out;
  EXPECT_GT(black, 0) << "noise and outlines";
  EXPECT_GT(first, 20) << "cluster 0 in #f3c300";
  EXPECT_GT(second, 20) << "cluster 1 in #875692";

  // PNG only, by extension; nothing else left in the directory.
  const auto only = hullmap::test::freshDir("plot_png_only");
  hullmap::plot::writePicture(svg, {(only / "map.png").string(), false, "-o"}, converter);
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(only)) files += e.is_regular_file();
  EXPECT_EQ(files, 1u);
  EXPECT_EQ(hullmap::test::slurp(only / "map.png").substr(1, 3), "PNG");
}

// ---------------------------------------------------------------- the subcommand

}  // namespace
