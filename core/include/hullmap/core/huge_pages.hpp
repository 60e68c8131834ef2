#pragma once

// Transparent huge pages for big buffers. A short run that fills fresh memory (reading a point file,
// DBSCAN's arrays, writing labels.csv) spends much of its time in first-touch page faults, one per
// 4 KiB page, and on a virtual machine each costs more (measured on `hullmap cluster` of 257,000
// points: 7,300 faults, a third of the process in the kernel; with glibc's THP tunable, 2,850
// faults and 0.09 s instead of 0.14 s). Asking for huge pages where a buffer holds whole ones
// takes 512 pages per fault.

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
