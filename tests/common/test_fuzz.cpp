/// @file test_fuzz.cpp
/// Mutation fuzzing without libFuzzer: seeded, bounded, registered with label `fuzz` (also run under
/// ASan+UBSan). Every case must end in success or a typed error (InputError, IoError): never another
/// exception, a crash or a hang (each case runs in a child process, see fuzz_harness.hpp).
///
///  - HDF5 readers: a small valid particle snapshot and sphere set with 1-64 bytes overwritten at
///    seeded random offsets (or truncated), read by read_particle_snapshot, read_sphere_set and
///    h5::read_provenance.
///  - Scene parser: each tool's schema (mpm-frag, mpm2spheres, ssdem-grav, ssdem-analyse) over its
///    resolved default scene and the shipped scene files, mutated (bytes flipped, ranges cut or
///    repeated, TOML tokens inserted, lines spliced), plus mutated --set overrides.
///
/// Knobs (environment): FUZZ_SEED, FUZZ_H5_CASES, FUZZ_SCENE_CASES, FUZZ_CASE_TIMEOUT_S, and
/// FUZZ_SAVE_DIR (failing HDF5 mutants are saved there as mutant_<index>.h5).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "analysis/analyse_scene.hpp"
#include "common/h5.hpp"
#include "common/schema.hpp"
#include "fuzz_harness.hpp"
#include "handoff/handoff_scene.hpp"
#include "mpm/scene_setup.hpp"
#include "ssdem/scene_setup.hpp"
#include "test_util.hpp"

namespace fs = std::filesystem;
using namespace common;

namespace {

std::uint64_t seed() { return static_cast<std::uint64_t>(fuzz::env_double("FUZZ_SEED", 20261202)); }

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void spit(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

/// Mutant `i` of one of `bases`: 1..64 random bytes overwritten at random offsets, or a truncation.
std::string h5_mutant(const std::vector<std::string>& bases, std::size_t i) {
  std::mt19937_64 rng(seed() * 1000003u + i);
  std::string s = bases[i % bases.size()];
  static const int kFlips[] = {1, 2, 3, 4, 8, 16, 64};
  const int mode = static_cast<int>(rng() % 16);
  if (mode == 0) {
    s.resize(rng() % s.size());
    return s;
  }
  const int flips = kFlips[rng() % std::size(kFlips)];
  for (int k = 0; k < flips; ++k) s[rng() % s.size()] = static_cast<char>(rng() & 0xff);
  return s;
}

void read_all_three(const std::string& path) {
  try {
    read_particle_snapshot(path);
  } catch (const InputError&) {
  }
  try {
    read_sphere_set(path);
  } catch (const InputError&) {
  }
  h5::Handle f = h5::open_file_read(path);
  h5::read_provenance(f, path);
}

TEST(Fuzz, Hdf5ReadersEndInSuccessOrTypedError) {
  testutil::TempDir dir;
  write_particle_snapshot(dir.file("p.h5"), testutil::sample_particles(8), testutil::sample_provenance());
  write_sphere_set(dir.file("s.h5"), testutil::sample_spheres(8), testutil::sample_provenance());
  const std::vector<std::string> bases = {slurp(dir.file("p.h5")), slurp(dir.file("s.h5"))};
  // A hanging mutant costs the readers' time limit (10 s by default) three times over; a limit too
  // short for a slow machine only turns an accepted mutant into an InputError, which is typed too.
  ::setenv("SUITE_H5_CHECK_TIMEOUT_S", "0.3", 0);
  const auto n = static_cast<std::size_t>(fuzz::env_double("FUZZ_H5_CASES", 300));
  const std::string mutant = dir.file("mutant.h5");
  const auto failures = fuzz::run_cases(n, fuzz::env_double("FUZZ_CASE_TIMEOUT_S", 30), [&](std::size_t i) {
    spit(mutant, h5_mutant(bases, i));
    read_all_three(mutant);
  });
  const char* save = std::getenv("FUZZ_SAVE_DIR");
  for (const auto& f : failures) {
    ADD_FAILURE() << "HDF5 mutant " << f.index << " (FUZZ_SEED=" << seed() << "): " << f.what;
    if (save) spit(std::string(save) + "/mutant_" + std::to_string(f.index) + ".h5", h5_mutant(bases, f.index));
  }
}

// ---- scene parser ----------------------------------------------------------------------------

const char* const kTokens[] = {"=", "[", "]", "[[", "]]", "{", "}", "\"", "'", "'''", "\"\"\"", "\n", ",", ".",
                               "#", "1e999", "-1e999", "nan", "inf", "-inf", "0x7fffffffffffffff",
                               "99999999999999999999999", "-9223372036854775808", "true", "1979-05-27T07:32:00Z",
                               "\\u0000", "\\", "\xff\xfe", "body[0].", "material[9999].", "[[body]]\n",
                               "[[material]]\n", "= []", "= {}", "= [[1,2],[3]]", "0.0", "-0", "\t", " = 1\n"};

struct SceneBase {
  const Schema* schema;
  std::string text;
};

std::string mutate_text(const std::vector<SceneBase>& bases, std::string s, std::mt19937_64& rng) {
  const int steps = 1 + static_cast<int>(rng() % 4);
  for (int k = 0; k < steps; ++k) {
    const std::size_t at = s.empty() ? 0 : rng() % (s.size() + 1);
    switch (rng() % 5) {
      case 0:
        if (!s.empty()) s[std::min(at, s.size() - 1)] = static_cast<char>(rng() & 0xff);
        break;
      case 1:
        s.erase(at, rng() % 40);
        break;
      case 2: {
        const std::string piece = s.substr(at, rng() % 60);
        s.insert(at, piece);
        break;
      }
      case 3:
        s.insert(at, kTokens[rng() % std::size(kTokens)]);
        break;
      default: {  // splice a line of another scene
        const std::string& other = bases[rng() % bases.size()].text;
        if (other.empty()) break;
        const std::size_t from = other.rfind('\n', rng() % other.size());
        const std::size_t b = from == std::string::npos ? 0 : from + 1;
        s.insert(at, other.substr(b, other.find('\n', b) - b) + "\n");
      }
    }
  }
  return s;
}

TEST(Fuzz, SceneParserEndsInSuccessOrTypedError) {
  static const Schema schemas[] = {mpmfrag::mpm_schema(), ssdem::ssdem_schema(), handoff::handoff_schema(),
                                   analysis::analyse_schema()};
  const std::vector<std::vector<std::string>> files = {
      {"mpm/scenes/elastic_sphere.toml", "mpm/scenes/basalt_impact.toml", "mpm/scenes/two_spheres.toml",
       "pipelines/impact/fragment.toml"},
      {"nbody/scenes/rubble_pile.toml", "nbody/scenes/two_bodies.toml", "pipelines/impact/reaccumulate.toml"},
      {},
      {"nbody/analysis/scenes/el_mir_2019.toml"}};
  std::vector<SceneBase> bases;
  for (std::size_t k = 0; k < std::size(schemas); ++k) {
    try {  // the resolved default scene: every key of the schema
      bases.push_back({&schemas[k], Scene::parse(schemas[k], "", "<defaults>").to_toml()});
    } catch (const InputError&) {
      bases.push_back({&schemas[k], ""});
    }
    for (const auto& f : files[k]) bases.push_back({&schemas[k], slurp(std::string(SUITE_SOURCE_DIR) + "/" + f)});
  }
  const auto n = static_cast<std::size_t>(fuzz::env_double("FUZZ_SCENE_CASES", 2000));
  const auto failures = fuzz::run_cases(n, fuzz::env_double("FUZZ_CASE_TIMEOUT_S", 30), [&](std::size_t i) {
    std::mt19937_64 rng(seed() * 7919u + i);
    const SceneBase& base = bases[i % bases.size()];
    const Schema& schema = rng() % 8 == 0 ? schemas[rng() % std::size(schemas)] : *base.schema;
    std::vector<std::string> overrides;
    std::string text = base.text;
    if (rng() % 4 == 0) {  // a mutated --set override on the base text
      const std::string& line = bases[rng() % bases.size()].text;
      const std::size_t eq = line.find('=');
      const std::size_t b = eq == std::string::npos ? 0 : line.rfind('\n', eq);
      std::string ov = eq == std::string::npos ? "time.end=1" : line.substr(b == std::string::npos ? 0 : b + 1);
      ov = ov.substr(0, ov.find('\n'));
      ov.erase(std::remove(ov.begin(), ov.end(), ' '), ov.end());
      overrides.push_back(mutate_text(bases, ov, rng));
    } else {
      text = mutate_text(bases, text, rng);
    }
    Scene s = Scene::parse(schema, text, "<fuzz>", overrides);
    (void)s.to_toml();
  });
  for (const auto& f : failures) ADD_FAILURE() << "scene case " << f.index << " (FUZZ_SEED=" << seed() << "): " << f.what;
}

}  // namespace
