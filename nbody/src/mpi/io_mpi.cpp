/// @file io_mpi.cpp
/// Collective snapshots and checkpoints of ssdem-grav (io_mpi.hpp).
#include "ssdem/mpi/io_mpi.hpp"

#include <cstring>
#include <type_traits>

#include "common/agreed.hpp"
#include "common/exact_sum_mpi.hpp"
#include "common/finite.hpp"
#include "common/h5_parallel.hpp"
#include "common/sphere_file_mpi.hpp"

namespace ssdem::mpi {
namespace {
// The rank's own spheres as a file set: core arrays and Spheres' other arrays as fields; the
// carried fields come from the rank's block instead.
common::SphereSet own_set(const DomainSim::Local& L) {
  Spheres sp = L.st.sp;
  sp.carried.clear();
  return to_sphere_set(sp, L.st.time, L.st.step);
}

std::vector<Vec3> move3(const common::mpi::SortedRows& plan, const std::vector<Vec3>& v) {
  std::vector<double> f(3 * v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int c = 0; c < 3; ++c) f[3 * i + c] = v[i][c];
  const std::vector<double> m = plan.move(f, 3);
  std::vector<Vec3> out(m.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = Vec3(m[3 * i], m[3 * i + 1], m[3 * i + 2]);
  return out;
}

// Each array of the rank's bonds moved to its block of the bond rows (dense blocks).
BondSet move_bonds(const common::mpi::SortedRows& plan, const BondSet& b) {
  BondSet out;
  BondSet::zip_arrays([&](auto& to, const auto& from) {
    using T = typename std::decay_t<decltype(to)>::value_type;
    if constexpr (std::is_same_v<T, Vec3>)
      to = move3(plan, from);
    else
      to = plan.move(from, 1);
  }, out, b);
  out.released_base = b.released_base;
  return out;
}
}  // namespace

void write_snapshot_mpi(Comm& comm, const std::string& path, const DomainSim& sim, const DomainSim::Local& mine,
                        const common::Provenance& prov) {
  if (sim.global_bonds() == 0) {
    common::mpi::write_sphere_set_mpi(comm, path, own_set(mine), mine.row, sim.carried_block(), prov);
    return;
  }
  const common::mpi::BondRows bonds{to_bond_table(mine.st.bonds), mine.brow, mine.bsph};
  common::mpi::write_sphere_set_mpi(comm, path, own_set(mine), mine.row, sim.carried_block(), prov, &bonds);
}

void write_checkpoint_mpi(Comm& comm, const std::string& path, const DomainSim& sim, const DomainSim::Local& mine,
                          const StateHeader& h, double energy0, const common::Provenance& prov) {
  namespace cm = common::mpi;
  const cm::SphereBlock b(comm, own_set(mine), mine.row, sim.carried_block(), path);
  cm::agreed(comm, [&] { common::check_output_spheres(b.set, path); });
  // the state's per-sphere arrays move with the spheres; the history records by their own order
  const SimState& st = mine.st;
  SimState blk;
  blk.step = st.step;
  blk.time = st.time;
  blk.gravity_step = st.gravity_step;
  blk.energy0 = energy0;
  blk.a = move3(b.plan, st.a);
  blk.alpha = move3(b.plan, st.alpha);
  if (h.has_ag) blk.ag = move3(b.plan, st.ag);
  if (h.has_prev) {
    blk.a_prev = move3(b.plan, st.a_prev);
    blk.alpha_prev = move3(b.plan, st.alpha_prev);
  }
  if (h.has_level) {
    blk.level = b.plan.move(st.level, 1);
    blk.tau_prev = b.plan.move(st.tau_prev, 1);
  }
  std::vector<cm::RowKey> hkey;
  for (const auto& [first, second] : mine.hkey) hkey.push_back(cm::RowKey{first, second});
  const cm::SortedRows hplan(comm, hkey);
  const std::vector<char> hb =
      hplan.move(reinterpret_cast<const char*>(st.history.data()), sizeof(HistoryRecord));  // plain records
  blk.history.resize(hb.size() / sizeof(HistoryRecord));
  if (!hb.empty()) std::memcpy(static_cast<void*>(blk.history.data()), hb.data(), hb.size());

  // bonds (a run with bonds: the same on every rank) by their rows, the one-rank order; the
  // released total exact over the ranks
  const std::size_t nb = sim.global_bonds();
  std::size_t boff = 0;
  common::ExactSum released;
  if (nb > 0) {
    std::vector<cm::RowKey> bkey;
    for (std::uint64_t g : mine.brow) bkey.push_back(cm::RowKey{0, g});
    const cm::SortedRows bplan(comm, bkey, cm::dense_splitters(nb, comm.size));
    boff = bplan.offset();
    blk.bonds = move_bonds(bplan, st.bonds);
    for (double e : blk.bonds.released) released.add(e);
    if (comm.rank == 0) released.add(st.bonds.released_base);
    cm::allreduce(comm, released);
  }

  const std::uintmax_t state_bytes = b.plan.total() * (5 * 24 + 12) +
                                     hplan.total() * (16 + kHistVec * 24 + kHistScal * 8) + nb * 160 +
                                     (std::uintmax_t{1} << 16);
  cm::ParallelFile file(comm, path, cm::sphere_file_bytes(b.set, b.plan.total()) + state_bytes);
  bool ok = common::write_sphere_content(file.id(), b.set, prov, file.rows(b.plan.offset(), b.plan.total()));
  ok = write_state_group(file.id(), blk, h, file.rows(b.plan.offset(), b.plan.total()),
                         file.rows(hplan.offset(), hplan.total()), file.rows(boff, nb), released.value()) &&
       ok;
  file.commit(ok);
  cm::agreed(comm, [&] {  // the sidecar: a failure there fails every rank alike
    if (comm.rank == 0) common::write_sphere_xdmf(path, b.set, b.plan.total());
  });
}

}  // namespace ssdem::mpi
