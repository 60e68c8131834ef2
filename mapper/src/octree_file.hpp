#pragma once
// The .bt / .ot validator readMap runs before octomap sees a file's bytes. Not installed.

#include <cstddef>
#include <string>

namespace hullmap::mapper::detail {

// Parses octomap's text header ("id", "size", "res" lines up to "data") and walks the node
// stream: 2 bytes per node in .bt (2 bits per child: 01 occupied, 10 free, 11 inner), a float
// and a child mask per node in .ot. Throws naming the file when anything does not add up.
/// What the header of a .bt / .ot file says, and where its node stream starts.
struct OctreeFileHeader {
  double resolution = 0.0;
  std::size_t size = 0;         ///< nodes
  std::size_t data_offset = 0;  ///< first byte after the 'data' line
};

/// Parses the header line by line, strictly (one `key value` a line, nothing after it), and walks the
/// node stream. readMap then gives octomap only those node bytes: octomap's own header parser reads
/// tokens, not lines ("res 0.1data" ends its header), so a file it parsed differently could pass this
/// walk and still send octomap's recursive reader into garbage.
OctreeFileHeader validateOctreeFile(const std::string& path, const std::string& bytes, bool binary);

}  // namespace hullmap::mapper::detail
