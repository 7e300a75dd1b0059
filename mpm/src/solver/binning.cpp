/// @file binning.cpp
/// Particle binning for the deterministic parallel scatter (see solver.hpp): every step each
/// particle gets the key of its block of kBlock^3 cells (counting sort, stable in particle
/// index; blocks coloured by the parity of their block coordinates, 8 colours), the grid-exit
/// check (stop, or outflow removal), the periodic locality reordering of the particle arrays,
/// and the fixed chunks (kChunk particles of one material) of the material update.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "kernels.hpp"

namespace mpmfrag {

using namespace detail;

void Solver::build_chunks() {
  chunks_.clear();
  for (std::size_t m = 0; m < mats_.size(); ++m)
    for (std::size_t b = mats_[m].begin; b < mats_[m].end; b += kChunk)
      chunks_.push_back({b, std::min(b + kChunk, mats_[m].end), static_cast<int>(m)});
  chunk_speed_.assign(chunks_.size(), 0.0);
  chunk_fail_.assign(chunks_.size(), 0);
  chunk_msg_.assign(chunks_.size(), std::string());
}

// ------------------------------------------------------------------------------------------
// Binning: block key per particle, counting sort stable in particle index.
template <int NPA>
void Solver::bin() {
  const std::size_t n = ps_.size();
  key_.resize(n);
  order_.resize(n);
  const double* x = ps_.x.data();
  const double* lp = ps_.half_width.data();
  std::size_t first_bad = n, first_nan = n, n_out = 0;
  if (cfg_.outflow_remove) out_flag_.assign(n, 0);
  char* flag = out_flag_.data();
#pragma omp parallel for schedule(static) reduction(min : first_bad, first_nan) reduction(+ : n_out)
  for (std::size_t p = 0; p < n; ++p) {
    int f[3];
    bool ok = true, finite = true;
    for (int d = 0; d < 3; ++d) {
      const AxisWeights a = axis_weights(cfg_.shape, x[3 * p + d], grid_.origin[d], grid_.cell_size[d], lp[3 * p + d]);
      f[d] = a.first - sub_.lo[d];  // index in the box held (the whole grid when serial)
      if (!(f[d] >= 0 && f[d] + NPA <= sub_.shape[d])) ok = false;
      if (!std::isfinite(x[3 * p + d])) finite = ok = false;
    }
    if (!ok) {
      first_bad = std::min(first_bad, p);
      if (!finite) first_nan = std::min(first_nan, p);
      if (cfg_.outflow_remove) flag[p] = 1;
      ++n_out;
      key_[p] = 0;
      continue;
    }
    key_[p] = static_cast<std::uint32_t>(f[0] / kBlock + nblocks_[0] * (f[1] / kBlock + nblocks_[1] * (f[2] / kBlock)));
  }
  if (first_nan < n) {
    std::ostringstream os;
    os << "non-finite position of particle id " << ps_.id[first_nan] << " at t = " << time_ << " s, step " << step_;
    throw SolverFailure(os.str(), true);
  }
  if (cfg_.outflow_remove && sub_.exchange && !rebinning_) {
    // On MPI ranks (every rank, once per step: the re-binning below, on the removing ranks only,
    // does not reduce): every particle of every rank leaving stops the run before any is
    // removed, the state intact, as remove_particles does on one process.
    if (!any_process(n_out < n)) {
      std::ostringstream os;
      os << "all particles left the grid by t = " << time_ << " s, step " << step_;
      throw SolverFailure(os.str(), true);
    }
  }
  if (n_out > 0 && cfg_.outflow_remove) {
    remove_particles(out_flag_);
    rebinning_ = true;
    bin<NPA>();
    rebinning_ = false;
    return;
  }
  if (first_bad < n) {
    std::ostringstream os;
    const std::size_t p = first_bad;
    os << "particle id " << ps_.id[p] << " (material '" << mats_[ps_.material[p]].name << "') at (" << x[3 * p]
       << ", " << x[3 * p + 1] << ", " << x[3 * p + 2] << ") m left the grid (its interpolation stencil"
       << " leaves the domain plus ghost layers) at t = " << time_ << " s, step " << step_
       << "; enlarge [grid] domain_min/domain_max or use fixed/symmetry faces";
    throw SolverFailure(os.str(), true);
  }
  const std::size_t nb = static_cast<std::size_t>(nblocks_[0]) * nblocks_[1] * nblocks_[2];
  block_start_.assign(nb + 1, 0);
  for (std::size_t p = 0; p < n; ++p) ++block_start_[key_[p] + 1];
  for (std::size_t b = 0; b < nb; ++b) block_start_[b + 1] += block_start_[b];
  std::vector<std::uint32_t> fill(block_start_.begin(), block_start_.end() - 1);
  for (std::size_t p = 0; p < n; ++p) order_[fill[key_[p]]++] = static_cast<std::uint32_t>(p);
  for (auto& c : colour_blocks_) c.clear();
  for (std::size_t b = 0; b < nb; ++b) {
    if (block_start_[b + 1] == block_start_[b]) continue;
    const std::size_t bx = b % nblocks_[0], by = (b / nblocks_[0]) % nblocks_[1], bz = b / (static_cast<std::size_t>(nblocks_[0]) * nblocks_[1]);
    colour_blocks_[(bx & 1) | ((by & 1) << 1) | ((bz & 1) << 2)].push_back(static_cast<std::uint32_t>(b));
  }
}

template void Solver::bin<2>();
template void Solver::bin<3>();

// Locality: sort each material's particles by block key (stable), applied to every particle
// array (ParticleSet::for_each_array) and to the material state arrays.
void Solver::reorder() {
  const std::size_t n = ps_.size();
  std::vector<std::uint32_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0u);
  for (const MaterialSlot& s : mats_)
    std::sort(perm.begin() + s.begin, perm.begin() + s.end, [&](std::uint32_t a, std::uint32_t b) {
      return key_[a] != key_[b] ? key_[a] < key_[b] : a < b;
    });
  bool identity = true;
  for (std::size_t i = 0; i < n && identity; ++i) identity = perm[i] == i;
  if (identity) return;
  auto apply = [&](auto& vec, std::size_t stride, std::size_t offset, std::size_t count) {
    if (vec.empty()) return;
    using T = typename std::decay_t<decltype(vec)>::value_type;
    std::vector<T> tmp(vec.size());
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < count; ++i)
      for (std::size_t c = 0; c < stride; ++c) tmp[stride * i + c] = vec[stride * (perm[offset + i] - offset) + c];
    vec.swap(tmp);
  };
  ParticleSet::for_each_array(
      [&](const auto& a) { apply(ps_.*a.member, static_cast<std::size_t>(a.info.width), 0, n); });
  if (!body_accel_.empty()) body_accel_.clear();
  for (MaterialSlot& s : mats_)
    for (std::size_t f = 0; f < s.state.size(); ++f)
      apply(s.state[f], static_cast<std::size_t>(s.style->state_fields[f].ncomp), s.begin, s.end - s.begin);
}

}  // namespace mpmfrag
