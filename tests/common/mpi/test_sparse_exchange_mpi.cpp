/// @file test_sparse_exchange_mpi.cpp
/// Comm::sparse (common/mpi_comm.hpp, the NBX sparse exchange) under mpirun -np 2 and -np 3: on
/// random sparse patterns (each rank sending to some ranks, itself included, buffers of 0 bytes
/// to 3 MB, every byte naming its sender, receiver, call and place) it returns on every rank
/// exactly what alltoallv returns, and counts the same bytes sent, with one rank held back before
/// some calls; over calls back to back with nothing in between (a rank whose barrier completed
/// first sends the next call's messages, which carry the other tag, while others may still probe
/// in the previous call: with one tag this fails on 3 ranks); and when no rank sends anything.
/// Failures are EXPECTs, so that a failing rank keeps making the collective calls of the others.
#include <gtest/gtest.h>
#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <random>
#include <thread>
#include <vector>

#include "common/mpi_comm.hpp"
#include "mpi_test_util.hpp"

namespace {

using mpi_test::world;

// The buffers rank `me` sends at call `k`: to each rank with probability p, n bytes each, every
// byte a function of (sender, receiver, call, place); now and then one large buffer.
std::vector<std::vector<char>> pattern(int me, int size, int k, double p) {
  std::mt19937_64 rng(1000003u * static_cast<unsigned>(k) + 7919u * static_cast<unsigned>(me) + 1u);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<std::vector<char>> out(size);
  for (int r = 0; r < size; ++r) {
    if (!(U(rng) < p)) continue;
    const std::size_t n = U(rng) < 0.05 ? 3u << 20 : static_cast<std::size_t>(U(rng) * 5000.0);
    out[r].resize(n);
    for (std::size_t i = 0; i < n; ++i)
      out[r][i] = static_cast<char>((i * 131u + static_cast<std::size_t>(me) * 17u + static_cast<std::size_t>(r) * 29u +
                                     static_cast<std::size_t>(k) * 7u) & 0xffu);
  }
  return out;
}

}  // namespace

TEST(SparseExchange, EqualsAlltoallvOnRandomPatterns) {
  common::mpi::Comm& c = world();
  std::size_t messages = 0, bytes = 0;
  for (int k = 0; k < 60; ++k) {
    const double p = k % 3 == 0 ? 0.3 : 0.7;
    const std::vector<std::vector<char>> send = pattern(c.rank, c.size, k, p);
    // rank 0 held back before every 7th call: the others enter it (and send) first
    if (k % 7 == 3 && c.rank == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const double before_sparse = c.bytes_sent;
    const std::vector<std::vector<char>> got = c.sparse(send);
    const double sparse_bytes = c.bytes_sent - before_sparse;
    const double before_dense = c.bytes_sent;
    const std::vector<std::vector<char>> want = c.alltoallv(send);
    const double dense_bytes = c.bytes_sent - before_dense;
    EXPECT_EQ(got.size(), static_cast<std::size_t>(c.size));
    for (int r = 0; r < c.size && r < static_cast<int>(got.size()); ++r) {
      EXPECT_EQ(got[r], want[r]) << "call " << k << ", from rank " << r << " on rank " << c.rank;
      messages += got[r].empty() ? 0 : 1;
      bytes += got[r].size();
    }
    EXPECT_EQ(sparse_bytes, dense_bytes) << "call " << k;
  }
  // (the patterns are not empty: some messages and a large one arrived here)
  EXPECT_GT(messages, 20u);
  EXPECT_GT(bytes, std::size_t{3} << 20);
}

TEST(SparseExchange, NothingSentAndOnlyToSelf) {
  common::mpi::Comm& c = world();
  const std::vector<std::vector<char>> none(c.size);
  for (int k = 0; k < 5; ++k) {
    const std::vector<std::vector<char>> got = c.sparse(none);
    EXPECT_EQ(got.size(), static_cast<std::size_t>(c.size));
    for (const auto& b : got) EXPECT_TRUE(b.empty());
  }
  std::vector<std::vector<char>> self(c.size);
  self[c.rank] = {'a', 'b', static_cast<char>(c.rank)};
  const std::vector<std::vector<char>> got = c.sparse(self);
  for (int r = 0; r < c.size; ++r) EXPECT_EQ(got[r], r == c.rank ? self[c.rank] : std::vector<char>{});
}

// Consecutive calls with nothing in between (no collective that would hold the ranks together):
// a rank whose barrier completed first sends the next call's messages while others may still be
// probing in the previous call; every result still equals the pattern's alltoallv, taken after.
TEST(SparseExchange, BackToBackCallsKeepApart) {
  common::mpi::Comm& c = world();
  const int calls = 300;
  // small buffers to nearly everyone (no large one): calls short enough to overlap
  auto small = [&](int k) {
    std::vector<std::vector<char>> send = pattern(c.rank, c.size, 100 + k, 0.9);
    for (auto& b : send)
      if (b.size() > 64) b.resize(64);
    return send;
  };
  std::vector<std::vector<std::vector<char>>> got;
  for (int k = 0; k < calls; ++k) {
    if (k % 50 == 17 && c.rank == c.size - 1) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    got.push_back(c.sparse(small(k)));
  }
  for (int k = 0; k < calls; ++k) {
    const std::vector<std::vector<char>> want = c.alltoallv(small(k));
    for (int r = 0; r < c.size; ++r) EXPECT_EQ(got[k][r], want[r]) << "call " << k << ", from rank " << r;
  }
}
