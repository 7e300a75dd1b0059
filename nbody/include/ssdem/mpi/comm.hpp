/// @file comm.hpp
/// Thin typed helpers over MPI for the domain decomposition of ssdem-grav (MPI build only,
/// SUITE_MPI=ON). Every exchange is a byte alltoallv / allgatherv of trivially copyable records;
/// the helpers count the bytes each rank sends (communication volume per step, nbody/README.md).
/// Determinism: results are placed by sender rank, in the sender's order, never by arrival order.
#pragma once
#include <mpi.h>

#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

namespace ssdem::mpi {

/// One communicator with its rank and size, and a running count of the bytes this rank sent.
struct Comm {
  MPI_Comm c = MPI_COMM_WORLD;
  int rank = 0, size = 1;
  double bytes_sent = 0;  ///< point-to-point and collective payload sent by this rank [B]
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

  /// Every rank's vector, concatenated in rank order, on every rank (root < 0) or on `root`.
  template <class T>
  std::vector<T> gather(const std::vector<T>& mine, int root = -1, std::vector<int>* counts = nullptr) {
    static_assert(std::is_trivially_copyable_v<T>);
    const int nb = static_cast<int>(mine.size() * sizeof(T));
    std::vector<int> rc(size), rd(size);
    if (root < 0)
      MPI_Allgather(&nb, 1, MPI_INT, rc.data(), 1, MPI_INT, c);
    else
      MPI_Gather(&nb, 1, MPI_INT, rc.data(), 1, MPI_INT, root, c);
    std::size_t tot = 0;
    for (int r = 0; r < size; ++r) {
      rd[r] = static_cast<int>(tot);
      tot += static_cast<std::size_t>(rc[r]);
    }
    std::vector<T> out(root < 0 || root == rank ? tot / sizeof(T) : 0);
    if (root < 0) {
      bytes_sent += static_cast<double>(nb) * (size - 1);
      MPI_Allgatherv(mine.data(), nb, MPI_BYTE, out.data(), rc.data(), rd.data(), MPI_BYTE, c);
    } else {
      if (rank != root) bytes_sent += nb;
      MPI_Gatherv(mine.data(), nb, MPI_BYTE, out.data(), rc.data(), rd.data(), MPI_BYTE, root, c);
    }
    if (counts) {
      counts->resize(size);
      for (int r = 0; r < size; ++r) (*counts)[r] = rc[r] / static_cast<int>(sizeof(T));
    }
    return out;
  }

  /// Largest value over the ranks.
  double max(double v) {
    double o = 0;
    MPI_Allreduce(&v, &o, 1, MPI_DOUBLE, MPI_MAX, c);
    return o;
  }
};

/// Append the bytes of a plain value (arithmetic, fixed-size Eigen vector, HistoryRecord: no
/// pointers) to a buffer / read one back.
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

}  // namespace ssdem::mpi
