/// @file sorted_rows.cpp
/// Implementation of common/sorted_rows.hpp (the header states the contract).
#include "common/sorted_rows.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace common::mpi {

std::vector<RowKey> dense_splitters(std::size_t n, int P) {
  std::vector<RowKey> split;
  for (int r = 1; r < P; ++r) split.push_back(RowKey{0, dense_first(n, P, r)});
  return split;
}

SortedRows::SortedRows(Comm& comm, const std::vector<RowKey>& keys, const std::vector<RowKey>* given)
    : comm_(comm) {
  const std::size_t n = keys.size();
  const int P = comm.size;
  send_order_.resize(n);
  std::iota(send_order_.begin(), send_order_.end(), std::size_t{0});
  std::sort(send_order_.begin(), send_order_.end(), [&](std::size_t a, std::size_t b) { return keys[a] < keys[b]; });
  std::vector<RowKey> split;  // rank r takes keys in [split[r-1], split[r])
  if (given) {
    if (given->size() != static_cast<std::size_t>(P - 1)) throw std::logic_error("SortedRows: P - 1 splitters expected");
    split = *given;
  } else {
    // regular sampling: P keys at this rank's quantiles, every rank's on every rank
    std::vector<RowKey> mine;
    for (int j = 0; j < P && n > 0; ++j) mine.push_back(keys[send_order_[(static_cast<std::size_t>(j) * n) / P]]);
    std::vector<RowKey> samples = comm.gather(mine);
    std::sort(samples.begin(), samples.end());
    for (int r = 1; r < P && !samples.empty(); ++r) split.push_back(samples[(static_cast<std::size_t>(r) * samples.size()) / P]);
  }
  send_rows_.assign(P, 0);
  for (const std::size_t i : send_order_) {
    const auto dest = static_cast<std::size_t>(std::upper_bound(split.begin(), split.end(), keys[i]) - split.begin());
    ++send_rows_[dest];
  }
  // the keys themselves move first; the block's order is theirs sorted (each source's already are)
  const std::vector<RowKey> got = arrivals(keys.data(), 1);
  recv_order_.resize(got.size());
  std::iota(recv_order_.begin(), recv_order_.end(), std::size_t{0});
  std::sort(recv_order_.begin(), recv_order_.end(), [&](std::size_t a, std::size_t b) { return got[a] < got[b]; });
  long long c[2] = {static_cast<long long>(got.size()), 0};
  MPI_Exscan(&c[0], &c[1], 1, MPI_LONG_LONG, MPI_SUM, comm.c);
  if (comm.rank == 0) c[1] = 0;  // MPI_Exscan leaves rank 0's result undefined
  offset_ = static_cast<std::size_t>(c[1]);
  long long tot = c[0];
  comm.sum(&tot, 1);
  total_ = static_cast<std::size_t>(tot);
}

}  // namespace common::mpi
