/// @file test_mpm_mpi_restart.cpp
/// Checkpoints of mpm-frag on MPI (label mpi; part of test_mpm_mpi, whose main() initialises
/// MPI): a Tonge–Ramesh impact (mpi_test_helpers.hpp) checkpointed at t_c on N ranks (or by the
/// serial Solver, N = 1) and restarted on M ranks (or by the serial Solver) to t_end, against
/// the uninterrupted run on N ranks with the same steps (dt cut at t_c). N and M run on
/// sub-communicators of MPI_COMM_WORLD (ranks 0 .. N-1), so one mpirun covers several pairs.
///   N -> N: bit-identical (every particle array, every style state array, the totals);
///   N -> M != N: the tolerances of the cross-rank agreement in test_mpm_mpi.cpp (v 1e-12 U,
///   x 1e-12 h, stress 1e-12 rho U c, damage 1e-9, energy 1e-12 U^2), momentum to 1e-12 P.
/// And a checkpoint as written before the ORB boxes (slab cuts in /mpm_state/mpi, attribute
/// cuts) restarts on N ranks bit-identically.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "mpi_test_helpers.hpp"
#include "mpm/checkpoint.hpp"
#include "common/h5.hpp"
#include "mpm/mpi/checkpoint_mpi.hpp"

using namespace mpmfrag;
using namespace mpmtest;

namespace {

constexpr double kCheck = 8e-5;  // the checkpoint: after the impactor hit the rock (damage > 0)
const common::Provenance kProv{"mpm-frag", "test", "test", "test", ""};

/// Ranks 0 .. n-1 of MPI_COMM_WORLD (MPI_COMM_NULL on the others).
MPI_Comm first_ranks(int n) {
  MPI_Comm c = MPI_COMM_NULL;
  MPI_Comm_split(MPI_COMM_WORLD, rank() < n ? 0 : MPI_UNDEFINED, rank(), &c);
  return c;
}

/// The same file name on every rank.
std::string temp_path(const std::string& tag) {
  long long pid = getpid();
  MPI_Bcast(&pid, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  return (std::filesystem::temp_directory_path() / ("mpm_mpi_restart_" + std::to_string(pid) + "_" + tag + ".h5")).string();
}

struct Result {
  ParticleSet ps;
  std::vector<MaterialSlot> mats;
  Diagnostics d1;
};

/// Largest value of the state field `name` in a checkpoint file.
double max_state(const std::string& path, const std::string& name) {
  double m = 0;
  for (const MaterialState& s : read_checkpoint(path).materials)
    for (const auto& [f, v] : s.fields)
      if (f == name)
        for (const double x : v) m = std::max(m, x);
  return m;
}

/// Run to kImpactEnd and keep the end state (gathered to rank 0 for a DomainSolver).
Result finish(Solver& s) {
  Result r;
  run_serial(s, kImpactEnd);
  r.ps = s.particles();
  r.mats = s.materials();
  r.d1 = s.diagnostics();
  return r;
}
Result finish(DomainSolver& dom) {
  Result r;
  run_domain(dom, kImpactEnd);
  r.d1 = dom.diagnostics();
  dom.gather(0, r.ps, r.mats);
  return r;
}

/// The uninterrupted run on n ranks (the serial Solver for n = 1), writing the checkpoint at
/// kCheck to `path` on the way. Result on world rank 0.
Result write_and_run(int n, const std::string& path) {
  Result r;
  if (n == 1) {
    if (rank() == 0) {
      Solver s = solver_from(impact_setup());
      run_serial(s, kCheck);
      write_checkpoint(path, s, DriverState{}, kProv, "");
      r = finish(s);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    return r;
  }
  MPI_Comm c = first_ranks(n);
  if (c != MPI_COMM_NULL) {
    DomainSolver dom(c, impact_setup(), impact_options());
    dom.initialize();
    run_domain(dom, kCheck);
    mpi::write_checkpoint_mpi(dom, path, DriverState{}, kProv, "");
    r = finish(dom);
    MPI_Comm_free(&c);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return r;
}

/// Restart `path` on m ranks (the serial Solver for m = 1) and run to kImpactEnd.
Result restart_and_run(int m, const std::string& path) {
  Result r;
  if (m == 1) {
    if (rank() == 0) {
      Setup st = impact_setup();
      Checkpoint ck = read_checkpoint(path);
      apply_materials(ck, st.materials, path);
      Solver s(st.solver, st.grid, std::move(ck.particles), std::move(st.materials));
      s.resume(std::move(ck.solver));
      r = finish(s);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    return r;
  }
  MPI_Comm c = first_ranks(m);
  if (c != MPI_COMM_NULL) {
    mpi::Comm comm(c);
    mpi::RestartData rd = mpi::read_checkpoint_mpi(comm, path, common::RunIdentity{});
    Setup st = impact_setup();
    apply_materials(rd.ck, st.materials, path);  // each rank its part of the file's rows
    st.particles = std::move(rd.ck.particles);
    DomainSolver dom(c, st, rd.layout, impact_options());
    mpi::resume(dom, rd);
    r = finish(dom);
    MPI_Comm_free(&c);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return r;
}

bool bit_identical(const Result& a, const Result& b) {
  bool same = a.ps.size() == b.ps.size() && a.mats.size() == b.mats.size();
  ParticleSet::for_each_array([&](const auto& arr) {
    const auto& va = a.ps.*arr.member;
    const auto& vb = b.ps.*arr.member;
    same = same && va.size() == vb.size() && std::memcmp(va.data(), vb.data(), va.size() * sizeof(va[0])) == 0;
  });
  for (std::size_t m = 0; same && m < a.mats.size(); ++m)
    for (std::size_t f = 0; f < a.mats[m].state.size(); ++f)
      same = same && a.mats[m].state[f] == b.mats[m].state[f];
  return same && a.d1.momentum == b.d1.momentum && a.d1.total() == b.d1.total() && a.d1.mass == b.d1.mass;
}

/// Rewrite a checkpoint's tree of cuts as the slab cuts written before the boxes (attribute
/// "cuts": planes 0, P_1, .., S along x); false when the tree is not slabs along x.
bool as_slab_cuts(const std::string& path) {
  namespace h5 = common::h5;
  h5::Handle f(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT));
  h5::Handle g = h5::open_group(f, "mpm_state/mpi", path);
  const std::vector<mpi::Orb::Split> split = mpi::Orb::unflat(h5::read_attr_ints(g, "orb", path));
  std::vector<std::int64_t> cuts{0};
  for (const mpi::Orb::Split& s : split) {
    if (s.axis != 0 || s.left != 1) return false;
    cuts.push_back(s.cut);
  }
  cuts.push_back(impact_setup().grid.shape[0]);
  H5Adelete(g, "orb");
  h5::write_attr(g, "cuts", cuts);
  return true;
}

/// Checkpoint on n ranks, restart on m; compare on world rank 0. With `legacy` the checkpoint's
/// tree is rewritten as slab cuts first (n == m).
void check_pair(int n, int m, bool legacy = false) {
  const std::string path = temp_path(std::to_string(n) + "to" + std::to_string(m));
  const Result ref = write_and_run(n, path);
  int slabs = 1;
  if (legacy && rank() == 0) slabs = as_slab_cuts(path) ? 1 : 0;
  MPI_Bcast(&slabs, 1, MPI_INT, 0, MPI_COMM_WORLD);
  if (!slabs) {
    if (rank() == 0) std::filesystem::remove(path);
    FAIL() << "the impact's boxes on " << n << " ranks are not slabs along x: this test needs another scene";
  }
  const Result res = restart_and_run(m, path);
  if (rank() != 0) return;
  const double damage = max_state(path, "damage");
  std::filesystem::remove(path);
  const Diff df = compare(res.ps, res.mats, ref.ps, ref.mats);
  ASSERT_TRUE(df.same_ids) << n << " -> " << m;
  const Diagnostics s0 = solver_from(impact_setup()).diagnostics();
  const double U = 450.0, P = std::sqrt(2 * s0.mass * s0.kinetic);
  std::printf("restart %d -> %d ranks: damage at the checkpoint %.3g; max |diff| vs the uninterrupted %d-rank run: v %.3e m/s, x %.3e m, stress %.3e Pa, damage %.3e, energy %.3e J/kg; bit-identical %s\n",
              n, m, damage, n, df.max.at("v"), df.max.at("x"), df.max.at("stress"),
              df.max.at("state:damage"), df.max.at("energy"), bit_identical(res, ref) ? "yes" : "no");
  EXPECT_GT(damage, 0.01) << "the checkpoint must carry Tonge–Ramesh damage";
  if (n == m) {
    EXPECT_TRUE(bit_identical(res, ref)) << n << " -> " << m << " must continue bit-identically";
    return;
  }
  EXPECT_LT(df.max.at("v"), 1e-12 * U);
  EXPECT_LT(df.max.at("x"), 1e-12 * 0.01);
  EXPECT_LT(df.max.at("stress"), 1e-12 * 2700.0 * U * 6000.0);
  EXPECT_LT(df.max.at("state:damage"), 1e-9);
  EXPECT_LT(df.max.at("energy"), 1e-12 * U * U);
  EXPECT_NEAR(res.d1.mass, ref.d1.mass, 2.2e-16 * static_cast<double>(res.ps.size()) * s0.mass);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(res.d1.momentum[k], ref.d1.momentum[k], 1e-12 * P) << k;
}

}  // namespace

TEST(MpmMpiRestart, SameRankCountIsBitIdentical) { check_pair(ranks(), ranks()); }
TEST(MpmMpiRestart, SlabCutsOfAnOlderCheckpointContinueBitIdentically) {
  if (ranks() > 3) GTEST_SKIP() << "the impact's boxes are slabs along x on 2 and 3 ranks only";
  check_pair(ranks(), ranks(), true);
}
TEST(MpmMpiRestart, FewerRanks) { check_pair(ranks(), ranks() - 1); }  // 3 -> 2, 2 -> 1 (serial)
TEST(MpmMpiRestart, MoreRanks) { check_pair(ranks() - 1, ranks()); }   // 2 -> 3, 1 (serial) -> 2
TEST(MpmMpiRestart, TwoRanksToOneAndBack) {                              // on 3 ranks: 2 -> 1, 1 -> 2
  if (ranks() < 3) GTEST_SKIP() << "covered by FewerRanks / MoreRanks on 2 ranks";
  check_pair(2, 1);
  check_pair(1, 2);
}
