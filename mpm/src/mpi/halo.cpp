/// @file halo.cpp
/// Completion of the shared grid nodes after a P2G pass (mpm/mpi/domain.hpp, step 3): rank r
/// and each neighbour r' = r -+ 1 swap their partial sums of the pass's fields over the 2H
/// overlap planes [P - H, P + H) around their common cut P, and both set
///   X_i = X_i^(r) + X_i^(r')   (m_i, (m v)_i and/or f_i),
/// the same bits on both ranks (a single IEEE addition is commutative). The two overlaps of a
/// rank are disjoint (slabs are at least 2H planes wide), so the two swaps are independent.
/// Sparse: a rank sends only the overlap nodes whose pass fields are not all +0 (bit patterns:
/// a -0 is sent), each as its ordinal in the overlap (the nodes of planes [p0, p1) in memory
/// order, the same global nodes on both ranks) and its values; a node it did not send is +0 in
/// every field, so the receiver adds +0.0 to it, which is the dense sum's a + 0 bit for bit
/// (-0 + 0 = +0 included). Most of an impact grid's planes are empty: the halo shrinks to the
/// nodes with mass (plus 8 B of ordinal per node sent).
/// The velocity drives' node flags are swapped over the same planes (min_shared_drive), and
/// sum() is the drives' reduction of their reaction impulses.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <stdexcept>

#include "mpm/mpi/domain.hpp"

namespace mpmfrag::mpi {

namespace {
// doubles of a Node per field bit (1 mass, 2 momentum, 4 force) and their offsets in the Node
struct FieldRange {
  int bit, offset, n;
};
constexpr FieldRange kFields[3] = {{1, 0, 1}, {2, 1, 3}, {4, 4, 3}};
static_assert(sizeof(Solver::Node) == 8 * sizeof(double));

/// Visit the local indices of the nodes of global planes [p0, p1) along axis a of `box`, in
/// memory order.
template <class F>
void for_planes(const Subdomain& box, int a, int p0, int p1, F&& f) {
  int lo[3] = {0, 0, 0}, hi[3] = {box.shape[0], box.shape[1], box.shape[2]};
  lo[a] = p0 - box.lo[a];
  hi[a] = p1 - box.lo[a];
  const std::size_t sx = static_cast<std::size_t>(box.shape[0]), sy = static_cast<std::size_t>(box.shape[1]);
  for (int k = lo[2]; k < hi[2]; ++k)
    for (int j = lo[1]; j < hi[1]; ++j)
      for (int i = lo[0]; i < hi[0]; ++i)
        f(static_cast<std::size_t>(i) + sx * (static_cast<std::size_t>(j) + sy * static_cast<std::size_t>(k)));
}
}  // namespace

bool HaloExchange::overlap(int s, int& p0, int& p1) const {
  const int r = comm_.rank, nb = s == 0 ? r - 1 : r + 1;
  if (nb < 0 || nb >= comm_.size) return false;
  const int P = slabs_.cut[s == 0 ? r : r + 1], H = slabs_.halo;
  p0 = std::max(P - H, 0);
  p1 = std::min(P + H, grid_.shape[slabs_.axis]);
  return true;
}

template <class T, class Pack, class Unpack>
void HaloExchange::swap_overlaps(std::vector<T> (&send)[2], std::vector<T> (&recv)[2], MPI_Datatype type, int tag,
                                 Pack&& pack, Unpack&& unpack) {
  const int r = comm_.rank;
  MPI_Request req[4];
  int nreq = 0;
  for (int s = 0; s < 2; ++s) {
    int p0, p1;
    if (!overlap(s, p0, p1)) continue;
    send[s].clear();
    pack(p0, p1, send[s]);
    recv[s].resize(send[s].size());  // the neighbour holds the same planes: as many values
    const double bytes = static_cast<double>(sizeof(T) * send[s].size());
    bytes_sent += bytes;
    comm_.bytes_sent += bytes;
    const int nb = s == 0 ? r - 1 : r + 1, n = static_cast<int>(send[s].size());
    MPI_Irecv(recv[s].data(), n, type, nb, tag, comm_.c, &req[nreq++]);
    MPI_Isend(send[s].data(), n, type, nb, tag, comm_.c, &req[nreq++]);
  }
  MPI_Waitall(nreq, req, MPI_STATUSES_IGNORE);
  for (int s = 0; s < 2; ++s) {
    int p0, p1;
    if (overlap(s, p0, p1)) unpack(p0, p1, recv[s].data());
  }
}

void HaloExchange::sum_shared(Solver::Node* nodes, int fields) {
  if (comm_.size == 1) return;
  const int a = slabs_.axis, r = comm_.rank;
  const Subdomain box = slabs_.box(r, grid_);
  auto node = [&](std::size_t i) { return reinterpret_cast<double*>(nodes + i); };
  MPI_Request req[2];
  int nreq = 0;
  for (int s = 0; s < 2; ++s) {  // pack: (ordinal, values) of the nodes not all +0
    int p0, p1;
    if (!overlap(s, p0, p1)) continue;
    std::vector<double>& out = send_[s];
    out.clear();
    std::uint64_t k = 0;
    for_planes(box, a, p0, p1, [&](std::size_t i) {
      const double* nd = node(i);
      bool any = false;
      for (const FieldRange& f : kFields)
        if (fields & f.bit)
          for (int c = 0; c < f.n; ++c) any = any || std::bit_cast<std::uint64_t>(nd[f.offset + c]) != 0;
      if (any) {
        out.push_back(std::bit_cast<double>(k));
        for (const FieldRange& f : kFields)
          if (fields & f.bit) out.insert(out.end(), nd + f.offset, nd + f.offset + f.n);
      }
      ++k;
    });
    const double bytes = static_cast<double>(sizeof(double) * out.size());
    bytes_sent += bytes;
    comm_.bytes_sent += bytes;
    MPI_Isend(out.data(), static_cast<int>(out.size()), MPI_DOUBLE, s == 0 ? r - 1 : r + 1, 71, comm_.c, &req[nreq++]);
  }
  for (int s = 0; s < 2; ++s) {  // receive (sizes differ: probe) and add
    int p0, p1;
    if (!overlap(s, p0, p1)) continue;
    const int nb = s == 0 ? r - 1 : r + 1;
    MPI_Status st;
    MPI_Probe(nb, 71, comm_.c, &st);
    int n = 0;
    MPI_Get_count(&st, MPI_DOUBLE, &n);
    std::vector<double>& in = recv_[s];
    in.resize(static_cast<std::size_t>(n));
    MPI_Recv(in.data(), n, MPI_DOUBLE, nb, 71, comm_.c, MPI_STATUS_IGNORE);
    const double* e = in.data();
    const double* end = in.data() + in.size();
    std::ptrdiff_t per = 0;  // doubles per node sent
    for (const FieldRange& f : kFields)
      if (fields & f.bit) per += f.n;
    std::uint64_t k = 0;
    for_planes(box, a, p0, p1, [&](std::size_t i) {
      double* nd = node(i);
      const bool got = e < end && std::bit_cast<std::uint64_t>(*e) == k;
      if (got && end - e < 1 + per) throw std::logic_error("halo: a truncated sparse record from the neighbour");
      if (got) ++e;
      for (const FieldRange& f : kFields)
        if (fields & f.bit)
          for (int c = 0; c < f.n; ++c) nd[f.offset + c] += got ? *e++ : 0.0;
      ++k;
    });
    if (e != end) throw std::logic_error("halo: the neighbour's sparse record does not match the overlap");
  }
  MPI_Waitall(nreq, req, MPI_STATUSES_IGNORE);
}

void HaloExchange::min_shared_drive(std::int32_t* node_drive, std::vector<std::size_t>& added) {
  if (comm_.size == 1) return;
  const int a = slabs_.axis;
  const Subdomain box = slabs_.box(comm_.rank, grid_);
  swap_overlaps(
      isend_, irecv_, MPI_INT32_T, 72,
      [&](int p0, int p1, std::vector<std::int32_t>& out) {
        for_planes(box, a, p0, p1, [&](std::size_t i) { out.push_back(node_drive[i]); });
      },
      [&](int p0, int p1, const std::int32_t* in) {
        for_planes(box, a, p0, p1, [&](std::size_t i) {
          const std::int32_t theirs = *in++;
          std::int32_t& mine = node_drive[i];
          if (theirs < 0 || (mine >= 0 && mine <= theirs)) return;
          if (mine < 0) added.push_back(i);
          mine = theirs;
        });
      });
}

void HaloExchange::sum(double* v, int n) {
  const std::vector<double> all = comm_.allgather(v, n);
  for (int k = 0; k < n; ++k) v[k] = 0.0;
  for (int q = 0; q < comm_.size; ++q)
    for (int k = 0; k < n; ++k) v[k] += all[static_cast<std::size_t>(q) * n + k];
}

}  // namespace mpmfrag::mpi
