#pragma once

// The bytes of one point input, visited front to back: what the point readers parse. Not installed.

#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace hullmap::io::detail {

/// The bytes of one input by absolute offset, either all visible at once (bytes in memory, a mapped
/// regular file) or arriving in chunks (pipes and other non-regular files: each fill appends what
/// one read returned). A parser asks for the bytes it needs with ensure(), find() or more(), and
/// says with release() which bytes it is done with: a mapped file hands those pages back to the
/// kernel, a chunked one drops them from its buffer, so memory stays bounded by the bytes a parser
/// holds on to, not by the input's size. Not thread-safe.
class ByteSource {
 public:
  /// Reads up to `capacity` bytes into `buffer`; 0 at the end of the input. Throws on error.
  using ReadFunction = std::function<std::size_t(char* buffer, std::size_t capacity)>;

  static constexpr std::size_t kNpos = std::numeric_limits<std::size_t>::max();

  /// Bytes already in memory, all visible; the caller keeps them alive.
  explicit ByteSource(std::string_view bytes);
  /// Bytes that arrive through `read`, asking for `read_bytes` (>= 1) at a time.
  ByteSource(ReadFunction read, std::size_t read_bytes);
  /// A file: mapped when it is a regular file, read in chunks of `read_bytes` otherwise. Throws
  /// hullmap::Error naming `path` when it is a directory or cannot be opened or read.
  ByteSource(const std::string& path, std::size_t read_bytes);
  ~ByteSource();
  ByteSource(const ByteSource&) = delete;
  ByteSource& operator=(const ByteSource&) = delete;

  /// Makes bytes [pos, pos + n) visible; false when the input ends first.
  bool ensure(std::size_t pos, std::size_t n) {
    if (n <= end_ && pos <= end_ - n) return true;
    return ensureSlow(pos, n);
  }
  /// Loads at least one more byte; false at the end of the input.
  bool more();
  /// Loads the whole input: then end() is its size.
  void loadAll();
  /// The offset of the first `c` at or after `pos`, loading as needed; kNpos when there is none.
  std::size_t find(char c, std::size_t pos);

  /// The visible byte at `pos` (release() must not have passed it).
  const char* at(std::size_t pos) const { return data_ + (pos - begin_); }
  /// Visible bytes [pos, pos + n).
  std::string_view view(std::size_t pos, std::size_t n) const { return {at(pos), n}; }
  /// One past the last visible byte.
  std::size_t end() const { return end_; }
  /// True when no byte is left to load: end() is the size of the input.
  bool complete() const { return done_; }
  /// The input's size when known before reading it all (memory, mapped files), else 0.
  std::size_t sizeHint() const { return done_ ? end_ : 0; }

  /// Bytes before `pos` will not be asked for again (pos may lie beyond end(): those bytes are
  /// skipped as they arrive).
  void release(std::size_t pos) {
    if (pos <= released_) return;
    released_ = pos;
    if (map_ != nullptr && released_ >= advised_ + kAdviseBytes) adviseReleased();
  }

 private:
  // Mapped pages go back in steps of this many bytes: one madvise per step.
  static constexpr std::size_t kAdviseBytes = std::size_t(8) << 20;

  bool ensureSlow(std::size_t pos, std::size_t n);
  bool fill();
  void adviseReleased();
  void setWhole(const char* data, std::size_t size);

  const char* data_ = nullptr;  // byte at offset begin_
  std::size_t begin_ = 0;
  std::size_t end_ = 0;
  bool done_ = false;
  std::size_t released_ = 0;

  ReadFunction read_;
  std::size_t read_bytes_ = 0;
  std::vector<char> buffer_;  // chunked: bytes [begin_, end_)

  void* map_ = nullptr;
  std::size_t map_size_ = 0;
  std::size_t advised_ = 0;
  int fd_ = -1;
};

}  // namespace hullmap::io::detail
