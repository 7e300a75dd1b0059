/// @file test_helpers.hpp
/// Helpers for mpm tests: build a solver from TOML text (the same path as mpm-frag).
#pragma once
#include <functional>
#include <string>

#include "mpm/scene_setup.hpp"
#include "mpm/solver.hpp"

namespace mpmtest {

inline mpmfrag::Setup setup_from(const std::string& toml, const std::vector<std::string>& overrides = {}) {
  static const common::Schema schema = mpmfrag::mpm_schema();
  return mpmfrag::build_setup(common::Scene::parse(schema, toml, "test-scene", overrides));
}

inline mpmfrag::Solver solver_from(mpmfrag::Setup st) {
  mpmfrag::Solver s(st.solver, st.grid, std::move(st.particles), std::move(st.materials));
  s.initialize();
  return s;
}

/// Step to time t (landing exactly on it); `each` is called after every step.
inline void run_to(mpmfrag::Solver& s, double t, const std::function<void(const mpmfrag::Solver&, double)>& each = {}) {
  while (s.time() < t * (1 - 1e-12)) {
    const double dt = std::min(s.stable_dt(), t - s.time());
    s.step(dt);
    if (each) each(s, dt);
  }
}

}  // namespace mpmtest
