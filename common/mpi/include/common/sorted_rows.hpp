/// @file sorted_rows.hpp
/// Rows spread over the ranks, moved so that each rank holds one contiguous block of their global
/// sorted order (a parallel sample sort, MPI build only). The collective file writers use it: the
/// serial files list particles sorted by (material slot, id), so rank r writes rows
/// [offset, offset + count) of every dataset with one hyperslab, and no rank ever holds the whole
/// set (a gather to rank 0 held all of it, plus a copy in the file image).
///
/// Splitters by regular sampling (each rank's P keys at its local quantiles, allgathered, every
/// P-th of the sorted samples): a rank receives fewer than about 2 N / P rows. The plan is made
/// once from the keys; each column then moves by one alltoallv of its own values, so the extra
/// memory in flight is one column. Keys must be unique (ids are).
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "common/mpi_comm.hpp"

namespace common::mpi {

/// Sort key of a row: (group, id), lexicographic (group = material slot, or 0).
struct RowKey {
  std::uint64_t group = 0;
  std::uint64_t id = 0;
  friend bool operator<(const RowKey& a, const RowKey& b) {
    return a.group != b.group ? a.group < b.group : a.id < b.id;
  }
};

/// Rows numbered densely 0..n-1 (RowKey{0, row}) in fixed blocks: rank r's block is rows
/// [dense_first(n, P, r), dense_first(n, P, r + 1)), whatever the rows' distribution, so that
/// data a rank keeps for its block (ssdem-grav's carried fields) line up with the moved rows.
inline std::size_t dense_first(std::size_t n, int P, int r) {
  return static_cast<std::size_t>((static_cast<unsigned __int128>(n) * static_cast<unsigned>(r)) / static_cast<unsigned>(P));
}
/// The splitters of those blocks (for SortedRows).
std::vector<RowKey> dense_splitters(std::size_t n, int P);

class SortedRows {
 public:
  /// Collective over `comm`: plan the move of this rank's rows (keys[i] for local row i). Rank r
  /// receives the keys in [split[r-1], split[r]) (P - 1 ascending splitters, the same on every
  /// rank); without `split` they come from the keys by regular sampling.
  SortedRows(Comm& comm, const std::vector<RowKey>& keys) : SortedRows(comm, keys, nullptr) {}
  SortedRows(Comm& comm, const std::vector<RowKey>& keys, const std::vector<RowKey>& split)
      : SortedRows(comm, keys, &split) {}
  /// Rows this rank holds after the move, their first global row, and the global row count.
  std::size_t count() const { return recv_order_.size(); }
  std::size_t offset() const { return offset_; }
  std::size_t total() const { return total_; }
  /// Collective: local rows of `ncomp` values each (data[i * ncomp + c]) -> this rank's block, in
  /// global order.
  template <class T>
  std::vector<T> move(const T* data, std::size_t ncomp) const;
  template <class T>
  std::vector<T> move(const std::vector<T>& data, std::size_t ncomp) const {
    return move(data.data(), ncomp);
  }

 private:
  SortedRows(Comm& comm, const std::vector<RowKey>& keys, const std::vector<RowKey>* split);
  /// Collective: this rank's rows sent to their destinations; received rows in arrival order
  /// (sources ascending, each source's rows in key order).
  template <class T>
  std::vector<T> arrivals(const T* data, std::size_t ncomp) const;

  Comm& comm_;
  std::vector<std::size_t> send_order_;  ///< local rows in key order (destinations ascending)
  std::vector<std::size_t> send_rows_;   ///< rows to each rank (consecutive in send_order_)
  std::vector<std::size_t> recv_order_;  ///< block row i = received row recv_order_[i]
  std::size_t offset_ = 0, total_ = 0;
};

template <class T>
std::vector<T> SortedRows::arrivals(const T* data, std::size_t ncomp) const {
  static_assert(std::is_trivially_copyable_v<T>);
  const std::size_t row = ncomp * sizeof(T);
  std::vector<std::vector<char>> send(send_rows_.size());
  std::size_t k = 0;
  for (std::size_t r = 0; r < send_rows_.size(); ++r) {
    send[r].resize(send_rows_[r] * row);
    for (std::size_t j = 0; j < send_rows_[r]; ++j, ++k)
      if (row > 0) std::memcpy(send[r].data() + j * row, data + send_order_[k] * ncomp, row);
  }
  const std::vector<std::vector<char>> recv = comm_.alltoallv(send);
  std::size_t bytes = 0;
  for (const std::vector<char>& b : recv) bytes += b.size();
  std::vector<T> out(row > 0 ? bytes / sizeof(T) : 0);
  char* o = reinterpret_cast<char*>(out.data());
  for (const std::vector<char>& b : recv)
    if (!b.empty()) o = static_cast<char*>(std::memcpy(o, b.data(), b.size())) + b.size();
  return out;
}

template <class T>
std::vector<T> SortedRows::move(const T* data, std::size_t ncomp) const {
  const std::vector<T> in = arrivals(data, ncomp);
  std::vector<T> out(recv_order_.size() * ncomp);
  for (std::size_t i = 0; i < recv_order_.size(); ++i)
    std::copy_n(in.begin() + recv_order_[i] * ncomp, ncomp, out.begin() + i * ncomp);
  return out;
}

}  // namespace common::mpi
