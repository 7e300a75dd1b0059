/// @file test_sphere_file_mpi.cpp
/// The collective sphere-file writer (common/sphere_file_mpi.hpp) under mpirun -np 2 and -np 3:
/// each rank passes its own spheres in a scrambled order, with their file rows, and the carried
/// fields of its fixed block of rows; the file equals, by h5diff, the serial writer's file of the
/// whole set in row order: rows hashed over the ranks, the last rank holding none, all on one
/// rank, fewer spheres than ranks, none at all. A NaN on one rank is a NumericalError on every
/// rank with nothing written; a file-size limit an IoError on every rank with the earlier file
/// kept; block fields that do not match the rank's block are refused.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "common/sphere_file_mpi.hpp"
#include "common/status.hpp"
#include "mpi_test_util.hpp"

namespace {

using common::SphereSet;
using mpi_test::contents;
using mpi_test::prov;
using mpi_test::SharedDir;
using mpi_test::owner;
using mpi_test::Spread;
using mpi_test::world;
namespace fs = std::filesystem;

/// n spheres in row order, every value distinct; a carried field damage (1) and a per-sphere
/// field dissipated (1, J).
SphereSet global_set(std::size_t n) {
  SphereSet s;
  s.time = 3600.5;
  s.step = 77;
  s.resize(n);
  common::Field damage{"damage", "1", 1, {}, "scalar damage from mpm2spheres"}, diss{"dissipated", "J", 1, {}, ""};
  for (std::size_t k = 0; k < n; ++k) {
    s.id[k] = 1000 + 7 * ((k * 13) % (n + 1));  // ids not in row order
    for (int c = 0; c < 3; ++c) {
      s.position[3 * k + c] = 100.0 * k + c;
      s.velocity[3 * k + c] = -0.5 * k + c;
      s.spin[3 * k + c] = 1e-3 * k - 1e-4 * c;
    }
    s.mass[k] = 1e9 + k;
    s.radius[k] = 50.0 + 1e-3 * k;
    damage.values.push_back(1.0 / (1.0 + k));
    diss.values.push_back(1e3 * k);
  }
  s.fields = {damage, diss};
  return s;
}


/// This rank's spheres of g (rows in reverse order, with their rows; the per-sphere field only)
/// and its block of the carried field.
struct Part {
  SphereSet local;
  std::vector<std::uint64_t> row;
  std::vector<common::Field> block;
};
Part part(const SphereSet& g, Spread how) {
  Part p;
  p.local.time = g.time;
  p.local.step = g.step;
  const common::Field& diss = g.fields[1];
  p.local.fields = {common::Field{diss.name, diss.unit, 1, {}, diss.description}};
  for (std::size_t k = g.count(); k-- > 0;) {
    if (owner(k, how) != world().rank) continue;
    p.row.push_back(k);
    const std::size_t i = p.local.count();
    p.local.resize(i + 1);
    SphereSet::zip_arrays([&](const common::SphereArray& a, auto& to, const auto& from) {
      for (std::size_t c = 0; c < a.width; ++c) to[a.width * i + c] = from[a.width * k + c];
    }, p.local, g);
    p.local.fields[0].values.push_back(diss.values[k]);
  }
  const common::Field& dmg = g.fields[0];
  const std::size_t lo = common::mpi::dense_first(g.count(), world().size, world().rank),
                    hi = common::mpi::dense_first(g.count(), world().size, world().rank + 1);
  p.block = {common::Field{dmg.name, dmg.unit, 1, std::vector<double>(dmg.values.begin() + lo, dmg.values.begin() + hi),
                           dmg.description}};
  return p;
}

void check_against_serial(const SphereSet& g, Spread how, const std::string& dir) {
  const Part p = part(g, how);
  const std::string par = dir + "/par.h5", ser = dir + "/ser.h5";
  common::mpi::write_sphere_set_mpi(world(), par, p.local, p.row, p.block, prov());
  int same = 1;
  if (world().rank == 0) {
    common::write_sphere_set(ser, g, prov());
    same = std::system(("h5diff " + ser + " " + par).c_str()) == 0;
    EXPECT_TRUE(same) << "h5diff " << ser << " " << par << " (" << g.count() << " spheres)";
    std::string xs = contents(dir + "/ser.xmf");  // the sidecars differ only in the file name
    for (std::size_t at; (at = xs.find("ser.h5")) != std::string::npos;) xs.replace(at, 6, "par.h5");
    EXPECT_EQ(contents(dir + "/par.xmf"), xs);
    const SphereSet back = common::read_sphere_set(par);  // the reader's checks pass
    EXPECT_EQ(back.id, g.id);
    ASSERT_EQ(back.fields.size(), 2u);
    EXPECT_EQ(back.fields[0].name, "damage");
  }
  MPI_Bcast(&same, 1, MPI_INT, 0, MPI_COMM_WORLD);
  EXPECT_TRUE(same);
}

TEST(SphereFileMpi, CollectiveFileEqualsTheSerialWritersFile) {
  SharedDir d;
  const SphereSet g = global_set(1003);
  for (const Spread how : {Spread::hashed, Spread::last_empty, Spread::all_on_last}) check_against_serial(g, how, d.path);
}

TEST(SphereFileMpi, FewerSpheresThanRanksAndNone) {
  SharedDir d;
  check_against_serial(global_set(1), Spread::hashed, d.path);
  check_against_serial(global_set(0), Spread::hashed, d.path);
}

TEST(SphereFileMpi, ANanOnOneRankIsRefusedOnEveryRankWithNothingWritten) {
  SharedDir d;
  Part p = part(global_set(40), Spread::hashed);
  if (world().rank == world().size - 1 && p.local.count() > 0) p.local.velocity[1] = std::nan("");
  EXPECT_THROW(common::mpi::write_sphere_set_mpi(world(), d.path + "/x.h5", p.local, p.row, p.block, prov()),
               common::NumericalError);
  if (world().rank == 0) {
    EXPECT_TRUE(fs::is_empty(d.path));
  }
}

TEST(SphereFileMpi, AFullDiskThrowsOnEveryRankAndKeepsTheEarlierFile) {
  SharedDir d;
  const std::string path = d.path + "/snap.h5";
  const Part small = part(global_set(10), Spread::hashed);
  common::mpi::write_sphere_set_mpi(world(), path, small.local, small.row, small.block, prov());
  const std::string before = world().rank == 0 ? contents(path) : std::string();
  const Part big = part(global_set(10000), Spread::hashed);  // about 1.4 MB
  std::string what;
  const bool threw = mpi_test::io_error_under_file_size_limit(
      [&] { common::mpi::write_sphere_set_mpi(world(), path, big.local, big.row, big.block, prov()); }, &what);
  EXPECT_TRUE(threw) << "rank " << world().rank;
  EXPECT_NE(what.find(path), std::string::npos) << what;
  if (world().rank == 0) {
    EXPECT_EQ(contents(path), before) << "the earlier file changed";
    for (const auto& e : fs::directory_iterator(d.path))
      EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << "temporary left: " << e.path();
  }
}

TEST(SphereFileMpi, BlockFieldsThatDoNotMatchTheBlockAreRefused) {
  SharedDir d;
  Part p = part(global_set(30), Spread::hashed);
  p.block[0].values.push_back(0.5);  // one row too many on every rank
  EXPECT_THROW(common::mpi::write_sphere_set_mpi(world(), d.path + "/x.h5", p.local, p.row, p.block, prov()),
               std::logic_error);
  // on one rank only: every rank throws (none is left waiting in the row move)
  Part q = part(global_set(30), Spread::hashed);
  if (world().rank == world().size - 1) q.block[0].values.pop_back();
  EXPECT_THROW(common::mpi::write_sphere_set_mpi(world(), d.path + "/y.h5", q.local, q.row, q.block, prov()),
               std::logic_error);
  Part r = part(global_set(30), Spread::hashed);
  if (world().rank == 0) r.row.push_back(29);  // a row without a sphere
  EXPECT_THROW(common::mpi::write_sphere_set_mpi(world(), d.path + "/z.h5", r.local, r.row, r.block, prov()),
               std::logic_error);
}

}  // namespace
