/// @file work.cpp
/// What a rank's particles cost and need (mpm/mpi/domain.hpp): each particle's work weight
/// (work_weights: 1 plain unit plus its style's cost fields) and their sum, and the memory a
/// rank's box and particles need against its process limit and its node's memory
/// (DomainSolver::check_memory, the rebalancing's check).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "common/status.hpp"
#include "mpm/memory_bounds.hpp"
#include "mpm/mpi/domain.hpp"

namespace mpmfrag::mpi {

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
  const Box box = orb_.held(comm_.rank);
  const double nodes = static_cast<double>(box.size());
  double particles = 0;
  for (const MaterialSlot& m : mats) particles += static_cast<double>(m.end - m.begin);
  const MemoryRatio m = memory_ratio(nodes, process_bytes(nodes, mats) - 88.0 * nodes);
  if (!(m.ratio > 1.0)) return;
  const int worst = m.rank;
  const Box wb = orb_.own()[static_cast<std::size_t>(worst)];
  double w[6] = {nodes, particles, m.need, m.node_need, m.process, m.node};  // the worst rank's, on every rank
  MPI_Bcast(w, 6, MPI_DOUBLE, worst, comm_.c);
  char buf[720];
  std::snprintf(buf, sizeof buf,
                "grid.cell_size: MPI rank %d's box, cells [%d, %d) x [%d, %d) x [%d, %d) of %d x %d x %d with up to %d "
                "ghost nodes a side (the boxes balance particles or work, so a rank beside empty space holds more than its "
                "share of the grid), holds %.3g grid nodes and %.3g particles: %.3g GB, its node's ranks together %.3g GB; "
                "this process may use %.3g GB and the node offers %.3g GB. Use more ranks, fewer ranks per node, a "
                "smaller [grid] domain or a coarser cell_size",
                worst, wb.lo[0], wb.hi[0], wb.lo[1], wb.hi[1], wb.lo[2], wb.hi[2], grid_.shape[0], grid_.shape[1],
                grid_.shape[2], orb_.halo, w[0], w[1], w[2] / 1e9, w[3] / 1e9, w[4] / 1e9, w[5] / 1e9);
  throw common::InputError(buf);
}

}  // namespace mpmfrag::mpi
