/// @file test_mpm_mpi_halo.cpp
/// The sparse halo swap (mpm/src/mpi/halo.cpp, HaloExchange::sum_shared) against the dense sum
/// it replaces, under mpirun -np 2 and -np 3: each rank fills its box's nodes with partial sums
/// (a region with mass, nodes with a -0 in one field and nodes that are all +0 on one side only),
/// and after the swap every held node must equal, bit for bit, X = X^(r) + X^(r') computed
/// densely from every rank's partial values (allgathered here), for every field combination of
/// the passes (mass, momentum, force, and together). The bytes sent must be those of the nodes
/// that are not all +0.
#include <gtest/gtest.h>
#include <mpi.h>

#include <bit>
#include <cstring>

#include "common/rng.hpp"
#include "mpm/mpi/domain.hpp"

using namespace mpmfrag;

namespace {

int rank_of() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
int size_of() {
  int s = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}

// the partial value of global node (i, j, k), double d of the Node, on rank r
double partial(int r, int i, int j, int k, int d) {
  const bool body = j >= 2 && j < 6 && k >= 1 && k < 5;  // mass only in part of each plane
  if (!body) return (i + j + k + d) % 11 == 3 ? -0.0 : 0.0;  // -0 + -0 = -0: a -0 must travel
  if ((i + 2 * j + k + r) % 5 == 0) return 0.0;                             // all +0 on this rank
  common::KeyedRng g(static_cast<std::uint64_t>(r), static_cast<std::uint64_t>(((i * 16 + j) * 16 + k) * 8 + d));
  return g.normal();
}

}  // namespace

TEST(MpmMpiHalo, SparseSwapEqualsTheDenseSumBitForBit) {
  const int R = rank_of(), P = size_of();
  common::GridInfo g;
  g.shape = Eigen::Vector3i(6 * P + 2, 8, 7);
  mpi::Slabs sl;
  sl.axis = 0;
  sl.halo = 2;
  sl.min_width = 4;
  sl.cut.resize(P + 1);
  for (int r = 0; r <= P; ++r) sl.cut[r] = r == P ? g.shape[0] : 6 * r + (r > 0 ? 1 : 0);
  mpi::Comm comm(MPI_COMM_WORLD);
  mpi::HaloExchange halo(comm, sl, g);
  const Subdomain box = sl.box(R, g);
  const std::size_t n = static_cast<std::size_t>(box.shape.prod());
  auto idx = [&](int i, int j, int k) {
    return static_cast<std::size_t>(i - box.lo[0]) +
           static_cast<std::size_t>(box.shape[0]) * (static_cast<std::size_t>(j) + box.shape[1] * static_cast<std::size_t>(k));
  };
  for (int fields : {1, 2, 4, 3, 7}) {
    std::vector<Solver::Node> nodes(n);
    for (int k = 0; k < g.shape[2]; ++k)
      for (int j = 0; j < g.shape[1]; ++j)
        for (int i = box.lo[0]; i < box.lo[0] + box.shape[0]; ++i) {
          double* nd = reinterpret_cast<double*>(&nodes[idx(i, j, k)]);
          for (int d = 0; d < 8; ++d) nd[d] = partial(R, i, j, k, d);
        }
    const double before = halo.bytes_sent;
    halo.sum_shared(nodes.data(), fields);
    // dense reference: the doubles of the pass's fields summed with the neighbour's partial
    const int offs[3][2] = {{0, 1}, {1, 3}, {4, 3}};  // (offset, count) per field bit 1, 2, 4
    std::size_t bad = 0, expected_sent = 0;
    for (int k = 0; k < g.shape[2]; ++k)
      for (int j = 0; j < g.shape[1]; ++j)
        for (int i = box.lo[0]; i < box.lo[0] + box.shape[0]; ++i) {
          const double* nd = reinterpret_cast<const double*>(&nodes[idx(i, j, k)]);
          // the neighbour sharing plane i, if any (an overlap [P - H, P + H) around a cut P)
          int nb = -1;
          if (R > 0 && i < sl.cut[R] + sl.halo) nb = R - 1;
          if (R < P - 1 && i >= sl.cut[R + 1] - sl.halo) nb = R + 1;
          bool sent = false;
          for (int b = 0; b < 3; ++b)
            for (int c = 0; c < offs[b][1]; ++c) {
              const int d = offs[b][0] + c;
              const double mine = partial(R, i, j, k, d);
              double want = mine;
              if (nb >= 0 && (fields & (1 << b))) {
                want = mine + partial(nb, i, j, k, d);
                sent = sent || std::bit_cast<std::uint64_t>(mine) != 0;
              }
              if (std::bit_cast<std::uint64_t>(nd[d]) != std::bit_cast<std::uint64_t>(want)) ++bad;
            }
          if (sent) {
            int per = 0;
            for (int b = 0; b < 3; ++b)
              if (fields & (1 << b)) per += offs[b][1];
            expected_sent += 8 * (1 + per);
          }
        }
    EXPECT_EQ(bad, 0u) << "rank " << R << ", fields " << fields;
    EXPECT_EQ(halo.bytes_sent - before, static_cast<double>(expected_sent)) << "rank " << R << ", fields " << fields;
  }
}
