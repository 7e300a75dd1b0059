/// @file style_batch.hpp
/// A batch of n Tonge–Ramesh particles of volume V at rest (F = I, zero stress) driven in
/// uniaxial strain along x through the style's MaterialBatch interface (bench_damage.cpp,
/// test_style.cpp).
#pragma once
#include <cstdint>
#include <vector>

#include "mpm/tonge_ramesh/style.hpp"

namespace mpmfrag {

struct Batch {
  std::size_t n;
  std::vector<double> L, F, stress, mass, vol, vol0, energy, ws, bs;
  std::vector<std::uint64_t> id;
  std::vector<std::vector<double>> state;
  std::vector<double*> sp;
  MaterialBatch b;
  Batch(std::size_t n_, double V) : n(n_) {
    L.assign(9 * n, 0.0);
    F.assign(9 * n, 0.0);
    for (std::size_t k = 0; k < n; ++k) F[9 * k] = F[9 * k + 4] = F[9 * k + 8] = 1.0;
    stress.assign(6 * n, 0.0);
    mass.assign(n, 2700 * V);
    vol.assign(n, V);
    vol0.assign(n, V);
    energy.assign(n, 0.0);
    ws.assign(n, 0.0);
    bs.assign(n, 0.0);
    id.resize(n);
    for (std::size_t k = 0; k < n; ++k) id[k] = k;
    for (const auto& f : tonge_ramesh_state_fields()) state.emplace_back(n * f.ncomp, f.initial);
    for (auto& s : state) sp.push_back(s.data());
    b.n = n;
    b.L = L.data();
    b.F = F.data();
    b.stress = stress.data();
    b.mass = mass.data();
    b.volume = vol.data();
    b.volume0 = vol0.data();
    b.energy = energy.data();
    b.id = id.data();
    b.state = sp.data();
    b.wave_speed = ws.data();
    b.bulk_speed = bs.data();
    b.seed = 1;
  }
  /// One step of uniaxial strain at `rate` along x.
  void advance(double rate, double dt) {
    b.dt = dt;
    for (std::size_t k = 0; k < n; ++k) {
      L[9 * k] = rate;
      F[9 * k] *= 1.0 + rate * dt;
    }
  }
};

}  // namespace mpmfrag
