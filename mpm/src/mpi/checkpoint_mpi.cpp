/// @file checkpoint_mpi.cpp
/// mpm-frag checkpoints on MPI ranks (design and file layout in mpm/mpi/checkpoint_mpi.hpp):
/// read on rank 0 and broadcast, and the restart constructor of DomainSolver that distributes
/// the particles (writing: checkpoint_write_mpi.cpp).
#include "mpm/mpi/checkpoint_mpi.hpp"

#include <algorithm>
#include <functional>
#include <numeric>

#include "common/agreed.hpp"
#include "common/h5.hpp"
#include "common/status.hpp"

namespace mpmfrag::mpi {

namespace {
namespace h5 = common::h5;

/// Run `f` on rank 0; an exception there is thrown, with its type (exit code) and message, on
/// every rank (a rank left waiting in a collective would hang the run).
void on_root(Comm& comm, const std::function<void()>& f) {
  common::mpi::agreed(comm, [&] {
    if (comm.rank == 0) f();
  });
}
}  // namespace

RestartData read_checkpoint_mpi(Comm& comm, const std::string& path, const common::RunIdentity& ident) {
  RestartData d;
  on_root(comm, [&] {
    auto hook = [&](long long fid) {
      const hid_t f = static_cast<hid_t>(fid);
      if (!h5::exists(f, "mpm_state/mpi")) return;  // a serial checkpoint
      h5::Handle g = h5::open_group(f, "mpm_state/mpi", path);
      const std::vector<std::int64_t> cuts = h5::read_attr_ints(g, "cuts", path);
      d.layout.cut.assign(cuts.begin(), cuts.end());
      d.layout.rank = h5::read_i32(f, "mpm_state/mpi/rank", -1, 1, path);
      d.layout.index = h5::read_u64(f, "mpm_state/mpi/index", -1, 1, path);
      const long long nr = static_cast<long long>(d.layout.cut.size()) - 1;
      d.layout.outflow_totals = h5::read_doubles(f, "mpm_state/mpi/outflow_totals", nr, pack_totals(Diagnostics{}).size(), path);
    };
    d.ck = read_checkpoint(path, hook);
    const common::RunIdentity theirs = common::RunIdentity::parse(d.ck.identity);
    const std::string diff = common::RunIdentity::differences(ident, "this run", theirs, "checkpoint");
    if (!diff.empty())
      throw common::InputError(path + ": checkpoint of another run (run identity " + theirs.digest() +
                               ") than this scene's (run identity " + ident.digest() + "); they differ in " + diff);
    if (d.layout.cut.empty()) return;
    const std::size_t n = d.ck.particles.size();
    const std::int32_t ranks = static_cast<std::int32_t>(d.layout.cut.size()) - 1;
    if (ranks < 1 || d.layout.rank.size() != n || d.layout.index.size() != n)
      throw common::InputError(path, "/mpm_state/mpi", "cuts, rank and index must describe every particle");
    for (const std::int32_t k : d.layout.rank)
      if (k < 0 || k >= ranks) throw common::InputError(path, "/mpm_state/mpi/rank", "a rank outside [0, ranks)");
  });
  // the scalars of SolverResume and DriverState (outflow records and drive loads: none on MPI)
  SolverResume& r = d.ck.solver;
  DriverState& v = d.ck.driver;
  std::vector<double> s = {r.time, static_cast<double>(r.step), r.max_speed, r.min_node_mass,
                           v.next_snapshot, v.first_dt, v.min_dt, v.max_dt};
  const std::vector<double> tot = pack_totals(v.initial);
  s.insert(s.end(), tot.begin(), tot.end());
  MPI_Bcast(s.data(), static_cast<int>(s.size()), MPI_DOUBLE, 0, comm.c);
  r.time = s[0];
  r.step = static_cast<std::int64_t>(s[1]);
  r.max_speed = s[2];
  r.min_node_mass = s[3];
  v.next_snapshot = s[4];
  v.first_dt = s[5];
  v.min_dt = s[6];
  v.max_dt = s[7];
  v.initial = unpack_totals(std::vector<double>(s.begin() + 8, s.end()));
  return d;
}

void resume(DomainSolver& dom, RestartData& rd) {
  Comm& comm = dom.comm();
  // the removed particles' totals: each rank its own when as many ranks wrote the file (the
  // same sums in the same order), else all on rank 0; the record itself stays on rank 0
  const std::size_t nt = pack_totals(Diagnostics{}).size();
  std::vector<double> all;
  if (comm.rank == 0) {
    if (rd.layout.cut.size() == static_cast<std::size_t>(comm.size) + 1) {
      all = rd.layout.outflow_totals;
    } else {
      all.assign(nt * static_cast<std::size_t>(comm.size), 0.0);
      const std::vector<double> t = pack_totals(rd.ck.solver.outflow_totals);
      std::copy(t.begin(), t.end(), all.begin());
    }
  }
  std::vector<double> mine(nt);
  MPI_Scatter(all.data(), static_cast<int>(nt), MPI_DOUBLE, mine.data(), static_cast<int>(nt), MPI_DOUBLE, 0, comm.c);
  rd.ck.solver.outflow_totals = unpack_totals(mine);
  dom.local().resume(std::move(rd.ck.solver));
}

DomainSolver::DomainSolver(MPI_Comm comm, const Setup& setup, const Layout& layout, DomainOptions opt)
    : comm_(comm), opt_(opt), grid_(setup.grid) {
  init_slabs(setup);
  const bool root = comm_.rank == 0;
  const ParticleSet& ps = setup.particles;
  const std::size_t n = root ? ps.size() : 0;
  // the writer's cuts and order when it ran on as many ranks, else cuts balancing the count
  int same = root && layout.cut.size() == static_cast<std::size_t>(comm_.size) + 1 && layout.rank.size() == n &&
             layout.index.size() == n;
  MPI_Bcast(&same, 1, MPI_INT, 0, comm_.c);
  slabs_.cut.assign(static_cast<std::size_t>(comm_.size) + 1, 0);
  if (same) {
    if (root) slabs_.cut = layout.cut;
    MPI_Bcast(slabs_.cut.data(), comm_.size + 1, MPI_INT, 0, comm_.c);
    bool ok = slabs_.cut.front() == 0 && slabs_.cut.back() == grid_.shape[slabs_.axis];
    for (int r = 0; r < comm_.size; ++r) ok = ok && slabs_.cut[r + 1] - slabs_.cut[r] >= slabs_.min_width;
    if (!ok)  // every rank holds the same cuts: every rank throws
      throw common::InputError("checkpoint: /mpm_state/mpi cuts do not split this scene's grid into slabs of at least " +
                               std::to_string(slabs_.min_width) + " planes");
  } else {
    std::vector<long long> count(grid_.shape[slabs_.axis], 0);
    for (std::size_t p = 0; p < n; ++p) ++count[cell(ps.x[3 * p + slabs_.axis])];
    comm_.sum(count.data(), static_cast<int>(count.size()));
    slabs_.cut = balanced_cuts(count, comm_.size, slabs_.min_width);
  }
  std::vector<std::vector<char>> send(comm_.size);
  if (root) {
    std::vector<int> dest(n);
    for (std::size_t p = 0; p < n; ++p) dest[p] = same ? layout.rank[p] : slabs_.owner(cell(ps.x[3 * p + slabs_.axis]));
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    if (same)
      std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return layout.index[a] < layout.index[b]; });
    for (const std::size_t p : order) pack_particle(ps, setup.materials, p, send[dest[p]]);
  }
  const double before = comm_.bytes_sent;
  const std::vector<std::vector<char>> recv = comm_.alltoallv(send);
  stats_.migrate_bytes += comm_.bytes_sent - before;
  // the materials without particles (names, styles, models), then this rank's arrivals
  std::vector<MaterialSlot> empty = setup.materials;
  for (MaterialSlot& m : empty) {
    m.begin = m.end = 0;
    m.state.assign(m.style->state_fields.size(), {});
  }
  Arrivals in;
  for (const auto& b : recv) unpack_particles(b, empty, setup.solver.artificial_viscosity, in);
  ParticleSet mine;
  std::vector<MaterialSlot> mats;
  merge_particles(ParticleSet{}, empty, {}, in, mine, mats);
  build_solver(setup, std::move(mine), std::move(mats));
}

}  // namespace mpmfrag::mpi
