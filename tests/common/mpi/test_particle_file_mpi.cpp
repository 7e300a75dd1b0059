/// @file test_particle_file_mpi.cpp
/// The collective particle-snapshot writer (common/particle_file_mpi.hpp) under mpirun -np 2 and
/// -np 3: every rank passes its own particles in a scrambled order; the file equals, by h5diff
/// (every dataset, attribute and unit), the serial writer's file of the whole set in file order
/// (materials in slot order, ids ascending): with the rows hashed over the ranks, with the last
/// rank holding none, with all on one rank, and with no particles at all. A file-size limit
/// (a full disk) throws IoError on every rank and leaves the earlier file and no temporary;
/// ranks whose field lists differ are refused on every rank.
#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "common/particle_file_mpi.hpp"
#include "common/status.hpp"
#include "mpi_test_util.hpp"

namespace {

using common::ParticleSnapshot;
using mpi_test::contents;
using mpi_test::prov;
using mpi_test::SharedDir;
using mpi_test::owner;
using mpi_test::Spread;
using mpi_test::world;
using common::mpi::RowKey;
namespace fs = std::filesystem;

/// n particles in file order: material 0 then 1, ids ascending within each (and interleaved
/// between them), every value distinct; fields damage (1) and stress (6, with a description).
ParticleSnapshot global_set(std::size_t n) {
  ParticleSnapshot s;
  s.time = 1.25e-3;
  s.step = 42;
  s.grid.origin = Eigen::Vector3d(-1, -2, -3);
  s.grid.cell_size = Eigen::Vector3d(0.5, 0.5, 0.25);
  s.grid.shape = {9, 11, 13};
  const std::size_t n0 = (2 * n) / 3;
  common::Field damage{"damage", "1", 1, {}, ""}, stress{"stress", "Pa", 6, {}, "Cauchy stress (Voigt)"};
  for (std::size_t k = 0; k < n; ++k) {
    const bool first = k < n0;
    const std::uint64_t id = first ? 2 * k + 1 : 2 * (k - n0);  // odd ids in material 0, even in 1
    s.id.push_back(id);
    s.material.push_back(first ? 0 : 3);
    for (int c = 0; c < 3; ++c) {
      s.position.push_back(0.001 * k + c);
      s.velocity.push_back(-0.5 * k + 10 * c);
      s.size.push_back(0.01 + 1e-6 * k + 1e-3 * c);
    }
    s.mass.push_back(1.0 + k);
    s.volume.push_back(0.5 + 1e-3 * k);
    damage.values.push_back(1.0 / (1.0 + k));
    for (int c = 0; c < 6; ++c) stress.values.push_back(1e6 * k - 1e3 * c);
  }
  s.fields = {damage, stress};
  return s;
}

/// The rows `rows` of `g` (in that order) as one rank's particles, with their keys.
ParticleSnapshot take(const ParticleSnapshot& g, const std::vector<std::size_t>& rows, std::vector<RowKey>& keys) {
  ParticleSnapshot s;
  s.time = g.time;
  s.step = g.step;
  s.grid = g.grid;
  for (const common::Field& f : g.fields) s.fields.push_back(common::Field{f.name, f.unit, f.ncomp, {}, f.description});
  keys.clear();
  for (const std::size_t k : rows) {
    s.id.push_back(g.id[k]);
    s.material.push_back(g.material[k]);
    for (int c = 0; c < 3; ++c) {
      s.position.push_back(g.position[3 * k + c]);
      s.velocity.push_back(g.velocity[3 * k + c]);
      s.size.push_back(g.size[3 * k + c]);
    }
    s.mass.push_back(g.mass[k]);
    s.volume.push_back(g.volume[k]);
    for (std::size_t f = 0; f < g.fields.size(); ++f) {
      const std::size_t nc = g.fields[f].ncomp;
      for (std::size_t c = 0; c < nc; ++c) s.fields[f].values.push_back(g.fields[f].values[nc * k + c]);
    }
    keys.push_back(RowKey{g.material[k] == 0 ? 0u : 1u, g.id[k]});
  }
  return s;
}


/// Write g collectively (each rank its rows, in reverse order) and serially on rank 0; h5diff.
void check_against_serial(const ParticleSnapshot& g, Spread how, const std::string& dir) {
  std::vector<std::size_t> mine;
  for (std::size_t k = g.count(); k-- > 0;)
    if (owner(k, how) == world().rank) mine.push_back(k);
  std::vector<RowKey> keys;
  const ParticleSnapshot local = take(g, mine, keys);
  const std::string par = dir + "/par.h5", ser = dir + "/ser.h5";
  common::mpi::write_particle_snapshot_mpi(world(), par, local, keys, prov());
  int same = 1;
  if (world().rank == 0) {
    common::write_particle_snapshot(ser, g, prov());
    const int rc = std::system(("h5diff " + ser + " " + par).c_str());
    same = rc == 0;
    EXPECT_TRUE(same) << "h5diff " << ser << " " << par << " (" << g.count() << " particles)";
    EXPECT_TRUE(fs::exists(dir + "/par.xmf"));
    const ParticleSnapshot back = common::read_particle_snapshot(par);  // the reader's checks pass
    EXPECT_EQ(back.id, g.id);
    EXPECT_EQ(back.fields.size(), 2u);
  }
  MPI_Bcast(&same, 1, MPI_INT, 0, MPI_COMM_WORLD);
  EXPECT_TRUE(same);
}

TEST(ParticleFileMpi, CollectiveFileEqualsTheSerialWritersFile) {
  SharedDir d;
  const ParticleSnapshot g = global_set(1001);
  for (const Spread how : {Spread::hashed, Spread::last_empty, Spread::all_on_last}) check_against_serial(g, how, d.path);
}

TEST(ParticleFileMpi, NoParticlesAtAll) {
  SharedDir d;
  check_against_serial(global_set(0), Spread::hashed, d.path);
}

TEST(ParticleFileMpi, AFullDiskThrowsOnEveryRankAndKeepsTheEarlierFile) {
  SharedDir d;
  const std::string path = d.path + "/snap.h5";
  std::vector<std::size_t> mine;
  const ParticleSnapshot small = global_set(10);
  for (std::size_t k = 0; k < small.count(); ++k)
    if (owner(k, Spread::hashed) == world().rank) mine.push_back(k);
  std::vector<RowKey> keys;
  common::mpi::write_particle_snapshot_mpi(world(), path, take(small, mine, keys), keys, prov());
  const std::string before = world().rank == 0 ? contents(path) : std::string();
  // a bigger snapshot (about 1.3 MB) under a 64 KiB file-size limit on every rank
  const ParticleSnapshot big = global_set(8000);
  mine.clear();
  for (std::size_t k = 0; k < big.count(); ++k)
    if (owner(k, Spread::hashed) == world().rank) mine.push_back(k);
  const ParticleSnapshot local = take(big, mine, keys);
  std::string what;
  const bool threw = mpi_test::io_error_under_file_size_limit(
      [&] { common::mpi::write_particle_snapshot_mpi(world(), path, local, keys, prov()); }, &what);
  EXPECT_TRUE(threw) << "rank " << world().rank;
  EXPECT_NE(what.find(path), std::string::npos) << what;
  if (world().rank == 0) {
    EXPECT_EQ(contents(path), before) << "the earlier file changed";
    for (const auto& e : fs::directory_iterator(d.path))
      EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << "temporary left: " << e.path();
  }
}

TEST(ParticleFileMpi, FieldListsThatDifferAreRefusedOnEveryRank) {
  SharedDir d;
  ParticleSnapshot g = global_set(12);
  std::vector<std::size_t> mine;
  for (std::size_t k = 0; k < g.count(); ++k)
    if (owner(k, Spread::hashed) == world().rank) mine.push_back(k);
  std::vector<RowKey> keys;
  ParticleSnapshot local = take(g, mine, keys);
  if (world().rank == 1) local.fields.pop_back();
  EXPECT_THROW(common::mpi::write_particle_snapshot_mpi(world(), d.path + "/x.h5", local, keys, prov()), std::logic_error);
  if (world().rank == 0) {
    EXPECT_FALSE(fs::exists(d.path + "/x.h5"));
  }
}

}  // namespace
