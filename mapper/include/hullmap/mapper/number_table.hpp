#pragma once
// readNumberTable lives in the io library; this header stays for code written against the old path.
#include "hullmap/io/number_table.hpp"

namespace hullmap::mapper {
using io::readNumberTable;
}  // namespace hullmap::mapper
