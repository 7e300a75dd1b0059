/// @file outflow.cpp
/// Particles that leave the grid (SolverConfig::outflow_remove; see solver.hpp): removal,
/// compaction and the outflow record.
///
/// A particle whose interpolation stencil would reach past the ghost layers is taken out of the
/// MPM computation at the start of a step, before any update of that step: its core arrays, its
/// output state fields and the removal time are appended to the outflow record, and every
/// particle array (and each material's state arrays) is compacted in index order, so the result
/// does not depend on the thread count. A removed particle carries no stress and feels no grid
/// force, so it moves ballistically, x(t) = x_r + v_r (t - t_r): its momentum m v, its angular
/// momentum about the origin m x(t) x v (d/dt = m v x v = 0), its kinetic and internal energy are
/// constant, and diagnostics() adds them to the grid particles' totals, which therefore remain
/// the conserved totals of the whole system.
#include <algorithm>
#include <sstream>

#include "common/particle_file.hpp"
#include "kernels.hpp"
#include "mpm/output.hpp"

namespace mpmfrag {

void Solver::remove_particles(const std::vector<char>& out) {
  const std::size_t n = ps_.size();
  std::size_t n_out = 0;
  for (std::size_t p = 0; p < n; ++p) n_out += out[p] ? 1 : 0;
  if (n_out == 0) return;
  if (n_out == n && !sub_.exchange) {  // on MPI ranks a rank may empty: bin() checks the total
    std::ostringstream os;
    os << "all " << n << " particles left the grid by t = " << time_ << " s, step " << step_;
    throw SolverFailure(os.str(), true);
  }
  // 1. Append the leaving particles to the outflow record (index order).
  const std::size_t n0 = out_.size();
  const bool with_q = !ps_.q.empty();
  out_.resize(n0 + n_out, with_q);
  out_time_.resize(n0 + n_out, time_);
  // Fields are merged by name; a particle whose material lacks a field gets its initial value.
  auto field_index = [&](const StateField& sf) {
    for (std::size_t i = 0; i < out_fields_.size(); ++i)
      if (out_fields_[i].name == sf.name) return i;
    out_fields_.push_back({sf.name, sf.unit, static_cast<std::size_t>(sf.ncomp),
                           std::vector<double>((n0 + n_out) * sf.ncomp, sf.initial), sf.description});
    out_init_.push_back(sf.initial);
    return out_fields_.size() - 1;
  };
  for (std::size_t i = 0; i < out_fields_.size(); ++i)
    out_fields_[i].values.resize((n0 + n_out) * out_fields_[i].ncomp, out_init_[i]);
  std::size_t k = n0;
  for (std::size_t p = 0; p < n; ++p) {
    if (!out[p]) continue;
    ParticleSet::for_each_array([&](const auto& a) {
      const auto& src = ps_.*a.member;
      if (src.empty()) return;  // optional array not in use (q)
      const std::size_t w = static_cast<std::size_t>(a.info.width);
      std::copy_n(src.begin() + w * p, w, (out_.*a.member).begin() + w * k);
    });
    // state fields: value of the particle's material, the field's initial value otherwise
    const MaterialSlot& s = mats_[ps_.material[p]];
    for (std::size_t f = 0; f < s.state.size(); ++f) {
      const StateField& sf = s.style->state_fields[f];
      if (!sf.output) continue;
      const std::size_t i = field_index(sf);
      std::copy_n(s.state[f].begin() + (p - s.begin) * sf.ncomp, sf.ncomp, out_fields_[i].values.begin() + k * sf.ncomp);
    }
    detail::add_particle_totals(out_diag_, ps_, p);
    double el = 0, di = 0;  // the style's stored and dissipated energy at removal (kept constant)
    material_energies(static_cast<std::size_t>(ps_.material[p]), p, 1, &el, &di);
    out_diag_.elastic += el;
    out_diag_.dissipated += di;
    ++k;
  }
  // 2. Compact the particle arrays and the material state (order preserved).
  std::vector<std::size_t> keep;
  keep.reserve(n - n_out);
  for (std::size_t p = 0; p < n; ++p)
    if (!out[p]) keep.push_back(p);
  auto compact = [&](auto& vec, std::size_t stride) {
    if (vec.empty()) return;
    for (std::size_t i = 0; i < keep.size(); ++i)
      if (keep[i] != i) std::copy_n(vec.begin() + stride * keep[i], stride, vec.begin() + stride * i);
    vec.resize(stride * keep.size());
  };
  for (MaterialSlot& s : mats_) {
    std::size_t kept = 0;
    for (std::size_t p = s.begin; p < s.end; ++p) kept += out[p] ? 0 : 1;
    for (std::size_t f = 0; f < s.state.size(); ++f) {
      const std::size_t nc = static_cast<std::size_t>(s.style->state_fields[f].ncomp);
      std::size_t j = 0;
      for (std::size_t p = s.begin; p < s.end; ++p) {
        if (out[p]) continue;
        if (p - s.begin != j) std::copy_n(s.state[f].begin() + nc * (p - s.begin), nc, s.state[f].begin() + nc * j);
        ++j;
      }
      s.state[f].resize(nc * kept);
    }
    s.end = s.begin + kept;  // begin shifted below
  }
  std::size_t start = 0;
  for (MaterialSlot& s : mats_) {
    const std::size_t len = s.end - s.begin;
    s.begin = start;
    s.end = start + len;
    start += len;
  }
  ParticleSet::for_each_array([&](const auto& a) { compact(ps_.*a.member, static_cast<std::size_t>(a.info.width)); });
  body_accel_.clear();
  key_.resize(ps_.size());
  order_.resize(ps_.size());
  build_chunks();
}

// The record's datasets are those of a snapshot (add_particle_datasets, the shared mapping),
// except: positions moved ballistically to the current time, `removal_time` first among the
// state datasets, and the stress described as the stress at removal.
common::ParticleSnapshot Solver::outflow_snapshot() const {
  return make_outflow_snapshot(out_, out_time_, out_fields_, grid_, time_, step_);
}

common::ParticleSnapshot make_outflow_snapshot(const ParticleSet& out, const std::vector<double>& removal_time,
                                               const std::vector<common::Field>& fields, const common::GridInfo& grid,
                                               double time, std::int64_t step) {
  common::ParticleSnapshot s;
  const std::size_t n = out.size();
  s.time = time;
  s.step = step;
  s.grid = grid;
  add_particle_datasets(s, out);
  for (std::size_t p = 0; p < n; ++p)
    for (int d = 0; d < 3; ++d) s.position[3 * p + d] = out.x[3 * p + d] + out.v[3 * p + d] * (time - removal_time[p]);
  for (common::Field& f : s.fields)
    if (f.name == "stress") f.description = "Cauchy stress at removal, Voigt xx,yy,zz,yz,xz,xy";
  s.fields.insert(s.fields.begin(), common::Field{"removal_time", "s", 1, removal_time, "time at which the particle left the grid"});
  for (const common::Field& f : fields) s.fields.push_back(f);
  return s;
}

}  // namespace mpmfrag
