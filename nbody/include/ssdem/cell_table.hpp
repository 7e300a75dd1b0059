/// @file cell_table.hpp
/// The contact list's cell grid index: cell key -> first sphere of the cell's linked list, an
/// open-addressing hash table (linear probing, deletion by backward shift, load <= 1/2).
///
/// Why not std::unordered_map: the re-insertion of a moving sphere looks up the 27 cells around
/// it, most of them empty on a debris cloud; the node-based map pays a division and a pointer
/// chase per lookup, and its lookups were most of ContactSystem::local_update on the 2.42 km
/// impact's debris (perf; nbody/README.md, "Cell table"). Here a lookup is a multiply, a shift
/// and usually one cache line.
/// Which spheres a cell holds, and in which order, does not depend on the table: the results
/// are the same bit for bit.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ssdem {

class CellTable {
 public:
  /// A key no cell has (cell keys use the low 63 bits).
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  /// Empties the table, sized for up to n cells (capacity the power of two >= 2 n, at least 16).
  void reset(std::size_t n) {
    std::size_t cap = 16;
    while (cap < 2 * n) cap *= 2;
    slots_.assign(cap, Slot{kEmpty, 0});
    shift_ = 64 - log2(cap);
    size_ = 0;
  }

  /// The value of key k, or null.
  const std::uint32_t* find(std::uint64_t k) const {
    if (slots_.empty()) return nullptr;
    const std::size_t m = slots_.size() - 1;
    for (std::size_t s = slot(k);; s = (s + 1) & m) {
      if (slots_[s].key == k) return &slots_[s].val;
      if (slots_[s].key == kEmpty) return nullptr;
    }
  }
  std::uint32_t* find(std::uint64_t k) {
    return const_cast<std::uint32_t*>(static_cast<const CellTable&>(*this).find(k));
  }

  /// Starts loading the cache line where find(k) begins (several prefetched, then found: their
  /// misses overlap).
  void prefetch(std::uint64_t k) const {
    if (!slots_.empty()) __builtin_prefetch(&slots_[slot(k)]);
  }

  /// The value of key k, inserted with value v when absent. The reference is valid until the next
  /// get_or_insert (which may grow the table) or erase (which may shift entries).
  std::uint32_t& get_or_insert(std::uint64_t k, std::uint32_t v) {
    if (2 * (size_ + 1) > slots_.size()) grow();
    const std::size_t m = slots_.size() - 1;
    std::size_t s = slot(k);
    for (; slots_[s].key != kEmpty; s = (s + 1) & m)
      if (slots_[s].key == k) return slots_[s].val;
    slots_[s] = Slot{k, v};
    ++size_;
    return slots_[s].val;
  }

  /// Removes key k (present or not).
  void erase(std::uint64_t k) {
    if (slots_.empty()) return;
    const std::size_t m = slots_.size() - 1;
    std::size_t s = slot(k);
    while (slots_[s].key != k) {
      if (slots_[s].key == kEmpty) return;
      s = (s + 1) & m;
    }
    // backward shift: move up every later entry of the run whose home slot is not in (s, t]
    for (std::size_t t = (s + 1) & m; slots_[t].key != kEmpty; t = (t + 1) & m) {
      const std::size_t h = slot(slots_[t].key);
      if (((t - h) & m) >= ((t - s) & m)) {  // h lies cyclically at or before s
        slots_[s] = slots_[t];
        s = t;
      }
    }
    slots_[s].key = kEmpty;
    --size_;
  }

  std::size_t size() const { return size_; }
  std::size_t capacity() const { return slots_.size(); }
  /// Bytes held by the table.
  std::size_t bytes() const { return slots_.size() * sizeof(Slot); }

 private:
  static int log2(std::size_t p) {
    int b = 0;
    while ((std::size_t{1} << b) < p) ++b;
    return b;
  }
  // Fibonacci hashing: the top bits of k times 2^64 / golden ratio (cell keys differ mostly in
  // their low bits, which the product spreads over the top)
  std::size_t slot(std::uint64_t k) const {
    return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ull) >> shift_);
  }
  void grow() {
    std::vector<Slot> old;
    old.swap(slots_);
    reset(old.empty() ? 8 : old.size());  // capacity doubles
    for (const Slot& e : old)
      if (e.key != kEmpty) get_or_insert(e.key, e.val);
  }

  struct Slot {  // one cache line holds four
    std::uint64_t key;
    std::uint32_t val;
  };
  std::vector<Slot> slots_;
  int shift_ = 64;
  std::size_t size_ = 0;
};

}  // namespace ssdem
