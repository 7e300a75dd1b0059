/// @file test_mpm_mpi_files.cpp
/// mpm-frag's checkpoints written collectively with parallel HDF5 (mpi/checkpoint_mpi.hpp;
/// label mpi, part of test_mpm_mpi) under mpirun -np 2 and -np 3:
///   - the file equals, by h5diff (every dataset, attribute and unit; provenance aside), the one
///     the former writer made: every particle, its material state and the outflow record gathered
///     to rank 0 and written by the serial checkpoint writer plus /mpm_state/mpi. Two scenes: the
///     Tonge–Ramesh impact with artificial viscosity (the optional array q) mid-run, and the
///     outflow flyers when half have left (a non-empty outflow record gathered from every rank);
///   - a file-size limit (a full disk) throws IoError on every rank, and the earlier checkpoint
///     stays byte for byte with no temporary file left beside it;
///   - a non-finite value on one rank throws NumericalError on every rank and writes nothing;
///   - a restart reads the file in parts that tile it; a corrupt file is refused on every rank.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "common/h5.hpp"
#include "common/status.hpp"
#include "mpi_test_helpers.hpp"
#include "mpm/checkpoint.hpp"
#include "mpm/mpi/checkpoint_mpi.hpp"

using namespace mpmfrag;
using namespace mpmtest;
namespace fs = std::filesystem;

namespace {

const common::Provenance kProv{"mpm-frag", "test", "test", "test", ""};

/// A driver state with rank 0's series text (the other ranks' is empty, as in run_mpi.cpp).
DriverState driver(DomainSolver& dom) {
  DriverState d;
  d.next_snapshot = 1.5e-4;
  d.first_dt = 1e-7;
  d.min_dt = 9e-8;
  d.max_dt = 2e-7;
  d.initial = dom.diagnostics();
  if (rank() == 0) d.series = "step,time\n0,0\n10,1e-06\n";
  return d;
}

/// The former writer: everything gathered to rank 0, the serial writer, /mpm_state/mpi.
void write_gathered(DomainSolver& dom, const std::string& path, const DriverState& d) {
  ParticleSet ps;
  std::vector<MaterialSlot> mats;
  mpi::Layout layout;
  dom.gather(0, ps, mats, &layout);
  SolverResume r = dom.local().resume_state();
  mpi::OutflowRecord out = dom.gather_outflow(0);
  if (rank() != 0) return;
  r.outflow = std::move(out.ps);
  r.outflow_time = std::move(out.time);
  r.outflow_fields = std::move(out.fields);
  r.outflow_init = std::move(out.init);
  r.outflow_totals = out.totals;
  auto hook = [&](long long fid) {
    namespace h5 = common::h5;
    h5::Handle g = h5::create_group(static_cast<hid_t>(fid), "mpm_state/mpi");
    h5::write_attr(g, "ranks", static_cast<std::int64_t>(layout.ranks));
    mpi::Orb o;
    o.split = layout.split;
    h5::write_attr(g, "orb", o.flat());
    h5::write_dataset(g, "rank", layout.rank.data(), layout.rank.size(), 1, "1");
    h5::write_dataset(g, "index", layout.index.data(), layout.index.size(), 1, "1");
    const std::size_t nt = pack_totals(Diagnostics{}).size();
    h5::write_dataset(g, "outflow_totals", out.rank_totals.data(), out.rank_totals.size() / nt, nt, "SI");
  };
  write_checkpoint(path, ps, mats, dom.local().grid(), r, d, kProv, "", hook);
}

/// Run `setup` to t on every rank, write the checkpoint both ways, h5diff on rank 0.
void expect_equal_to_gathered(const Setup& setup, double t, mpi::DomainOptions opt, std::size_t min_outflow, bool q) {
  SharedDir dir;
  DomainSolver dom(MPI_COMM_WORLD, setup, opt);
  dom.initialize();
  const DriverState d = driver(dom);
  run_domain(dom, t);
  const std::string par = dir.path + "/parallel.h5", ser = dir.path + "/gathered.h5";
  mpi::write_checkpoint_mpi(dom, par, d, kProv, "");
  write_gathered(dom, ser, d);
  if (rank() != 0) return;
  const Checkpoint ck = read_checkpoint(par);
  EXPECT_GE(ck.solver.outflow.size(), min_outflow);
  EXPECT_EQ(ck.particles.q.size(), q ? ck.particles.size() : 0u) << "artificial viscosity's q";
  EXPECT_EQ(ck.driver.series, d.series);
  const std::string cmd = "h5diff --exclude-path /provenance " + ser + " " + par;
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  EXPECT_TRUE(fs::exists(dir.path + "/parallel.xmf"));
}

/// The Tonge–Ramesh impact on every rank at 20 us, and its driver state.
struct ImpactAt20us {
  DomainSolver dom{MPI_COMM_WORLD, impact_setup(), impact_options()};
  DriverState d;
  ImpactAt20us() {
    dom.initialize();
    d = driver(dom);
    run_domain(dom, 2e-5);
  }
};

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST(MpmMpiFiles, CheckpointOfTheImpactEqualsTheGatheredFile) {
  expect_equal_to_gathered(impact_setup(), 8e-5, impact_options(), 0, true);
}

TEST(MpmMpiFiles, CheckpointWithTheOutflowRecordEqualsTheGatheredFile) {
  expect_equal_to_gathered(outflow_setup(), 7.5e-5, mpi::DomainOptions{}, 100, false);
}

// The same with artificial viscosity: the optional array q in the particles' and the outflow
// record's blocks (a rank without removed particles holds none of either's rows).
TEST(MpmMpiFiles, CheckpointWithTheOutflowRecordAndViscosityEqualsTheGatheredFile) {
  expect_equal_to_gathered(outflow_setup({"solver.artificial_viscosity.enabled=true"}), 7.5e-5, mpi::DomainOptions{}, 100,
                           true);
}

TEST(MpmMpiFiles, FullDiskKeepsTheEarlierCheckpoint) {
  SharedDir dir;
  ImpactAt20us run;
  DomainSolver& dom = run.dom;
  const DriverState& d = run.d;
  const std::string path = dir.path + "/ck.h5";
  mpi::write_checkpoint_mpi(dom, path, d, kProv, "");
  const std::string before = rank() == 0 ? bytes_of(path) : std::string();
  run_domain(dom, 4e-5);
  std::signal(SIGXFSZ, SIG_IGN);
  rlimit old{};
  ::getrlimit(RLIMIT_FSIZE, &old);
  rlimit lim = old;
  lim.rlim_cur = 64 * 1024;  // the checkpoint is ~1 MB
  ::setrlimit(RLIMIT_FSIZE, &lim);
  EXPECT_THROW(mpi::write_checkpoint_mpi(dom, path, d, kProv, ""), common::IoError);
  ::setrlimit(RLIMIT_FSIZE, &old);
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() != 0) return;
  EXPECT_EQ(bytes_of(path), before) << "the earlier checkpoint must stay as it was";
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir.path)) files += e.path().extension() != ".xmf";
  EXPECT_EQ(files, 1u) << "no temporary file may be left";
}

TEST(MpmMpiFiles, NonFiniteValueOnOneRankWritesNothing) {
  SharedDir dir;
  ImpactAt20us run;
  DomainSolver& dom = run.dom;
  const DriverState& d = run.d;
  // inject the fault on the last rank only (a test of the error path, not a solver state)
  auto& ps = const_cast<ParticleSet&>(dom.local().particles());
  if (rank() == ranks() - 1) {
    ASSERT_GT(ps.size(), 0u);
    ps.v[0] = std::numeric_limits<double>::quiet_NaN();
  }
  const std::string path = dir.path + "/ck.h5";
  EXPECT_THROW(mpi::write_checkpoint_mpi(dom, path, d, kProv, ""), common::NumericalError);
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() == 0) {
    EXPECT_TRUE(fs::is_empty(dir.path));
  }
}

// A restart on several ranks reads the checkpoint in parts (read_checkpoint_part): the parts of
// any count tile the whole read exactly (every array, every material's state rows and ranges,
// the outflow record's rows), and only the first carries the series. With 20 parts the last lie
// beyond the Tonge–Ramesh rock's rows (94 % of them, material 0), whose state they must not
// read. Two files: the impact, and the outflow scene after 100 or more removals.
TEST(MpmMpiFiles, CheckpointPartsTileTheWholeFile) {
  SharedDir dir;
  ImpactAt20us run;
  const std::string impact = dir.path + "/ck.h5", removed = dir.path + "/outflow.h5";
  mpi::write_checkpoint_mpi(run.dom, impact, run.d, kProv, "");
  DomainSolver out(MPI_COMM_WORLD, outflow_setup(), mpi::DomainOptions{});
  out.initialize();
  const DriverState od = driver(out);
  run_domain(out, 7.5e-5);
  mpi::write_checkpoint_mpi(out, removed, od, kProv, "");
  if (rank() != 0) return;
  for (const std::string& path : {impact, removed}) {
    const Checkpoint whole = read_checkpoint(path);
    ASSERT_GT(whole.particles.size(), 100u);
    if (path == removed) {
      ASSERT_GE(whole.solver.outflow.size(), 100u);
    }
    for (const int parts : {1, 2, 3, 7, 20}) {
      ParticleSet cat, ocat;
      std::vector<double> otime;
      std::vector<std::vector<double>> ofields(whole.solver.outflow_fields.size());
      std::vector<std::vector<std::vector<double>>> state(whole.materials.size());
      for (int i = 0; i < parts; ++i) {
        const Checkpoint p = read_checkpoint_part(path, CheckpointPart{i, parts, i == 0});
        EXPECT_EQ(p.first, cat.size()) << parts << " parts, part " << i;
        EXPECT_EQ(p.total, whole.particles.size());
        EXPECT_EQ(p.driver.series.empty(), i != 0);
        EXPECT_EQ(p.solver.step, whole.solver.step);
        ParticleSet::for_each_array([&](const auto& a) {
          const auto& v = p.particles.*a.member;
          (cat.*a.member).insert((cat.*a.member).end(), v.begin(), v.end());
          const auto& o = p.solver.outflow.*a.member;
          (ocat.*a.member).insert((ocat.*a.member).end(), o.begin(), o.end());
        });
        otime.insert(otime.end(), p.solver.outflow_time.begin(), p.solver.outflow_time.end());
        ASSERT_EQ(p.solver.outflow_fields.size(), ofields.size()) << "every part carries the field list";
        for (std::size_t f = 0; f < ofields.size(); ++f) {
          EXPECT_EQ(p.solver.outflow_fields[f].name, whole.solver.outflow_fields[f].name);
          ofields[f].insert(ofields[f].end(), p.solver.outflow_fields[f].values.begin(),
                            p.solver.outflow_fields[f].values.end());
        }
        ASSERT_EQ(p.materials.size(), whole.materials.size());
        for (std::size_t m = 0; m < p.materials.size(); ++m) {
          const MaterialState& s = p.materials[m];
          EXPECT_LE(s.begin, s.end);
          EXPECT_LE(s.end, p.particles.size());
          state[m].resize(s.fields.size());
          for (std::size_t f = 0; f < s.fields.size(); ++f)
            state[m][f].insert(state[m][f].end(), s.fields[f].second.begin(), s.fields[f].second.end());
        }
      }
      EXPECT_EQ(cat.id, whole.particles.id) << parts << " parts";
      EXPECT_EQ(cat.x, whole.particles.x);
      EXPECT_EQ(cat.F, whole.particles.F);
      EXPECT_EQ(cat.q, whole.particles.q);
      EXPECT_EQ(cat.material, whole.particles.material);
      for (std::size_t m = 0; m < whole.materials.size(); ++m)
        for (std::size_t f = 0; f < whole.materials[m].fields.size(); ++f)
          EXPECT_EQ(state[m][f], whole.materials[m].fields[f].second) << parts << " parts, material " << m << " field " << f;
      EXPECT_EQ(ocat.id, whole.solver.outflow.id) << parts << " parts: the outflow record";
      EXPECT_EQ(ocat.x, whole.solver.outflow.x);
      EXPECT_EQ(ocat.v, whole.solver.outflow.v);
      EXPECT_EQ(otime, whole.solver.outflow_time);
      for (std::size_t f = 0; f < ofields.size(); ++f)
        EXPECT_EQ(ofields[f], whole.solver.outflow_fields[f].values) << whole.solver.outflow_fields[f].name;
    }
    EXPECT_THROW(read_checkpoint_part(path, CheckpointPart{3, 3, false}), std::logic_error);
  }
}

// A corrupt or truncated checkpoint: every rank reads its own part, and every rank throws the
// same InputError (exit 2), none waits in a collective. Truncated: the first 64 KiB of a real one.
TEST(MpmMpiFiles, CorruptCheckpointIsRefusedOnEveryRank) {
  SharedDir dir;
  ImpactAt20us run;
  const std::string good = dir.path + "/ck.h5", cut = dir.path + "/cut.h5", junk = dir.path + "/junk.h5";
  mpi::write_checkpoint_mpi(run.dom, good, run.d, kProv, "");
  if (rank() == 0) {
    const std::string b = bytes_of(good);
    ASSERT_GT(b.size(), 65536u);
    std::ofstream(cut, std::ios::binary) << b.substr(0, 65536);
    std::ofstream(junk, std::ios::binary) << std::string(4096, 'x');
  }
  MPI_Barrier(MPI_COMM_WORLD);
  mpi::Comm comm(MPI_COMM_WORLD);
  for (const std::string& path : {cut, junk}) {
    try {
      mpi::read_checkpoint_mpi(comm, path, common::RunIdentity{});
      ADD_FAILURE() << path << " was accepted";
    } catch (const common::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}
