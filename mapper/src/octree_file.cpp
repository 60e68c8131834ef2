#include "octree_file.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "hullmap/core/error.hpp"

namespace hullmap::mapper::detail {
namespace {

constexpr unsigned kTreeDepth = 16;

}  // namespace

OctreeFileHeader validateOctreeFile(const std::string& path, const std::string& bytes, bool binary) {
  std::size_t pos = bytes.find('\n');
  std::string id;
  long long size = -1;
  double res = 0.0;
  bool data = false;
  while (pos != std::string::npos && pos + 1 < bytes.size()) {
    const std::size_t begin = pos + 1;
    pos = bytes.find('\n', begin);
    const std::string line = bytes.substr(begin, pos == std::string::npos ? std::string::npos : pos - begin);
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    std::string token;
    words >> token;
    if (token == "data") {
      std::string extra;
      if (words >> extra) throw Error(path + ": malformed OctoMap header line '" + line + "'");
      data = true;
      break;
    }
    if (token == "id")
      words >> id;
    else if (token == "size")
      words >> size;
    else if (token == "res")
      words >> res;
    else
      throw Error(path + ": unknown OctoMap header line '" + line + "'");
    std::string extra;
    if (!words || words >> extra) throw Error(path + ": malformed OctoMap header line '" + line + "'");
  }
  if (!data || pos == std::string::npos) throw Error(path + ": OctoMap header without a 'data' line");
  if (size < 0 || !(res > 0.0) || !std::isfinite(res))
    throw Error(path + ": OctoMap header lacks a valid size and res");
  if (id != "OcTree") throw Error(path + ": octree type '" + id + "' is not an OcTree");
  std::size_t at = pos + 1;
  long long nodes = 0;
  auto need = [&](std::size_t n) {
    if (at + n > bytes.size())
      throw Error(path + ": truncated OctoMap data (file ends inside node " + std::to_string(nodes) + ")");
  };
  // Depth-first; the depth check bounds the recursion at 16.
  std::function<void(unsigned)> walk = [&](unsigned depth) {
    ++nodes;
    if (nodes > size)
      throw Error(path + ": OctoMap data holds more nodes than its header's size " + std::to_string(size));
    if (binary) {
      need(2);
      const unsigned char a = static_cast<unsigned char>(bytes[at]);
      const unsigned char b = static_cast<unsigned char>(bytes[at + 1]);
      at += 2;
      const unsigned bits = a | (b << 8);
      for (unsigned i = 0; i < 8; ++i) {
        const unsigned code = (bits >> (2 * i)) & 3;
        if (code == 0) continue;
        if (depth + 1 > kTreeDepth) throw Error(path + ": corrupt OctoMap data (tree deeper than 16)");
        if (code == 3) {
          walk(depth + 1);
        } else {
          ++nodes;
        }
      }
    } else {
      need(sizeof(float) + 1);
      const unsigned char mask = static_cast<unsigned char>(bytes[at + sizeof(float)]);
      at += sizeof(float) + 1;
      for (unsigned i = 0; i < 8; ++i) {
        if (!(mask & (1u << i))) continue;
        if (depth + 1 > kTreeDepth) throw Error(path + ": corrupt OctoMap data (tree deeper than 16)");
        walk(depth + 1);
      }
    }
  };
  if (size > 0) walk(0);
  if (nodes != size) {
    throw Error(path + ": OctoMap data holds " + std::to_string(nodes) + " nodes, its header says " +
                std::to_string(size));
  }
  return {res, static_cast<std::size_t>(size), pos + 1};
}

}  // namespace hullmap::mapper::detail
