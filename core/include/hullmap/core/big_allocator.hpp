#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include <stdlib.h>

#include "hullmap/core/huge_pages.hpp"

namespace hullmap::core {

/// Allocator for big arrays: blocks of 2 MiB and more are 2 MiB aligned and advised as huge pages
/// (adviseHugePages). construct() without arguments default-initialises: resize() does not zero.
template <typename T>
struct BigAllocator {
  using value_type = T;
  BigAllocator() = default;
  template <typename U>
  BigAllocator(const BigAllocator<U>&) {}

  T* allocate(std::size_t count) {
    const std::size_t bytes = count * sizeof(T);
    void* p = nullptr;
    if (bytes >= kHugePageBytes) {
      if (posix_memalign(&p, kHugePageBytes, bytes) != 0) throw std::bad_alloc();
      adviseHugePages(p, bytes);
    } else {
      p = std::malloc(bytes == 0 ? 1 : bytes);
      if (!p) throw std::bad_alloc();
    }
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t) { std::free(p); }

  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }

  template <typename U>
  bool operator==(const BigAllocator<U>&) const {
    return true;
  }
  template <typename U>
  bool operator!=(const BigAllocator<U>&) const {
    return false;
  }
};

/// A std::vector whose storage comes from BigAllocator.
template <typename T>
using BigVector = std::vector<T, BigAllocator<T>>;

}  // namespace hullmap::core
