/// @file halo.cpp
/// Completion of the shared grid nodes after a P2G pass (mpm/mpi/domain.hpp, step 3): rank r
/// and each neighbour r' = r -+ 1 swap their partial sums of the pass's fields over the 2H
/// overlap planes [P - H, P + H) around their common cut P, and both set
///   X_i = X_i^(r) + X_i^(r')   (m_i, (m v)_i and/or f_i),
/// the same bits on both ranks (a single IEEE addition is commutative). The two overlaps of a
/// rank are disjoint (slabs are at least 2H planes wide), so the two swaps are independent.
#include <algorithm>

#include "mpm/mpi/domain.hpp"

namespace mpmfrag::mpi {

namespace {
// doubles of a Node per field bit (1 mass, 2 momentum, 4 force) and their offsets in the Node
struct FieldRange {
  int bit, offset, n;
};
constexpr FieldRange kFields[3] = {{1, 0, 1}, {2, 1, 3}, {4, 4, 3}};
static_assert(sizeof(Solver::Node) == 8 * sizeof(double));
}  // namespace

void HaloExchange::sum_shared(Solver::Node* nodes, int fields) {
  const int r = comm_.rank, R = comm_.size;
  if (R == 1) return;
  const int a = slabs_.axis, H = slabs_.halo;
  const Subdomain box = slabs_.box(r, grid_);
  // the overlap with neighbour side s (0: r-1, 1: r+1) in global planes [p0, p1)
  auto overlap = [&](int s, int& p0, int& p1) {
    const int P = slabs_.cut[s == 0 ? r : r + 1];
    p0 = std::max(P - H, 0);
    p1 = std::min(P + H, grid_.shape[a]);
  };
  // visit the nodes of planes [p0, p1) of the box in memory order
  auto for_nodes = [&](int p0, int p1, auto&& f) {
    int lo[3] = {0, 0, 0}, hi[3] = {box.shape[0], box.shape[1], box.shape[2]};
    lo[a] = p0 - box.lo[a];
    hi[a] = p1 - box.lo[a];
    for (int k = lo[2]; k < hi[2]; ++k)
      for (int j = lo[1]; j < hi[1]; ++j)
        for (int i = lo[0]; i < hi[0]; ++i)
          f(reinterpret_cast<double*>(nodes + (static_cast<std::size_t>(i) +
                                               static_cast<std::size_t>(box.shape[0]) *
                                                   (static_cast<std::size_t>(j) + static_cast<std::size_t>(box.shape[1]) * k))));
  };
  MPI_Request req[4];
  int nreq = 0;
  for (int s = 0; s < 2; ++s) {
    const int nb = s == 0 ? r - 1 : r + 1;
    if (nb < 0 || nb >= R) continue;
    int p0, p1;
    overlap(s, p0, p1);
    std::vector<double>& out = send_[s];
    out.clear();
    for_nodes(p0, p1, [&](const double* nd) {
      for (const FieldRange& f : kFields)
        if (fields & f.bit) out.insert(out.end(), nd + f.offset, nd + f.offset + f.n);
    });
    recv_[s].resize(out.size());
    bytes_sent += 8.0 * out.size();
    comm_.bytes_sent += 8.0 * out.size();
    MPI_Irecv(recv_[s].data(), static_cast<int>(out.size()), MPI_DOUBLE, nb, 71, comm_.c, &req[nreq++]);
    MPI_Isend(out.data(), static_cast<int>(out.size()), MPI_DOUBLE, nb, 71, comm_.c, &req[nreq++]);
  }
  MPI_Waitall(nreq, req, MPI_STATUSES_IGNORE);
  for (int s = 0; s < 2; ++s) {
    const int nb = s == 0 ? r - 1 : r + 1;
    if (nb < 0 || nb >= R) continue;
    int p0, p1;
    overlap(s, p0, p1);
    const double* in = recv_[s].data();
    for_nodes(p0, p1, [&](double* nd) {
      for (const FieldRange& f : kFields)
        if (fields & f.bit)
          for (int c = 0; c < f.n; ++c) nd[f.offset + c] += *in++;
    });
  }
}

}  // namespace mpmfrag::mpi
