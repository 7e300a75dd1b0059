#pragma once
// An allocator for large, short-lived work arrays that asks the kernel for transparent huge pages.
//
// Why: a one-shot tool run (mpm2spheres on 1e6 particles) touches tens of MB of fresh memory, and on
// a virtual machine every first touch of a 4 KiB page is a slow, paravirtualised page fault (40 % of
// the hand-off's time was spent there, handoff/README.md). With `madvise(MADV_HUGEPAGE)` on a 2 MiB
// aligned block the kernel maps 2 MiB per fault where transparent huge pages are enabled in
// `madvise` or `always` mode (/sys/kernel/mm/transparent_hugepage/enabled); elsewhere the advice is
// ignored and the block behaves like any other. Blocks below `kHugeThreshold` use operator new.
//
// The allocator is stateless and interchangeable; it changes where memory comes from, never values.
#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

namespace common {

inline constexpr std::size_t kHugePage = std::size_t(2) << 20;      // 2 MiB (x86-64, aarch64 4K)
inline constexpr std::size_t kHugeThreshold = std::size_t(4) << 20;  // below this: ordinary new

template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() noexcept = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    if (n > std::size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kHugeThreshold) return static_cast<T*>(::operator new(bytes));
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, rounded);
    if (!p) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
    ::madvise(p, rounded, MADV_HUGEPAGE);  // advice only: failure leaves ordinary pages
#endif
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) < kHugeThreshold)
      ::operator delete(p);
    else
      std::free(p);
  }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const noexcept { return true; }
  template <class U>
  bool operator!=(const HugePageAllocator<U>&) const noexcept { return false; }
};

/// A std::vector whose storage comes from HugePageAllocator.
template <class T>
using huge_vector = std::vector<T, HugePageAllocator<T>>;

}  // namespace common
