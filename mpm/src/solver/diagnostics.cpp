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
  // the styles' stored (elastic) and dissipated energies, per material chunk
  const std::size_t nch = chunks_.size();
  std::vector<double> el(nch, 0.0), di(nch, 0.0);
#pragma omp parallel
  {
    std::vector<double> a(kChunk), b(kChunk);
#pragma omp for schedule(static)
    for (std::size_t c = 0; c < nch; ++c) {
      const Chunk& ch = chunks_[c];
      material_energies(static_cast<std::size_t>(ch.mat), ch.begin, ch.end - ch.begin, a.data(), b.data());
      for (std::size_t k = 0; k < ch.end - ch.begin; ++k) {
        el[c] += a[k];
        di[c] += b[k];
      }
    }
  }
  Diagnostics t;
  for (std::size_t c = 0; c < nch; ++c) {
    t.elastic += el[c];
    t.dissipated += di[c];
  }
  part.push_back(out_diag_);  // removed particles: constant totals, summed last (same order always)
  for (const Diagnostics& d : part) {
    t.mass += d.mass;
    t.momentum += d.momentum;
    t.angular_momentum += d.angular_momentum;
    t.kinetic += d.kinetic;
    t.internal += d.internal;
    t.work_dev += d.work_dev;
    t.heat_shock += d.heat_shock;
    t.heat_transfer += d.heat_transfer;
  }
  t.elastic += out_diag_.elastic;
  t.dissipated += out_diag_.dissipated;
  t.removed = out_.size();
  t.removed_mass = out_diag_.mass;
  return t;
}

void Solver::material_energies(std::size_t mat, std::size_t begin, std::size_t n, double* el, double* di) const {
  const MaterialSlot& slot = mats_[mat];
  std::vector<double*> sp(slot.state.size());
  for (std::size_t f = 0; f < slot.state.size(); ++f)
    sp[f] = state_pointer(slot, f, begin);
  MaterialBatch b;
  b.n = n;
  b.first = begin;
  b.cell_size = h_min_;
  b.seed = cfg_.seed;
  b.F = ps_.F.data() + 9 * begin;
  b.stress = const_cast<double*>(ps_.stress.data()) + 6 * begin;  // read-only in stored_energies
  b.mass = ps_.mass.data() + begin;
  b.volume = ps_.volume.data() + begin;
  b.volume0 = ps_.volume0.data() + begin;
  b.energy = ps_.energy.data() + begin;
  b.id = ps_.id.data() + begin;
  b.state = sp.data();
  slot.model->stored_energies(b, el, di);
}

double Solver::bytes_per_particle() const {
  std::size_t b = ps_.bytes();
  for (const MaterialSlot& s : mats_) b += s.bytes();
  return static_cast<double>(b) / static_cast<double>(ps_.size());
}

std::size_t Solver::grid_bytes() const { return nodes_.size() * sizeof(Node); }

}  // namespace mpmfrag
