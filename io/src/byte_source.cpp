#include "byte_source.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "hullmap/core/error.hpp"

namespace hullmap::io::detail {

ByteSource::ByteSource(std::string_view bytes) { setWhole(bytes.data(), bytes.size()); }

ByteSource::ByteSource(ReadFunction read, std::size_t read_bytes)
    : read_(std::move(read)), read_bytes_(std::max<std::size_t>(read_bytes, 1)) {}

ByteSource::ByteSource(const std::string& path, std::size_t read_bytes)
    : read_bytes_(std::max<std::size_t>(read_bytes, 1)) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error(path + ": is a directory, not a point file");
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw Error(path + ": cannot open (" + std::strerror(errno) + ")");
  struct stat st {};
  if (::fstat(fd_, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) {
    // Mapped, not read: no copy and no zero-filled buffer, and pages already parsed can be handed
    // back (release) so a large map does not stay resident.
    const auto size = static_cast<std::size_t>(st.st_size);
    void* p = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd_, 0);
    if (p != MAP_FAILED) {
      ::madvise(p, size, MADV_SEQUENTIAL);
      map_ = p;
      map_size_ = size;
      setWhole(static_cast<const char*>(p), size);
      ::close(fd_);
      fd_ = -1;
      return;
    }
  }
  const int fd = fd_;
  read_ = [fd, path](char* buffer, std::size_t capacity) -> std::size_t {
    while (true) {
      const ssize_t n = ::read(fd, buffer, capacity);
      if (n >= 0) return static_cast<std::size_t>(n);
      if (errno != EINTR) throw Error(path + ": read error (" + std::strerror(errno) + ")");
    }
  };
}

ByteSource::~ByteSource() {
  if (map_ != nullptr) ::munmap(map_, map_size_);
  if (fd_ >= 0) ::close(fd_);
}

void ByteSource::setWhole(const char* data, std::size_t size) {
  data_ = data;
  begin_ = 0;
  end_ = size;
  done_ = true;
}

bool ByteSource::ensureSlow(std::size_t pos, std::size_t n) {
  while (!(n <= end_ && pos <= end_ - n)) {
    if (!more()) return false;
  }
  return true;
}

bool ByteSource::more() {
  while (!done_) {
    if (fill()) return true;
  }
  return false;
}

void ByteSource::loadAll() {
  while (more()) {}
}

std::size_t ByteSource::find(char c, std::size_t pos) {
  std::size_t from = pos;
  while (true) {
    if (from < end_) {
      const void* hit = std::memchr(at(from), c, end_ - from);
      if (hit != nullptr) return begin_ + static_cast<std::size_t>(static_cast<const char*>(hit) - data_);
      from = end_;
    }
    if (!more()) return kNpos;
  }
}

bool ByteSource::fill() {
  // Released bytes leave the buffer once they are half of it (or all of it): each byte is moved
  // at most about once.
  const std::size_t drop = std::min(released_, end_) - begin_;
  if (drop > 0 && 2 * drop >= buffer_.size()) {
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(drop));
    begin_ += drop;
  }
  const std::size_t old = buffer_.size();
  buffer_.resize(old + read_bytes_);
  std::size_t got = 0;
  try {
    got = read_(buffer_.data() + old, read_bytes_);
  } catch (...) {
    buffer_.resize(old);
    throw;
  }
  buffer_.resize(old + std::min(got, read_bytes_));
  data_ = buffer_.data();
  end_ = begin_ + buffer_.size();
  if (got == 0) done_ = true;
  return got > 0;
}

void ByteSource::adviseReleased() {
  const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  const std::size_t upto = std::min(released_, map_size_) / page * page;
  if (upto <= advised_) return;
  ::madvise(static_cast<char*>(map_) + advised_, upto - advised_, MADV_DONTNEED);
  advised_ = upto;
}

}  // namespace hullmap::io::detail
