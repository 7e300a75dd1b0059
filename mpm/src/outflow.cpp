/// @file outflow.cpp
/// Particles that leave the grid (SolverConfig::outflow_remove; see solver.hpp).
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
#include <Eigen/Geometry>

#include <algorithm>
#include <sstream>

#include "mpm/solver.hpp"

namespace mpmfrag {

void Solver::remove_particles(const std::vector<char>& out) {
  const std::size_t n = ps_.size();
  std::size_t n_out = 0;
  for (std::size_t p = 0; p < n; ++p) n_out += out[p] ? 1 : 0;
  if (n_out == 0) return;
  if (n_out == n) {
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
    auto copy = [&](auto& dst, const auto& src, std::size_t stride) {
      std::copy_n(src.begin() + stride * p, stride, dst.begin() + stride * k);
    };
    copy(out_.id, ps_.id, 1);
    copy(out_.material, ps_.material, 1);
    copy(out_.x, ps_.x, 3);
    copy(out_.v, ps_.v, 3);
    copy(out_.F, ps_.F, 9);
    copy(out_.stress, ps_.stress, 6);
    copy(out_.mass, ps_.mass, 1);
    copy(out_.volume, ps_.volume, 1);
    copy(out_.volume0, ps_.volume0, 1);
    copy(out_.energy, ps_.energy, 1);
    copy(out_.half_width, ps_.half_width, 3);
    if (with_q) copy(out_.q, ps_.q, 1);
    // state fields: value of the particle's material, the field's initial value otherwise
    const MaterialSlot& s = mats_[ps_.material[p]];
    for (std::size_t f = 0; f < s.state.size(); ++f) {
      const StateField& sf = s.style->state_fields[f];
      if (!sf.output) continue;
      const std::size_t i = field_index(sf);
      std::copy_n(s.state[f].begin() + (p - s.begin) * sf.ncomp, sf.ncomp, out_fields_[i].values.begin() + k * sf.ncomp);
    }
    const double m = ps_.mass[p];
    const Eigen::Vector3d x(ps_.x[3 * p], ps_.x[3 * p + 1], ps_.x[3 * p + 2]);
    const Eigen::Vector3d v(ps_.v[3 * p], ps_.v[3 * p + 1], ps_.v[3 * p + 2]);
    out_diag_.mass += m;
    out_diag_.momentum += m * v;
    out_diag_.angular_momentum += m * x.cross(v);
    out_diag_.kinetic += 0.5 * m * v.squaredNorm();
    out_diag_.internal += m * ps_.energy[p];
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
  compact(ps_.id, 1);
  compact(ps_.material, 1);
  compact(ps_.x, 3);
  compact(ps_.v, 3);
  compact(ps_.F, 9);
  compact(ps_.stress, 6);
  compact(ps_.mass, 1);
  compact(ps_.volume, 1);
  compact(ps_.volume0, 1);
  compact(ps_.energy, 1);
  compact(ps_.half_width, 3);
  compact(ps_.q, 1);
  body_accel_.clear();
  key_.resize(ps_.size());
  order_.resize(ps_.size());
  build_chunks();
}

common::ParticleSnapshot Solver::outflow_snapshot() const {
  common::ParticleSnapshot s;
  const std::size_t n = out_.size();
  s.time = time_;
  s.step = step_;
  s.grid = grid_;
  s.id = out_.id;
  s.velocity = out_.v;
  s.mass = out_.mass;
  s.volume = out_.volume;
  s.material = out_.material;
  s.position.resize(3 * n);
  s.size.resize(3 * n);
  for (std::size_t p = 0; p < n; ++p)
    for (int d = 0; d < 3; ++d) {
      s.position[3 * p + d] = out_.x[3 * p + d] + out_.v[3 * p + d] * (time_ - out_time_[p]);
      s.size[3 * p + d] = 2.0 * out_.half_width[3 * p + d];
    }
  s.fields.push_back({"removal_time", "s", 1, out_time_, "time at which the particle left the grid"});
  s.fields.push_back({"stress", "Pa", 6, out_.stress, "Cauchy stress at removal, Voigt xx,yy,zz,yz,xz,xy"});
  s.fields.push_back({"internal_energy", "J/kg", 1, out_.energy, "specific internal energy"});
  for (const common::Field& f : out_fields_) s.fields.push_back(f);
  return s;
}

}  // namespace mpmfrag
