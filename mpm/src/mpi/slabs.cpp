/// @file slabs.cpp
/// Slab decomposition of the background grid (mpm/mpi/domain.hpp): cuts balancing the particle
/// count or the work (work_weights) per rank: with P* = min { P : sum_{c < P} n(c) >= r N / R }, the cut P_r is whichever of
/// P* - 1 and P* leaves the cumulative count nearer r N / R (P* on a tie), every slab at least W
/// planes wide, the owner of a cell, and the box (owned planes plus H ghost planes per side,
/// clipped to the grid) a rank holds, and the memory that box and its particles need
/// (DomainSolver::check_memory).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "common/status.hpp"
#include "mpm/memory_bounds.hpp"
#include "mpm/mpi/domain.hpp"

namespace mpmfrag::mpi {

int Slabs::owner(int c) const {
  // the last r with cut[r] <= c
  const auto it = std::upper_bound(cut.begin() + 1, cut.end() - 1, c);
  return static_cast<int>(it - cut.begin()) - 1;
}

Subdomain Slabs::box(int r, const common::GridInfo& g) const {
  Subdomain s;
  s.shape = g.shape;
  const int lo = std::max(0, cut[r] - halo), hi = std::min(g.shape[axis], cut[r + 1] + halo);
  s.lo[axis] = lo;
  s.shape[axis] = hi - lo;
  s.own_axis = axis;
  s.own_lo = cut[r];
  s.own_hi = cut[r + 1];
  return s;
}

std::vector<int> balanced_cuts(const std::vector<long long>& count, int ranks, int min_width) {
  const int planes = static_cast<int>(count.size());
  if (ranks < 1 || planes < ranks * min_width)
    throw common::InputError("the grid has " + std::to_string(planes) + " node planes along its longest axis: at most " +
                             std::to_string(planes / min_width) + " MPI ranks (" + std::to_string(min_width) +
                             " planes per rank), not " + std::to_string(ranks) + "; use fewer ranks or a finer [grid] cell_size");
  long long total = 0;
  for (long long n : count) total += n;
  std::vector<int> cut(ranks + 1, 0);
  cut[ranks] = planes;
  long long cum = 0;
  int c = 0;
  for (int r = 1; r < ranks; ++r) {
    // smallest P with sum_{c < P} n(c) >= r N / R (integer test: R * cum >= r * N), then the
    // nearer of it and P - 1: where one plane holds much of the count (a thin shocked shell on a
    // coarse grid) the first crossing can overshoot the target by most of that plane
    while (c < planes && static_cast<__int128>(cum) * ranks < static_cast<__int128>(total) * r) cum += count[c++];
    int pick = c;
    if (c > 0) {
      const __int128 target = static_cast<__int128>(total) * r;
      const __int128 over = static_cast<__int128>(cum) * ranks - target;
      const __int128 under = target - static_cast<__int128>(cum - count[c - 1]) * ranks;
      if (under < over) pick = c - 1;
    }
    cut[r] = std::clamp(pick, cut[r - 1] + min_width, planes - (ranks - r) * min_width);
  }
  return cut;
}

namespace {
/// add(p, c) for every particle p with a cost c = round(kWorkUnit work_f min(s_{f,p}, 1e9)) > 0
/// of a cost field f of its material's style (work_weights).
template <class Add>
void each_cost(const std::vector<MaterialSlot>& mats, Add&& add) {
  for (const MaterialSlot& m : mats)
    for (std::size_t f = 0; f < m.style->state_fields.size(); ++f) {
      const StateField& sf = m.style->state_fields[f];
      if (!(sf.work > 0.0)) continue;
      const double* s = m.state[f].data();  // one component (StateField::work)
      for (std::size_t p = m.begin; p < m.end; ++p)
        if (const double v = s[p - m.begin]; v > 0.0)  // NaN and negative: 0
          add(p, std::llround(static_cast<double>(kWorkUnit) * sf.work * std::min(v, 1e9)));
    }
}
}  // namespace

std::vector<long long> work_weights(const ParticleSet& ps, const std::vector<MaterialSlot>& mats) {
  std::vector<long long> w(ps.size(), kWorkUnit);
  each_cost(mats, [&](std::size_t p, long long c) { w[p] += c; });
  return w;
}

long long total_work(const ParticleSet& ps, const std::vector<MaterialSlot>& mats) {
  long long t = kWorkUnit * static_cast<long long>(ps.size());
  each_cost(mats, [&](std::size_t, long long c) { t += c; });
  return t;
}

DomainSolver::MemoryRatio DomainSolver::memory_ratio(double nodes, double bytes) const {
  MemoryRatio m;
  const double need = 88.0 * nodes + bytes;  // process_bytes' grid term
  MPI_Comm node;
  MPI_Comm_split_type(comm_.c, MPI_COMM_TYPE_SHARED, comm_.rank, MPI_INFO_NULL, &node);
  double node_need = need;
  MPI_Allreduce(MPI_IN_PLACE, &node_need, 1, MPI_DOUBLE, MPI_SUM, node);
  MPI_Comm_free(&node);
  const double proc = opt_.process_memory >= 0 ? opt_.process_memory : process_memory_limit();
  const double avail = opt_.node_memory >= 0 ? opt_.node_memory : mpmfrag::node_memory();
  // the rank most over its limit (by the larger of its two ratios), the same on every rank
  struct {
    double ratio;
    int rank;
  } worst{std::max(need / proc, node_need / avail), comm_.rank};
  MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm_.c);
  m.ratio = worst.ratio;
  m.rank = worst.rank;
  m.need = need;
  m.node_need = node_need;
  m.process = proc;
  m.node = avail;
  return m;
}

void DomainSolver::check_memory(const std::vector<MaterialSlot>& mats) const {
  const Subdomain box = slabs_.box(comm_.rank, grid_);
  const double nodes = static_cast<double>(box.shape.cast<double>().prod());
  double particles = 0;
  for (const MaterialSlot& m : mats) particles += static_cast<double>(m.end - m.begin);
  const MemoryRatio m = memory_ratio(nodes, process_bytes(nodes, mats) - 88.0 * nodes);
  if (!(m.ratio > 1.0)) return;
  const int worst = m.rank;
  double w[6] = {nodes, particles, m.need, m.node_need, m.process, m.node};  // the worst rank's, on every rank
  MPI_Bcast(w, 6, MPI_DOUBLE, worst, comm_.c);
  char buf[640];
  std::snprintf(buf, sizeof buf,
                "grid.cell_size: MPI rank %d's slab, node planes [%d, %d) of %d along axis %d with up to %d ghost "
                "planes a side (the slabs balance particles or work, so a rank beside empty space holds more than its share "
                "of the grid), holds %.3g grid nodes and %.3g particles: %.3g GB, its node's ranks together %.3g GB; this "
                "process may use %.3g GB and the node offers %.3g GB. Use more ranks, fewer ranks per node, a "
                "smaller [grid] domain or a coarser cell_size",
                worst, slabs_.cut[worst], slabs_.cut[worst + 1], grid_.shape[slabs_.axis], slabs_.axis,
                slabs_.halo,
                w[0], w[1], w[2] / 1e9, w[3] / 1e9, w[4] / 1e9, w[5] / 1e9);
  throw common::InputError(buf);
}

}  // namespace mpmfrag::mpi
