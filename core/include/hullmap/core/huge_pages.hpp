#pragma once

// Transparent huge pages for big buffers: where a buffer holds whole huge pages, one page fault
// maps 512 pages instead of one (why and how much: docs/DESIGN_NOTES.md, "huge_pages.hpp").

#include <cstddef>
#include <vector>

namespace hullmap::core {

/// The transparent huge page this code asks for: 2 MiB (x86-64, and arm64 with 4 KiB pages).
inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

/// Asks the kernel to back the whole 2 MiB pages inside [p, p + bytes) with transparent huge pages
/// (Linux madvise MADV_HUGEPAGE); the parts of the range outside them are left alone. Meant for
/// memory not touched yet. A hint only: where the system has no such pages or refuses, nothing
/// changes but speed. Does nothing when the range holds no whole huge page.
void adviseHugePages(void* p, std::size_t bytes) noexcept;

/// v.reserve(n), then the room past v.size() advised as adviseHugePages does.
template <class T, class A>
void reserveHuge(std::vector<T, A>& v, std::size_t n) {
  v.reserve(n);
  adviseHugePages(v.data() + v.size(), (v.capacity() - v.size()) * sizeof(T));
}

}  // namespace hullmap::core
