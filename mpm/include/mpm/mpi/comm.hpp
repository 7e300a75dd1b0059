/// @file comm.hpp
/// Thin helpers over MPI for the domain decomposition of mpm-frag (MPI build only, SUITE_MPI=ON),
/// after the pattern of ssdem-grav's (nbody/include/ssdem/mpi/comm.hpp): byte alltoallv and
/// gatherv of packed records, placed by sender rank in the sender's order (never by arrival
/// order), and a running count of the bytes this rank sent (communication volume).
#pragma once
#include <mpi.h>

#include <cstring>
#include <vector>

namespace mpmfrag::mpi {

/// One communicator with its rank and size and the bytes this rank has sent.
struct Comm {
  MPI_Comm c = MPI_COMM_WORLD;
  int rank = 0, size = 1;
  double bytes_sent = 0;  ///< payload sent to other ranks [B]
  explicit Comm(MPI_Comm comm = MPI_COMM_WORLD) : c(comm) {
    MPI_Comm_rank(c, &rank);
    MPI_Comm_size(c, &size);
  }

  /// Byte buffers per destination rank -> byte buffers per source rank.
  std::vector<std::vector<char>> alltoallv(const std::vector<std::vector<char>>& send) {
    std::vector<int> sc(size), rc(size), sd(size), rd(size);
    std::size_t tot = 0;
    for (int r = 0; r < size; ++r) {
      sc[r] = static_cast<int>(send[r].size());
      sd[r] = static_cast<int>(tot);
      tot += send[r].size();
      if (r != rank) bytes_sent += static_cast<double>(send[r].size());
    }
    MPI_Alltoall(sc.data(), 1, MPI_INT, rc.data(), 1, MPI_INT, c);
    std::vector<char> sb(tot);
    for (int r = 0; r < size; ++r)
      if (!send[r].empty()) std::memcpy(sb.data() + sd[r], send[r].data(), send[r].size());
    std::size_t rtot = 0;
    for (int r = 0; r < size; ++r) {
      rd[r] = static_cast<int>(rtot);
      rtot += static_cast<std::size_t>(rc[r]);
    }
    std::vector<char> rb(rtot);
    MPI_Alltoallv(sb.data(), sc.data(), sd.data(), MPI_BYTE, rb.data(), rc.data(), rd.data(), MPI_BYTE, c);
    std::vector<std::vector<char>> out(size);
    for (int r = 0; r < size; ++r) out[r].assign(rb.begin() + rd[r], rb.begin() + rd[r] + rc[r]);
    return out;
  }

  /// Each rank's bytes, per source rank, on `root` (empty elsewhere).
  std::vector<std::vector<char>> gather(const std::vector<char>& mine, int root) {
    const int nb = static_cast<int>(mine.size());
    std::vector<int> rc(size), rd(size);
    MPI_Gather(&nb, 1, MPI_INT, rc.data(), 1, MPI_INT, root, c);
    std::size_t tot = 0;
    for (int r = 0; r < size; ++r) {
      rd[r] = static_cast<int>(tot);
      tot += static_cast<std::size_t>(rc[r]);
    }
    std::vector<char> rb(rank == root ? tot : 0);
    if (rank != root) bytes_sent += nb;
    MPI_Gatherv(mine.data(), nb, MPI_BYTE, rb.data(), rc.data(), rd.data(), MPI_BYTE, root, c);
    std::vector<std::vector<char>> out(rank == root ? size : 0);
    for (std::size_t r = 0; r < out.size(); ++r) out[r].assign(rb.begin() + rd[r], rb.begin() + rd[r] + rc[r]);
    return out;
  }

  /// Every rank's n doubles, concatenated in rank order, on every rank.
  std::vector<double> allgather(const double* v, int n) {
    std::vector<double> out(static_cast<std::size_t>(n) * size);
    bytes_sent += 8.0 * n * (size - 1);
    MPI_Allgather(v, n, MPI_DOUBLE, out.data(), n, MPI_DOUBLE, c);
    return out;
  }

  /// Element-wise maximum over the ranks, in place (exact: the same bits on every rank).
  void max(double* v, int n) { MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_DOUBLE, MPI_MAX, c); }
  /// Element-wise integer sum over the ranks, in place (exact).
  void sum(long long* v, int n) { MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_LONG_LONG, MPI_SUM, c); }
};

/// Append the bytes of a plain value to a buffer / read one back.
template <class T>
void put(std::vector<char>& b, const T& v) {
  const std::size_t o = b.size();
  b.resize(o + sizeof(T));
  std::memcpy(b.data() + o, &v, sizeof(T));
}
template <class T>
T get(const std::vector<char>& b, std::size_t& off) {
  T v;
  std::memcpy(static_cast<void*>(&v), b.data() + off, sizeof(T));
  off += sizeof(T);
  return v;
}

}  // namespace mpmfrag::mpi
