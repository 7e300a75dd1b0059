/// @file checkpoint_write_mpi.cpp
/// Writing mpm-frag checkpoints on MPI ranks (layout and contract in mpm/mpi/checkpoint_mpi.hpp):
/// every rank writes its block of the file's rows with collective parallel HDF5; no rank holds
/// every particle. Reading is in checkpoint_mpi.cpp.
#include <algorithm>
#include <numeric>

#include "common/agreed.hpp"
#include "common/finite.hpp"
#include "common/h5_parallel.hpp"
#include "common/particle_file_mpi.hpp"
#include "mpm/checkpoint_rows.hpp"
#include "mpm/mpi/checkpoint_mpi.hpp"
#include "mpm/mpi/snapshot_mpi.hpp"
#include "mpm/output.hpp"

namespace mpmfrag::mpi {

namespace {
namespace h5 = common::h5;
using common::mpi::RowKey;
using common::mpi::SortedRows;

/// Bytes of one row of every ParticleSet array (the optional ones if `optional`).
std::size_t set_row_bytes(bool optional) {
  std::size_t b = 0;
  ParticleSet::for_each_array([&](const auto& a) {
    using T = typename std::decay_t<decltype(a)>::element_type;
    if (!a.info.optional || optional) b += sizeof(T) * static_cast<std::size_t>(a.info.width);
  });
  return b;
}

/// The outflow record moved to this rank's block of the file's rows (sorted by (removal time, id)
/// across the ranks, outflow_keys) in r.outflow, outflow_time and outflow_fields, with the field
/// list merged over the ranks and the totals on every rank (DomainSolver::local_outflow): no rank
/// holds the whole record. Sets `rows`' outflow block and flag; returns the rank totals.
std::vector<double> outflow_block(DomainSolver& dom, SolverResume& r, CheckpointRows& rows) {
  Comm& comm = dom.comm();
  OutflowRecord out = dom.local_outflow();
  const SortedRows plan(comm, outflow_keys(out));
  rows.outflow_optional = !comm.all(!uses_optional_arrays(out.ps));
  r.outflow = ParticleSet{};
  ParticleSet::for_each_array([&](const auto& a) {
    if (!a.info.optional || rows.outflow_optional)
      r.outflow.*a.member = plan.move((out.ps.*a.member).data(), static_cast<std::size_t>(a.info.width));
  });
  r.outflow_time = plan.move(out.time, 1);
  for (common::Field& f : out.fields) f.values = plan.move(f.values, f.ncomp);
  r.outflow_fields = std::move(out.fields);
  r.outflow_init = std::move(out.init);
  r.outflow_totals = out.totals;
  rows.outflow_first = plan.offset();
  rows.outflow_total = plan.total();
  return out.rank_totals;
}
}  // namespace

void write_checkpoint_mpi(DomainSolver& dom, const std::string& path, const DriverState& driver,
                          const common::Provenance& prov, const std::string& identity) {
  Comm& comm = dom.comm();
  const Solver& s = dom.local();
  const ParticleSet& ps = s.particles();
  const std::vector<MaterialSlot>& mats = s.materials();
  SolverResume r = s.resume_state();  // the scalars: global reductions, the same bits on every rank
  const common::ParticleSnapshot local = make_snapshot(ps, mats, s.grid(), r.time, r.step);
  common::mpi::agreed(comm, [&] { common::check_output_particles(local, path); });  // exit 3, nothing written
  // the file's order: materials in slot order, ids ascending (as the serial checkpoint)
  std::vector<RowKey> keys(ps.size());
  for (std::size_t m = 0; m < mats.size(); ++m)
    for (std::size_t p = mats[m].begin; p < mats[m].end; ++p) keys[p] = {m, ps.id[p]};
  const SortedRows plan(comm, keys);
  const common::ParticleSnapshot snap = common::mpi::sorted_block(comm, plan, local, path);
  const bool optional = !comm.all(!uses_optional_arrays(ps));
  ParticleSet set;
  ParticleSet::for_each_array([&](const auto& a) {
    if (!a.info.optional || optional) set.*a.member = plan.move((ps.*a.member).data(), static_cast<std::size_t>(a.info.width));
  });
  const std::vector<std::int32_t> rank = plan.move(std::vector<std::int32_t>(ps.size(), comm.rank), 1);
  std::vector<std::uint64_t> index(ps.size());
  std::iota(index.begin(), index.end(), std::uint64_t{0});
  index = plan.move(index, 1);
  // each material's state: the rows of its own order (ids ascending), block by block
  std::vector<MaterialSlot> slots(mats.size());
  std::vector<std::pair<std::size_t, std::size_t>> slot_rows(mats.size());  // (offset, total)
  std::size_t begin = 0, state_bytes = 0;
  for (std::size_t m = 0; m < mats.size(); ++m) {
    std::vector<RowKey> mk;
    for (std::size_t p = mats[m].begin; p < mats[m].end; ++p) mk.push_back({0, ps.id[p]});
    const SortedRows pm(comm, mk);
    slots[m].name = mats[m].name;
    slots[m].style = mats[m].style;
    slots[m].state.resize(mats[m].state.size());
    for (std::size_t k = 0; k < mats[m].state.size(); ++k) {
      const std::size_t nc = static_cast<std::size_t>(mats[m].style->state_fields[k].ncomp);
      slots[m].state[k] = pm.move(mats[m].state[k].data(), nc);
      state_bytes += 8 * nc * pm.total();
    }
    slot_rows[m] = {pm.offset(), pm.total()};
    slots[m].begin = begin;
    slots[m].end = begin += pm.total();
  }
  CheckpointRows rows;
  const std::vector<double> rank_totals = outflow_block(dom, r, rows);
  const std::size_t no = rows.outflow_total;
  DriverState d = driver;
  d.series = comm.bcast(driver.series);  // rank 0's series text
  std::size_t out_row = set_row_bytes(rows.outflow_optional) + 8;
  for (const common::Field& f : r.outflow_fields) out_row += 8 * f.ncomp;
  const std::uintmax_t bytes = common::mpi::particle_file_bytes(local, plan.total()) +
                               (set_row_bytes(optional) + 12) * plan.total() + state_bytes +
                               out_row * no + d.series.size() + 16384 * (40 + 4 * mats.size());
  common::mpi::ParallelFile file(comm, path, bytes);
  rows.particles = file.rows(plan.offset(), plan.total());
  for (const auto& [off, tot] : slot_rows) rows.slots.push_back(file.rows(off, tot));
  rows.single_writer = comm.rank == 0;
  rows.xfer = file.xfer();
  rows.optional_arrays = optional;
  bool ok = common::write_particle_content(file.id(), snap, prov, rows.particles);
  ok = write_mpm_state(file.id(), set, slots, r, d, identity, rows) && ok;
  {  // /mpm_state/mpi: the tree of cuts and where each particle was (a restart on as many ranks)
    h5::Handle g = h5::create_group(file.id(), "mpm_state/mpi");
    h5::write_attr(g, "ranks", static_cast<std::int64_t>(dom.orb().ranks()));
    if (dom.orb().ranks() > 1) h5::write_attr(g, "orb", dom.orb().flat());
    ok = h5::write_dataset_rows(g, "rank", rank.data(), rank.size(), 1, "1", rows.particles) && ok;
    ok = h5::write_dataset_rows(g, "index", index.data(), index.size(), 1, "1", rows.particles) && ok;
    const std::size_t nt = pack_totals(Diagnostics{}).size(), nr = static_cast<std::size_t>(comm.size);
    ok = h5::write_dataset_rows(g, "outflow_totals", rank_totals.data(), rows.single_writer ? nr : 0, nt, "SI",
                                file.rows(0, nr)) && ok;
  }
  file.commit(ok);
  common::mpi::agreed(comm, [&] {  // the sidecar: a failure there fails every rank alike
    if (comm.rank == 0) common::write_particle_xdmf(path, snap, plan.total());
  });
}

}  // namespace mpmfrag::mpi
