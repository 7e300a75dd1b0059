/// @file test_tool.cpp
/// ssdem-analyse end to end: a time series of constructed sphere files -> JSON/CSV outputs with
/// the expected numbers; bad inputs -> exit code 2 naming the file and key.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>

#include <unistd.h>

#include "analysis/analyse_scene.hpp"
#include "analysis/run_analysis.hpp"
#include "common/status.hpp"
#include "common/h5.hpp"
#include "common/particle_file.hpp"
#include "common/sphere_file.hpp"
#include "sphere_configs.hpp"

namespace fs = std::filesystem;
using analysis_test::add;
using analysis_test::add_cube;

namespace {
struct RunResult {
  int code;
  std::string out;
};
RunResult run(const std::string& args) {
  // One log per test process: ctest runs the tests of this file in parallel processes.
  const std::string log =
      (fs::temp_directory_path() / ("ssdem_analyse_test_" + std::to_string(getpid()) + ".log")).string();
  const int rc = std::system((std::string(SSDEM_ANALYSE_EXE) + " " + args + " > " + log + " 2>&1").c_str());
  std::ifstream f(log);
  std::stringstream ss;
  ss << f.rdbuf();
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, ss.str()};
}
std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}
common::Provenance prov() { return common::Provenance{"test", "0", "0", "test", ""}; }

// t = 0: 64 touching spheres (target, damage 0.2) + 1 small sphere (impactor remnant) touching;
// t = 100 s: same cube, 2 escaping ejecta (damage 1) and one slow bound fragment (damage 0.5).
common::SphereSet snapshot(double t) {
  common::SphereSet s;
  s.time = t;
  s.step = static_cast<std::int64_t>(t);
  add_cube(s, {0, 0, 0}, 4, 100.0, 1e12, {0, 0, -0.01}, 0.2);
  if (t == 0) {
    add(s, {300, 300, 700 + 10}, 10.0, 1e9, {0, 0, -0.01}, 0.9);
  } else {
    add(s, {300, 300, 5e5}, 10.0, 1e9, {0, 0, 3000.0}, 1.0);
    add(s, {300, -5e5, 300}, 10.0, 1e9, {0, -2000.0, 0}, 1.0);
    add(s, {300, 300, 3000}, 10.0, 1e10, {0, 0, 0.01}, 0.5);
  }
  return s;
}
}  // namespace

TEST(AnalyseTool, TimeSeriesSummaryAndProfiles) {
  const fs::path dir = fs::temp_directory_path() / "ssdem_analyse_tool";
  fs::remove_all(dir);
  fs::create_directories(dir);
  common::write_sphere_set((dir / "late.h5").string(), snapshot(100.0), prov());
  // the hand-off file carries the MPM end time; on the N-body clock it is t = 0
  common::SphereSet handoff = snapshot(0.0);
  handoff.time = 30.0;
  common::Provenance hp = prov();
  hp.tool = "mpm2spheres";
  common::write_sphere_set((dir / "early.h5").string(), handoff, hp);
  // late given first: the tool orders by time
  const RunResult r = run((dir / "late.h5").string() + " " + (dir / "early.h5").string() + " -o " + (dir / "out/an").string() +
                    " --impactor-mass 1e9 --impactor-velocity '[0,0,-5000]' --parent-mass 6.4e13");
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string js = slurp(dir / "out/an.json");
  EXPECT_NE(js.find("\"format\": \"ssdem-analyse.summary\""), std::string::npos);
  EXPECT_NE(js.find("\"M_LR_over_M_PB\": 1,"), std::string::npos) << js;  // 64e12 / 6.4e13
  EXPECT_NE(js.find("\"n_clumps\": 4,"), std::string::npos) << js;
  EXPECT_NE(js.find("\"escaping_mass\": 2000000000,"), std::string::npos) << js;
  EXPECT_NE(js.find("\"bound_mass\": 64010000000000,"), std::string::npos) << js;
  EXPECT_NE(js.find("\"definitions\""), std::string::npos);
  const std::string ts = slurp(dir / "out/an.timeseries.csv");
  std::istringstream lines(ts);
  std::string header, row0, row1;
  std::getline(lines, header);
  std::getline(lines, row0);
  std::getline(lines, row1);
  EXPECT_EQ(header.rfind("time,M_LR_over_M_PB,bound_mass_fraction,beta,n_clumps,escaping_mass,", 0), 0u);
  EXPECT_EQ(row0.rfind("0,1,1.000015625,", 0), 0u) << row0;  // t = 0: the slow impactor sphere is bound
  EXPECT_EQ(row1.rfind("100,1,1.00015625,", 0), 0u) << row1;
  // beta at t = 100: P_bound.z = 64e12 * -0.01 + 1e10 * 0.01 = -6.399e11, / (1e9 * -5000) -> 0.12798
  EXPECT_NE(row1.find(",0.12798,4,"), std::string::npos) << row1;
  const std::string dc = slurp(dir / "out/an.damage.csv");
  EXPECT_NE(dc.find("nbody_end,"), std::string::npos);
  EXPECT_NE(dc.find("handoff,"), std::string::npos);
  EXPECT_NE(dc.find(",bound,axial,"), std::string::npos);
}

TEST(AnalyseTool, BadInputsExitWithCodeTwoNamingFileAndKey) {
  const fs::path dir = fs::temp_directory_path() / "ssdem_analyse_bad";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // no inputs
  RunResult r = run("-o " + (dir / "x").string());
  EXPECT_EQ(r.code, 2) << r.out;
  // missing file
  r = run((dir / "nope.h5").string() + " -o " + (dir / "x").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("nope.h5"), std::string::npos) << r.out;
  // an MPM particle snapshot given as a sphere time series
  common::ParticleSnapshot p;
  p.id = {0};
  p.position = {0, 0, 0};
  p.velocity = {0, 0, 0};
  p.mass = {1};
  p.volume = {1};
  p.size = {1, 1, 1};
  p.material = {0};
  p.grid.shape = {2, 2, 2};
  common::write_particle_snapshot((dir / "mpm.h5").string(), p, prov());
  r = run((dir / "mpm.h5").string() + " -o " + (dir / "x").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("mpm.h5"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("format"), std::string::npos) << r.out;
  // a sphere file given where the MPM snapshot belongs is fine; a file of another kind is not
  common::write_sphere_set((dir / "s.h5").string(), snapshot(0.0), prov());
  {
    std::ofstream junk(dir / "junk.h5");
    junk << "not hdf5";
  }
  r = run((dir / "s.h5").string() + " --mpm " + (dir / "junk.h5").string() + " -o " + (dir / "x").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("junk.h5"), std::string::npos) << r.out;
  // a malformed profile axis names the key
  r = run((dir / "s.h5").string() + " --set 'damage.axis=[1,0]' -o " + (dir / "x").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("damage.axis"), std::string::npos) << r.out;
  // a sphere file of an older format version
  common::write_sphere_set((dir / "old.h5").string(), snapshot(0.0), prov());
  {
    common::h5::quiet_errors();
    common::h5::Handle f(H5Fopen((dir / "old.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT));
    H5Adelete(f, "format_version");
    common::h5::write_attr(f, "format_version", std::int64_t{0});
  }
  r = run((dir / "old.h5").string() + " -o " + (dir / "x").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find((dir / "old.h5").string() + ": /format_version: version 0 is older"), std::string::npos) << r.out;
  // unknown scene key
  r = run((dir / "s.h5").string() + " --set fof.linking=0.3 -o " + (dir / "x").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("fof.linking"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir / "x.json"));
  // a good run for contrast; an MPM snapshot without damage (no damage model) is noted, not fatal
  r = run((dir / "s.h5").string() + " --mpm " + (dir / "mpm.h5").string() + " -o " + (dir / "x").string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(fs::exists(dir / "x.json"));
  EXPECT_NE(slurp(dir / "x.json").find("/particles/damage missing"), std::string::npos);
}

TEST(AnalyseTool, ImpactTakenFromTheInitialMpmSnapshot) {
  const fs::path dir = fs::temp_directory_path() / "ssdem_analyse_mpm0";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // t = 0: 64 target particles at rest (1e12 kg) + 3 impactor particles (1e9 kg) at -5 km/s z
  common::ParticleSnapshot p;
  p.grid.shape = {2, 2, 2};
  for (int i = 0; i < 67; ++i) {
    const bool imp = i >= 64;
    p.id.push_back(i);
    p.position.insert(p.position.end(), {100.0 * (i % 4), 100.0 * ((i / 4) % 4), imp ? 500.0 + 100 * (i - 64) : 100.0 * (i / 16)});
    p.velocity.insert(p.velocity.end(), {0.0, 0.0, imp ? -5000.0 : 0.0});
    p.mass.push_back(imp ? 1e9 : 1e12);
    p.volume.push_back(1.0);
    p.size.insert(p.size.end(), {100.0, 100.0, 100.0});
    p.material.push_back(0);
  }
  common::write_particle_snapshot((dir / "mpm0.h5").string(), p, prov());
  const analysis::MpmImpact mi = analysis::impact_from_mpm((dir / "mpm0.h5").string());
  EXPECT_DOUBLE_EQ(mi.impactor_mass, 3e9);
  EXPECT_DOUBLE_EQ(mi.target_mass, 64e12);
  EXPECT_EQ(mi.impactor_particles, 3u);
  EXPECT_TRUE(mi.impactor_velocity.isApprox(Eigen::Vector3d(0, 0, -5000)));
  EXPECT_TRUE(mi.target_velocity.isZero());
  common::write_sphere_set((dir / "s.h5").string(), snapshot(100.0), prov());
  RunResult r = run((dir / "s.h5").string() + " --mpm-initial " + (dir / "mpm0.h5").string() + " -o " + (dir / "a").string());
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string js = slurp(dir / "a.json");
  EXPECT_NE(js.find("\"impactor_mass\": 3000000000,"), std::string::npos) << js;
  EXPECT_NE(js.find("\"parent_body_mass\": 64000000000000,"), std::string::npos) << js;
  EXPECT_NE(js.find("\"impact_source\": \"initial MPM snapshot"), std::string::npos) << js;
  // an explicitly given value wins over the snapshot's
  r = run((dir / "s.h5").string() + " --mpm-initial " + (dir / "mpm0.h5").string() + " --impactor-mass 5e9 -o " +
          (dir / "b").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(slurp(dir / "b.json").find("\"impactor_mass\": 5000000000,"), std::string::npos);
  // all particles at rest: no impactor to find -> exit 2 naming the dataset
  for (auto& v : p.velocity) v = 0.0;
  common::write_particle_snapshot((dir / "rest.h5").string(), p, prov());
  r = run((dir / "s.h5").string() + " --mpm-initial " + (dir / "rest.h5").string() + " -o " + (dir / "c").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("/particles/velocity"), std::string::npos) << r.out;
}

// The three outputs are one set: a rerun that fails while writing (a file-size limit standing for
// a full disk) exits 4 and leaves the earlier set byte for byte, with no temporary file.
TEST(AnalyseTool, OutputsAreReplacedAsASetOrNotAtAll) {
  const fs::path dir = fs::temp_directory_path() / ("ssdem_analyse_set_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  common::write_sphere_set((dir / "late.h5").string(), snapshot(100.0), prov());
  const std::string args = (dir / "late.h5").string() + " -o " + (dir / "an").string() +
                           " --impactor-mass 1e9 --impactor-velocity '[0,0,-5000]' --parent-mass ";
  ASSERT_EQ(run(args + "6.4e13").code, 0);
  std::map<std::string, std::string> before;
  for (const char* ext : {".json", ".timeseries.csv", ".damage.csv"}) before[ext] = slurp(dir / ("an" + std::string(ext)));
  ASSERT_GT(before[".json"].size(), 4096u);  // the JSON is over the limit below
  // another parent mass (other numbers), files limited to 4 KB (SIGXFSZ ignored: write fails)
  const RunResult r = run("--version > /dev/null; trap '' XFSZ; ulimit -f 4; " + std::string(SSDEM_ANALYSE_EXE) + " " +
                          args + "7e13");
  EXPECT_EQ(r.code, 4) << r.out;
  EXPECT_NE(r.out.find(": write failed: File too large"), std::string::npos) << r.out;
  for (const auto& [ext, text] : before) EXPECT_EQ(slurp(dir / ("an" + ext)), text) << ext;
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.path().filename().string().rfind("an", 0) == 0;
  EXPECT_EQ(files, 3u);  // no temporary left
  fs::remove_all(dir);
}

// A NaN or Inf result is never written (the CSV would show an empty cell): exit 3 naming it.
TEST(AnalyseTool, NonFiniteResultsAreRefusedNamingTheQuantity) {
  analysis::AnalysisOutcome o;
  o.parent_body_mass = 1.0;
  analysis::SnapshotResult r;
  r.file = "s.h5";
  r.time = 5.0;
  r.bound.bound_mass = std::numeric_limits<double>::infinity();
  o.rows.push_back(r);
  try {
    analysis::check_outcome_finite(o, "out/an.json");
    FAIL() << "expected NumericalError";
  } catch (const common::NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("out/an.json: s.h5 (t = 5.000000 s)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bound_mass"), std::string::npos) << e.what();
  }
  o.rows[0].bound.bound_mass = 1.0;
  EXPECT_NO_THROW(analysis::check_outcome_finite(o, "out/an.json"));
}
