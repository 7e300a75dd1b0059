/// @file huge_pages.hpp
/// An allocator for large, short-lived work arrays that asks the kernel for transparent huge pages.
///
/// Why: a one-shot tool run (mpm2spheres on 1e6 particles) touches tens of MB of fresh memory, and on
/// a virtual machine every first touch of a 4 KiB page is a slow, paravirtualised page fault (40 % of
/// the hand-off's time was spent there, handoff/README.md). With `madvise(MADV_HUGEPAGE)` on a 2 MiB
/// aligned block the kernel maps 2 MiB per fault where transparent huge pages are enabled in
/// `madvise` or `always` mode (/sys/kernel/mm/transparent_hugepage/enabled); elsewhere the advice is
/// ignored and the block behaves like any other. Blocks below `kHugeThreshold` use operator new.
///
/// The allocator is stateless and interchangeable; it changes where memory comes from, never values.
///
/// The tool executables that link `common_tool_new` (src/huge_page_new.cpp: mpm2spheres) apply the
/// same policy to every block of 2 MiB or more through a replaced global operator new.
#pragma once
#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <utility>
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

/// Ask for transparent huge pages on the 2 MiB-aligned interior of an existing, not yet touched
/// block (e.g. a std::vector after reserve(), before it is filled), so that an ordinary
/// std::vector gets the same first-touch saving without changing its type. Advice only.
inline void advise_huge_pages(void* p, std::size_t bytes) noexcept {
#ifdef MADV_HUGEPAGE
  if (bytes < kHugeThreshold) return;
  const std::uintptr_t a = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t lo = (a + kHugePage - 1) / kHugePage * kHugePage, hi = (a + bytes) / kHugePage * kHugePage;
  if (hi > lo) ::madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

/// Resize an empty std::vector to n value-initialised elements on huge pages where possible.
template <class T>
void resize_huge(std::vector<T>& v, std::size_t n) {
  v.reserve(n);
  if (v.empty()) advise_huge_pages(v.data(), n * sizeof(T));
  v.resize(n);
}

/// A std::vector whose storage comes from HugePageAllocator.
template <class T>
using huge_vector = std::vector<T, HugePageAllocator<T>>;

/// A fixed-size array of trivially constructible T from HugePageAllocator, left uninitialised
/// (like `new T[n]`): for work arrays that are written in full before they are read, where
/// huge_vector's value-initialisation would be a wasted pass over fresh memory.
template <class T>
class huge_buffer {
  static_assert(std::is_trivially_default_constructible_v<T> && std::is_trivially_destructible_v<T>);

 public:
  huge_buffer() = default;
  explicit huge_buffer(std::size_t n) : p_(n ? HugePageAllocator<T>().allocate(n) : nullptr), n_(n) {}
  huge_buffer(huge_buffer&& o) noexcept : p_(std::exchange(o.p_, nullptr)), n_(std::exchange(o.n_, 0)) {}
  huge_buffer& operator=(huge_buffer&& o) noexcept {
    std::swap(p_, o.p_);
    std::swap(n_, o.n_);
    return *this;
  }
  huge_buffer(const huge_buffer&) = delete;
  huge_buffer& operator=(const huge_buffer&) = delete;
  ~huge_buffer() {
    if (p_) HugePageAllocator<T>().deallocate(p_, n_);
  }
  T* data() noexcept { return p_; }
  const T* data() const noexcept { return p_; }
  std::size_t size() const noexcept { return n_; }
  T& operator[](std::size_t i) noexcept { return p_[i]; }
  const T& operator[](std::size_t i) const noexcept { return p_[i]; }

 private:
  T* p_ = nullptr;
  std::size_t n_ = 0;
};

}  // namespace common
