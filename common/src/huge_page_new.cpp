/// @file huge_page_new.cpp
/// Global operator new / delete for the tool executables (linked into them and into the hand-off
/// benchmark, which measures the tool's configuration; never into the libraries or the tests): blocks of 2 MiB or more come 2 MiB-aligned and advised for transparent
/// huge pages, everything else from malloc as before.
///
/// Why: a one-shot tool run touches its large arrays (the particle snapshot it reads, the spheres
/// and index tables it builds) exactly once, so the first-touch page faults are a large part of the
/// run; on a paravirtualised VM each 4 KiB fault is slow (mpm2spheres on 10^6 particles took 11 200
/// minor faults, most of them in the zero-fill of std::vectors: handoff/README.md). With this
/// replacement every std::vector of the tools gets what common::huge_buffer gives the library's work
/// arrays, without changing any type. Where THP is off (/sys/kernel/mm/transparent_hugepage/enabled
/// = never) the advice is ignored and only the alignment remains (at most 2 MiB of address space
/// per large block, untouched and so never backed by memory).
///
/// C++ [new.delete.single] lets a program replace these functions; libstdc++'s array, nothrow and
/// sized forms call the two replaced here, and every block (malloc or aligned_alloc) is released
/// by free().
#include <sys/mman.h>

#include <cstdlib>
#include <new>

#include "common/huge_pages.hpp"

namespace {
void* allocate(std::size_t n) noexcept {
  if (n >= common::kHugePage) {
    const std::size_t rounded = (n + common::kHugePage - 1) / common::kHugePage * common::kHugePage;
    void* p = std::aligned_alloc(common::kHugePage, rounded);
#ifdef MADV_HUGEPAGE
    if (p) ::madvise(p, rounded, MADV_HUGEPAGE);
#endif
    return p;
  }
  return std::malloc(n ? n : 1);
}
}  // namespace

void* operator new(std::size_t n) {
  for (;;) {
    if (void* p = allocate(n)) return p;
    const std::new_handler h = std::get_new_handler();
    if (!h) throw std::bad_alloc();
    h();
  }
}

void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
