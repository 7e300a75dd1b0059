/// @file diagnostics.cpp
/// Monitored totals of the solver (deterministic chunked sums, the same for any thread count)
/// and its memory figures:
///
///   M = sum m_p,  P = sum m_p v_p,  L = sum m_p x_p × v_p (about the origin),
///   K = sum m_p |v_p|^2 / 2,  U = sum m_p e_p
///
/// over the grid particles in chunks of kReduceChunk summed in chunk order, plus the constant
/// totals of the particles removed at the grid edge (outflow.cpp), summed last.
#include <algorithm>

#include "kernels.hpp"

namespace mpmfrag {

using namespace detail;

Diagnostics Solver::diagnostics() const {
  const std::size_t n = ps_.size();
  const std::size_t nc = (n + kReduceChunk - 1) / kReduceChunk;
  std::vector<Diagnostics> part(nc);
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < nc; ++c) {
    Diagnostics d;
    for (std::size_t p = c * kReduceChunk; p < std::min(n, (c + 1) * kReduceChunk); ++p) add_particle_totals(d, ps_, p);
    part[c] = d;
  }
  Diagnostics t;
  part.push_back(out_diag_);  // removed particles: constant totals, summed last (same order always)
  for (const Diagnostics& d : part) {
    t.mass += d.mass;
    t.momentum += d.momentum;
    t.angular_momentum += d.angular_momentum;
    t.kinetic += d.kinetic;
    t.internal += d.internal;
  }
  t.removed = out_.size();
  t.removed_mass = out_diag_.mass;
  return t;
}

double Solver::bytes_per_particle() const {
  std::size_t b = ps_.bytes();
  for (const MaterialSlot& s : mats_) b += s.bytes();
  return static_cast<double>(b) / static_cast<double>(ps_.size());
}

std::size_t Solver::grid_bytes() const { return nodes_.size() * sizeof(Node); }

}  // namespace mpmfrag
