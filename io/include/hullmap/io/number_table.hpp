#pragma once

#include <string>
#include <vector>

namespace hullmap::io {

/// Reads a text table of exactly `columns` finite numbers a line (a path's waypoints "x y z", a
/// list of segments "x0 y0 z0 x1 y1 z1") by the point reader's rules: numbers separated by spaces,
/// tabs or one comma; blank lines and `#` comments skipped; a first line of column names
/// (`x,y,z`) skipped. `names` describes a row for messages ("x y z"). Throws hullmap::Error naming
/// the file and line: "p.txt:3: 'five' is not a number", "p.txt:2: expected 3 numbers (x y z), got 2",
/// "p.txt:4: non-finite coordinate", "p.txt: no coordinates", "p.txt: cannot open: <OS reason>".
std::vector<std::vector<double>> readNumberTable(const std::string& path, std::size_t columns,
                                                 const std::string& names);

}  // namespace hullmap::io
