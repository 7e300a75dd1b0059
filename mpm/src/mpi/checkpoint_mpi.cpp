/// @file checkpoint_mpi.cpp
/// mpm-frag checkpoints on MPI ranks (design and file layout in mpm/mpi/checkpoint_mpi.hpp):
/// every rank reads its part of the rows, and the restart constructor of DomainSolver that sends
/// each particle to its rank (writing: checkpoint_write_mpi.cpp).
#include "mpm/mpi/checkpoint_mpi.hpp"

#include <algorithm>
#include <cstring>

#include "common/agreed.hpp"
#include "common/h5.hpp"
#include "common/status.hpp"

namespace mpmfrag::mpi {

namespace h5 = common::h5;

RestartData read_checkpoint_mpi(Comm& comm, const std::string& path, const common::RunIdentity& ident) {
  RestartData d;
  // every rank reads its part of the rows itself (no rank holds every particle); a bad file
  // fails on every rank alike, and agreed() makes every rank throw the same error
  common::mpi::agreed(comm, [&] {
    auto hook = [&](long long fid, const Checkpoint& part) {
      const hid_t f = static_cast<hid_t>(fid);
      if (!h5::exists(f, "mpm_state/mpi")) return;  // a serial checkpoint
      h5::Handle g = h5::open_group(f, "mpm_state/mpi", path);
      // the tree of cuts ("orb": axis, cut, left per split); files written before the boxes
      // hold slab cuts ("cuts": planes P_0 .. P_R along the grid's longest axis)
      if (!h5::has_attr(g, "cuts")) {
        const std::vector<std::int64_t> ranks = h5::read_attr_ints(g, "ranks", path);
        const std::int64_t nr = ranks.empty() ? 0 : ranks[0];
        const std::vector<std::int64_t> flat =
            nr > 1 ? h5::read_attr_ints(g, "orb", path) : std::vector<std::int64_t>{};
        bool ok = nr >= 1 && nr <= (1 << 24) && flat.size() == 3 * static_cast<std::size_t>(nr - 1);
        for (const std::int64_t v : flat) ok = ok && v >= 0 && v < (1LL << 30);
        if (!ok)
          throw common::InputError(path, "/mpm_state/mpi",
                                   "attributes ranks (>= 1) and orb (3 (ranks - 1) non-negative integers) do not describe a tree of cuts");
        d.layout.ranks = static_cast<int>(nr);
        d.layout.split = Orb::unflat(flat);
      } else {  // slab planes 0 = P_0 < P_1 < ... < P_R = S along the grid's longest axis
        const std::vector<std::int64_t> cuts = h5::read_attr_ints(g, "cuts", path);
        bool ok = cuts.size() >= 2 && cuts.size() <= (1u << 24) && cuts.front() == 0 && cuts.back() < (1LL << 30);
        for (std::size_t k = 1; ok && k < cuts.size(); ++k) ok = cuts[k] > cuts[k - 1];
        if (!ok)
          throw common::InputError(path, "/mpm_state/mpi", "attribute cuts must rise from 0 and describe at least one rank");
        d.layout.ranks = static_cast<int>(cuts.size()) - 1;
        d.layout.split = Orb::slabs(-1, std::vector<int>(cuts.begin(), cuts.end()));  // axis: the grid's longest, set on restart
        d.layout.slab_end = static_cast<int>(cuts.back());
      }
      const long long n = static_cast<long long>(part.total);
      const h5::RowRange mine{part.first, part.particles.size()};
      d.layout.rank = h5::read_i32(f, "mpm_state/mpi/rank", n, 1, path, mine);
      d.layout.index = h5::read_u64(f, "mpm_state/mpi/index", n, 1, path, mine);
      const long long nr = d.layout.ranks;
      d.layout.outflow_totals = h5::read_doubles(f, "mpm_state/mpi/outflow_totals", nr, pack_totals(Diagnostics{}).size(), path);
      for (const std::int32_t k : d.layout.rank)
        if (k < 0 || k >= nr) throw common::InputError(path, "/mpm_state/mpi/rank", "a rank outside [0, ranks)");
    };
    d.ck = read_checkpoint_part(path, CheckpointPart{comm.rank, comm.size, comm.rank == 0}, hook);
    d.layout.first = d.ck.first;
    const common::RunIdentity theirs = common::RunIdentity::parse(d.ck.identity);
    const std::string diff = common::RunIdentity::differences(ident, "this run", theirs, "checkpoint");
    if (!diff.empty())
      throw common::InputError(path + ": checkpoint of another run (run identity " + theirs.digest() +
                               ") than this scene's (run identity " + ident.digest() + "); they differ in " + diff);
  });
  return d;
}

void resume(DomainSolver& dom, RestartData& rd) {
  Comm& comm = dom.comm();
  // the removed particles' totals: each rank its own when as many ranks wrote the file (the
  // same sums in the same order), else all on rank 0; each rank keeps its part of the record
  const std::size_t nt = pack_totals(Diagnostics{}).size();
  std::vector<double> all;
  if (comm.rank == 0) {
    if (rd.layout.ranks == comm.size) {
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
  init_orb(setup);
  const ParticleSet& ps = setup.particles;
  const std::size_t n = ps.size();
  // the writer's tree and order when it ran on as many ranks, else a tree balancing the work
  const bool same = comm_.all(layout.ranks == comm_.size && layout.rank.size() == n && layout.index.size() == n);
  if (same) {  // every rank read the same tree
    std::vector<Orb::Split> split = layout.split;
    int longest = 0;  // a file of slab cuts: along the grid's longest axis, as they were cut
    for (int d = 1; d < 3; ++d)
      if (grid_.shape[d] > grid_.shape[longest]) longest = d;
    for (Orb::Split& s : split)
      if (s.axis < 0) s.axis = longest;
    const bool slabs_fit = layout.slab_end < 0 || layout.slab_end == grid_.shape[longest];
    if (!slabs_fit || !orb_.set(std::move(split)))  // every rank holds the same tree: every rank throws
      throw common::InputError("checkpoint: /mpm_state/mpi's tree of cuts does not split this scene's grid into " +
                               std::to_string(comm_.size) + " boxes of at least " + std::to_string(orb_.min_width) +
                               " planes along their cuts");
  } else {
    orb_ = balanced_orb(ps, setup.materials);
  }
  // each particle to its rank, with its order key there: its index on the writing rank, or its
  // file row (each rank then holds its particles in file order)
  std::vector<std::vector<char>> send(comm_.size), keys(comm_.size);
  for (std::size_t p = 0; p < n; ++p) {
    const int dest = same ? layout.rank[p] : orb_.owner(cell(&ps.x[3 * p]));
    const std::uint64_t key = same ? layout.index[p] : layout.first + p;
    pack_particle(ps, setup.materials, p, send[dest]);
    const char* k = reinterpret_cast<const char*>(&key);
    keys[dest].insert(keys[dest].end(), k, k + sizeof key);
  }
  const double before = comm_.bytes_sent;
  const std::vector<std::vector<char>> recv = comm_.alltoallv(send);
  const std::vector<std::vector<char>> recv_keys = comm_.alltoallv(keys);
  stats_.migrate_bytes += comm_.bytes_sent - before;
  // the materials without particles (names, styles, models), then this rank's arrivals in key order
  std::vector<MaterialSlot> empty = setup.materials;
  for (MaterialSlot& m : empty) {
    m.begin = m.end = 0;
    m.state.assign(m.style->state_fields.size(), {});
  }
  Arrivals in;
  std::vector<std::uint64_t> key;
  for (std::size_t r = 0; r < recv.size(); ++r) {
    unpack_particles(recv[r], empty, setup.solver.artificial_viscosity, in);
    const std::size_t nk = recv_keys[r].size() / sizeof(std::uint64_t);
    key.resize(key.size() + nk);
    if (nk > 0) std::memcpy(key.data() + key.size() - nk, recv_keys[r].data(), recv_keys[r].size());
  }
  sort_arrivals(in, key);
  ParticleSet mine;
  std::vector<MaterialSlot> mats;
  merge_particles(ParticleSet{}, empty, {}, in, mine, mats);
  build_solver(setup, std::move(mine), std::move(mats));
}

}  // namespace mpmfrag::mpi
