/// @file mpi_comm.hpp
/// Thin helpers over MPI shared by the domain decompositions of ssdem-grav (nbody/src/mpi) and
/// mpm-frag (mpm/src/mpi); MPI build only (SUITE_MPI=ON, target common_mpi: the serial build
/// neither sees nor links it). Every exchange moves bytes of trivially copyable records:
/// alltoallv, a sparse exchange of unknown sizes (sparse), point-to-point halos of known sizes
/// (neighbours), gather / allgather, exact
/// reductions (max, integer sum), and put / get of plain
/// values into byte buffers. The helpers count the bytes this rank sends (communication volume).
/// Determinism: results are placed by sender rank, in the sender's order, never by arrival order.
#pragma once
#include <mpi.h>

#include <climits>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace common::mpi {

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
    std::vector<char> rb(offsets(rc, rd));
    MPI_Alltoallv(sb.data(), sc.data(), sd.data(), MPI_BYTE, rb.data(), rc.data(), rd.data(), MPI_BYTE, c);
    return split(rb, rc, rd);
  }

  /// Byte buffers per destination rank -> byte buffers per source rank, as alltoallv (the same
  /// result, placed by sender rank), for sparse patterns in which each rank sends to a few others
  /// and no receiver knows who sends: the NBX protocol (Hoefler, Siebert & Lumsdaine 2010,
  /// "Scalable communication protocols for dynamic sparse data exchange", PPoPP, section 3).
  /// Synchronous sends (MPI_Issend) to the ranks with data; every message probed is received;
  /// once this rank's sends are all matched it enters a non-blocking barrier, and when the barrier
  /// completes every rank's sends have been received. Per rank O(its messages + log P), against
  /// alltoallv's all-to-all of P counts (O(P) per rank and call, whatever the pattern). Two
  /// alternating tags keep consecutive calls apart: a rank cannot run two calls ahead of another,
  /// since the barrier of its next call needs the other's entry. Collective: every rank calls it,
  /// the same number of times, through one Comm object per MPI communicator (the tag counter is
  /// the object's; calls through two objects on one communicator need a blocking collective
  /// between them). The communication is O(messages + log P) per rank; the buffers per rank are
  /// still P entries of local work. A message over INT_MAX bytes throws before anything is sent.
  std::vector<std::vector<char>> sparse(const std::vector<std::vector<char>>& send) {
    for (int r = 0; r < size; ++r)
      if (send[r].size() > static_cast<std::size_t>(INT_MAX))
        throw std::length_error("common::mpi::Comm::sparse: a message of " + std::to_string(send[r].size()) +
                                " bytes (at most INT_MAX)");
    const int tag = kSparseTag + static_cast<int>(sparse_calls_++ & 1u);
    std::vector<std::vector<char>> recv(size);
    std::vector<MPI_Request> sends;
    for (int r = 0; r < size; ++r) {
      if (send[r].empty()) continue;
      if (r == rank) {
        recv[r] = send[r];
        continue;
      }
      bytes_sent += static_cast<double>(send[r].size());
      sends.emplace_back();
      MPI_Issend(send[r].data(), static_cast<int>(send[r].size()), MPI_BYTE, r, tag, c, &sends.back());
    }
    MPI_Request barrier = MPI_REQUEST_NULL;
    bool in_barrier = false;
    for (;;) {
      int flag = 0;
      MPI_Message msg;
      MPI_Status st;
      MPI_Improbe(MPI_ANY_SOURCE, tag, c, &flag, &msg, &st);
      if (flag) {  // (one message per sender and call)
        int n = 0;
        MPI_Get_count(&st, MPI_BYTE, &n);
        std::vector<char>& b = recv[st.MPI_SOURCE];
        b.resize(static_cast<std::size_t>(n));
        MPI_Mrecv(b.data(), n, MPI_BYTE, &msg, MPI_STATUS_IGNORE);
        continue;
      }
      int done = 0;
      if (!in_barrier) {
        MPI_Testall(static_cast<int>(sends.size()), sends.data(), &done, MPI_STATUSES_IGNORE);
        if (done) {
          MPI_Ibarrier(c, &barrier);
          in_barrier = true;
        }
      } else {
        MPI_Test(&barrier, &done, MPI_STATUS_IGNORE);
        if (done) break;
      }
    }
    return recv;
  }

  /// Byte buffers per destination rank -> byte buffers per source rank, where each receiver knows
  /// how many bytes each sender sends (recv_bytes[r]; a halo with fixed send and receive lists):
  /// point-to-point messages to and from those ranks only (no collective; O(neighbours) per rank).
  std::vector<std::vector<char>> neighbours(const std::vector<std::vector<char>>& send,
                                            const std::vector<std::size_t>& recv_bytes) {
    std::vector<std::vector<char>> recv(size);
    std::vector<MPI_Request> req;
    req.reserve(2 * static_cast<std::size_t>(size));
    for (int r = 0; r < size; ++r)
      if (r != rank && recv_bytes[r] > 0) {
        recv[r].resize(recv_bytes[r]);
        req.emplace_back();
        MPI_Irecv(recv[r].data(), static_cast<int>(recv_bytes[r]), MPI_BYTE, r, kHaloTag, c, &req.back());
      }
    for (int r = 0; r < size; ++r)
      if (r != rank && !send[r].empty()) {
        bytes_sent += static_cast<double>(send[r].size());
        req.emplace_back();
        MPI_Isend(send[r].data(), static_cast<int>(send[r].size()), MPI_BYTE, r, kHaloTag, c, &req.back());
      }
    MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
    return recv;
  }

  /// Every rank's vector, concatenated in rank order, on every rank (root < 0) or on `root`
  /// (empty elsewhere); `counts`: the elements from each rank.
  template <class T>
  std::vector<T> gather(const std::vector<T>& mine, int root = -1, std::vector<int>* counts = nullptr) {
    static_assert(std::is_trivially_copyable_v<T>);
    std::vector<int> rc, rd;
    const std::vector<char> b = gather_bytes(mine.data(), mine.size() * sizeof(T), root, rc, rd);
    std::vector<T> out(b.size() / sizeof(T));
    if (!b.empty()) std::memcpy(static_cast<void*>(out.data()), b.data(), b.size());
    if (counts) {
      counts->resize(size);
      for (int r = 0; r < size; ++r) (*counts)[r] = rc[r] / static_cast<int>(sizeof(T));
    }
    return out;
  }
  /// Each rank's bytes, one buffer per source rank, on `root` (no buffers elsewhere).
  std::vector<std::vector<char>> gather_per_rank(const std::vector<char>& mine, int root) {
    std::vector<int> rc, rd;
    const std::vector<char> b = gather_bytes(mine.data(), mine.size(), root, rc, rd);
    if (rank != root) return {};
    return split(b, rc, rd);
  }
  /// Every rank's n doubles, concatenated in rank order, on every rank.
  std::vector<double> allgather(const double* v, int n) {
    return gather(std::vector<double>(v, v + n));
  }

  /// Largest value over the ranks (exact: the same bits on every rank).
  double max(double v) {
    max(&v, 1);
    return v;
  }
  /// Element-wise maximum over the ranks, in place (exact).
  void max(double* v, int n) { MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_DOUBLE, MPI_MAX, c); }
  /// Element-wise integer sum over the ranks, in place (exact).
  void sum(long long* v, int n) { MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_LONG_LONG, MPI_SUM, c); }
  /// True on every rank iff `ok` on every rank (a failure every rank acts on together).
  bool all(bool ok) {
    int v = ok ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_INT, MPI_MIN, c);
    return v == 1;
  }
  /// `root`'s string on every rank.
  std::string bcast(std::string s, int root = 0) {
    long long n = static_cast<long long>(s.size());
    MPI_Bcast(&n, 1, MPI_LONG_LONG, root, c);
    s.resize(static_cast<std::size_t>(n));
    MPI_Bcast(s.data(), static_cast<int>(n), MPI_CHAR, root, c);
    return s;
  }

 private:
  static constexpr int kHaloTag = 7101;    ///< tag of neighbours() (collectives use no tags)
  static constexpr int kSparseTag = 7102;  ///< tags of sparse(): 7102 and 7103, alternating
  unsigned sparse_calls_ = 0;
  /// Displacements rd of the counts rc; returns the total.
  static std::size_t offsets(const std::vector<int>& rc, std::vector<int>& rd) {
    std::size_t tot = 0;
    rd.resize(rc.size());
    for (std::size_t r = 0; r < rc.size(); ++r) {
      rd[r] = static_cast<int>(tot);
      tot += static_cast<std::size_t>(rc[r]);
    }
    return tot;
  }
  static std::vector<std::vector<char>> split(const std::vector<char>& b, const std::vector<int>& rc,
                                              const std::vector<int>& rd) {
    std::vector<std::vector<char>> out(rc.size());
    for (std::size_t r = 0; r < rc.size(); ++r) out[r].assign(b.begin() + rd[r], b.begin() + rd[r] + rc[r]);
    return out;
  }
  /// Gather nb bytes of every rank on every rank (root < 0) or on `root`; rc, rd: byte counts
  /// and displacements per source rank (valid where the result is).
  std::vector<char> gather_bytes(const void* mine, std::size_t bytes, int root, std::vector<int>& rc, std::vector<int>& rd) {
    const int nb = static_cast<int>(bytes);
    rc.assign(size, 0);
    if (root < 0)
      MPI_Allgather(&nb, 1, MPI_INT, rc.data(), 1, MPI_INT, c);
    else
      MPI_Gather(&nb, 1, MPI_INT, rc.data(), 1, MPI_INT, root, c);
    const std::size_t tot = offsets(rc, rd);
    std::vector<char> out(root < 0 || root == rank ? tot : 0);
    if (root < 0) {
      bytes_sent += static_cast<double>(nb) * (size - 1);
      MPI_Allgatherv(mine, nb, MPI_BYTE, out.data(), rc.data(), rd.data(), MPI_BYTE, c);
    } else {
      if (rank != root) bytes_sent += nb;
      MPI_Gatherv(mine, nb, MPI_BYTE, out.data(), rc.data(), rd.data(), MPI_BYTE, root, c);
    }
    return out;
  }
};

/// Append the bytes of a plain value (arithmetic, fixed-size Eigen vector, records without
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

}  // namespace common::mpi
