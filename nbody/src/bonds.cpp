/// @file bonds.cpp
/// Parallel bonds: generator, dt check, forces, breakage and energy (equations in bonds.hpp).
#include "ssdem/bonds.hpp"

#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "common/bond_columns.hpp"
#include "common/status.hpp"
#include "ssdem/contact/part.hpp"

namespace ssdem {
namespace {
struct Section {
  double A, I, J;
};
Section section(double rb) {
  const double r2 = rb * rb;
  return {M_PI * r2, 0.25 * M_PI * r2 * r2, 0.5 * M_PI * r2 * r2};
}
}  // namespace

void BondSet::add(std::uint64_t a, std::uint64_t b, double kn_, double ks_, double sc, double tc,
                  double rb, double L0, const Vec3& n0) {
  common::push_bond_columns(*this, a, b, kn_, ks_, sc, tc, rb, L0);
  broken.push_back(0);
  Fs.push_back(Vec3::Zero());
  Mb.push_back(Vec3::Zero());
  n_old.push_back(n0);
  Mt.push_back(0.0);
  released.push_back(0.0);
}

void BondSet::append(const BondSet& o, std::size_t k) {
  zip_arrays([k](auto& to, const auto& from) { to.push_back(from[k]); }, *this, o);
}

double BondSet::released_total() const {
  common::ExactSum e;
  e.add(released_base);
  for (double r : released) e.add(r);
  return e.value();
}

std::size_t BondSet::broken_count() const {
  return static_cast<std::size_t>(std::count(broken.begin(), broken.end(), std::uint8_t{1}));
}

BondSet generate_bonds(const Spheres& sp, const BondParams& p) {
  BondSet b;
  const std::size_t n = sp.size();
  if (n == 0) return b;
  double smax = 0;
  for (double s : sp.s) smax = std::max(smax, s);
  // cell list with cells of the largest reach
  const double cell = 2.0 * smax * (1.0 + p.gap);
  auto key = [&](const Vec3& x) {
    const auto c = [&](double v) { return static_cast<std::int64_t>(std::floor(v / cell)) & 0x1FFFFF; };
    return (static_cast<std::uint64_t>(c(x.x())) << 42) | (static_cast<std::uint64_t>(c(x.y())) << 21) |
           static_cast<std::uint64_t>(c(x.z()));
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  for (std::size_t i = 0; i < n; ++i) grid[key(sp.x[i])].push_back(static_cast<std::uint32_t>(i));
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<std::uint32_t> near;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = grid.find(key(sp.x[i] + cell * Vec3(dx, dy, dz)));
          if (it == grid.end()) continue;
          for (auto j : it->second)
            if (j > i) near.push_back(j);
        }
    std::sort(near.begin(), near.end());
    near.erase(std::unique(near.begin(), near.end()), near.end());
    for (auto j : near) {
      const Vec3 r = sp.x[j] - sp.x[i];
      const double d = r.norm(), smin = std::min(sp.s[i], sp.s[j]);
      if (d < sp.s[i] + sp.s[j] + p.gap * smin && d > 0.0)
        b.add(sp.id[i], sp.id[j], p.kn, p.ks, p.sigma_c, p.tau_c, p.radius_ratio * smin, d, r / d);
    }
  }
  return b;
}

namespace {
// Shortest half-period of bond k's axial, shear, bending and twist modes.
double bond_time(const BondSet& b, std::size_t k, double ma, double mb, double sa, double sb) {
  const Section q = section(b.radius[k]);
  const double mu = ma * mb / (ma + mb);
  const double Ia = 0.4 * ma * sa * sa, Ib = 0.4 * mb * sb * sb, Ir = Ia * Ib / (Ia + Ib);
  double t = INFINITY;
  if (b.kn[k] > 0) t = std::min({t, M_PI * std::sqrt(mu / (b.kn[k] * q.A)), M_PI * std::sqrt(Ir / (b.kn[k] * q.I))});
  if (b.ks[k] > 0) t = std::min({t, M_PI * std::sqrt(mu / (b.ks[k] * q.A)), M_PI * std::sqrt(Ir / (b.ks[k] * q.J))});
  return t;
}
}  // namespace

double shortest_bond_time(const BondSet& b, const Spheres& sp) {
  if (b.empty()) return INFINITY;
  std::unordered_map<std::uint64_t, std::size_t> idx;
  for (std::size_t i = 0; i < sp.size(); ++i) idx.emplace(sp.id[i], i);
  double t = INFINITY;
  for (std::size_t k = 0; k < b.size(); ++k) {
    if (b.broken[k]) continue;
    auto ia = idx.find(b.id_a[k]), ib = idx.find(b.id_b[k]);
    if (ia == idx.end() || ib == idx.end()) continue;
    t = std::min(t, bond_time(b, k, sp.m[ia->second], sp.m[ib->second], sp.s[ia->second], sp.s[ib->second]));
  }
  return t;
}

void check_bond_dt(const BondSet& b, const Spheres& sp, double dt, double min_steps) {
  const double tau = shortest_bond_time(b, sp);
  if (!std::isfinite(tau)) return;
  if (dt * min_steps > tau * (1.0 + 1e-9)) {
    std::ostringstream os;
    os << "bonds.kn / bonds.ks: the stiffest bond (shortest mode half-period " << tau
       << " s) is resolved by time.dt = " << dt << " s with only " << tau / dt << " steps; at least "
       << min_steps << " are required (time.min_steps_per_contact). Use dt <= " << tau / min_steps
       << " s or bonds " << (dt * min_steps / tau) * (dt * min_steps / tau)
       << " x softer (bonds.kn, bonds.ks).";
    throw common::InputError(os.str());
  }
}

BondSystem::BondSystem(BondSet b, const Spheres& sp) : b_(std::move(b)) {
  std::unordered_map<std::uint64_t, std::uint32_t> idx;
  idx.reserve(2 * sp.size());
  for (std::size_t i = 0; i < sp.size(); ++i) idx.emplace(sp.id[i], static_cast<std::uint32_t>(i));
  ia_.resize(b_.size());
  ib_.resize(b_.size());
  for (std::size_t k = 0; k < b_.size(); ++k) {
    auto a = idx.find(b_.id_a[k]), c = idx.find(b_.id_b[k]);
    if (a == idx.end() || c == idx.end() || b_.id_a[k] == b_.id_b[k])
      throw common::InputError("bond " + std::to_string(k) + " (" + std::to_string(b_.id_a[k]) + ", " +
                               std::to_string(b_.id_b[k]) + ") names an unknown sphere id or one sphere twice");
    if (!(b_.radius[k] > 0.0) || !(b_.length0[k] > 0.0) || !(b_.kn[k] >= 0.0) || !(b_.ks[k] >= 0.0))
      throw common::InputError("bond " + std::to_string(k) + ": radius and length0 must be > 0, kn and ks >= 0");
    ia_[k] = a->second;
    ib_[k] = c->second;
  }
}

void BondSystem::refresh_live() {
  if (live_at_ == breaks_) return;
  live_.clear();
  for (std::size_t k = 0; k < b_.size(); ++k)
    if (!b_.broken[k]) live_.push_back(static_cast<std::uint32_t>(k));
  live_at_ = breaks_;
}

bool BondSystem::parallel(std::size_t n) {
  if (live_.size() < kParallelBonds || omp_get_max_threads() < 2) return false;
  if (srow_.size() != n + 1) {  // the index of every bond (ia_, ib_ never change)
    const std::size_t nb = ia_.size();
    for (std::size_t k = 0; k < nb; ++k)
      if (ia_[k] >= n || ib_[k] >= n)
        throw std::logic_error("BondSystem: bond " + std::to_string(k) + " names a sphere beyond the " +
                               std::to_string(n) + " given");
    srow_.assign(n + 1, 0);
    for (std::size_t k = 0; k < nb; ++k) {
      ++srow_[ia_[k] + 1];
      ++srow_[ib_[k] + 1];
    }
    for (std::size_t i = 0; i < n; ++i) srow_[i + 1] += srow_[i];
    sadj_.resize(srow_[n]);
    std::vector<std::uint32_t> fill(srow_.begin(), srow_.end() - 1);
    for (std::size_t k = 0; k < nb; ++k) {  // ascending k per sphere
      sadj_[fill[ia_[k]]++] = static_cast<std::uint32_t>(2 * k);
      sadj_[fill[ib_[k]]++] = static_cast<std::uint32_t>(2 * k + 1);
    }
    bf_.assign(nb, Vec3::Zero());
    bta_.assign(nb, Vec3::Zero());
    btb_.assign(nb, Vec3::Zero());
    bon_.assign(nb, 0);
  }
  return true;
}

// Each sphere (where only[i] != 0 if `only`) adds its applied bonds' terms in ascending bond order.
void BondSystem::gather(std::size_t n, const std::uint8_t* only, std::vector<Vec3>& F, std::vector<Vec3>& T) const {
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    if (only && !only[i]) continue;
    for (std::uint32_t q = srow_[i]; q < srow_[i + 1]; ++q) {
      const std::uint32_t k = sadj_[q] >> 1;
      if (!bon_[k] || b_.broken[k]) continue;  // (broken: also by a serial call since bon_ was set)
      if (sadj_[q] & 1u) {
        F[i] -= bf_[k];
        T[i] += btb_[k];
      } else {
        F[i] += bf_[k];
        T[i] += bta_[k];
      }
    }
  }
}

void BondSystem::compute(const Spheres& sp, double h, std::vector<Vec3>& F, std::vector<Vec3>& T) {
  refresh_live();  // the intact bonds in ascending order: the same order as a scan of all bonds
  if (!parallel(sp.size())) {
    for (std::uint32_t k : live_)
      if (!b_.broken[k]) compute_one(k, sp, h, F, T);
    return;
  }
  const std::size_t nl = live_.size();
  std::size_t broke = 0;
#pragma omp parallel for schedule(static) reduction(+ : broke)
  for (std::size_t r = 0; r < nl; ++r) {
    const std::uint32_t k = live_[r];
    bon_[k] = 0;
    if (b_.broken[k]) continue;
    bon_[k] = evaluate(k, sp, h, bf_[k], bta_[k], btb_[k]) ? 1 : 0;
    broke += bon_[k] ? 0 : 1;
  }
  breaks_ += broke;
  gather(sp.size(), nullptr, F, T);
}

void BondSystem::compute_synchronised(const Spheres& sp, const std::vector<std::uint8_t>& sync,
                                      const std::vector<std::int64_t>& topen, std::int64_t step, double dt,
                                      std::vector<Vec3>& F, std::vector<Vec3>& T) {
  refresh_live();
  for (std::uint32_t k : live_) {  // (a cheap check first, so the parallel loop cannot throw)
    if (b_.broken[k]) continue;
    const std::uint32_t a = ia_[k], b = ib_[k];
    if ((sync[a] || sync[b]) && (!sync[a] || !sync[b] || topen[a] != topen[b]))
      throw std::logic_error("multi-rate: the two spheres of bond " + std::to_string(k) + " are not synchronised together");
  }
  if (!parallel(sp.size())) {
    for (std::uint32_t k : live_)
      if (!b_.broken[k] && sync[ia_[k]]) compute_one(k, sp, static_cast<double>(step - topen[ia_[k]]) * dt, F, T);
    return;
  }
  const std::size_t nl = live_.size();
  std::size_t broke = 0;
#pragma omp parallel for schedule(static) reduction(+ : broke)
  for (std::size_t r = 0; r < nl; ++r) {
    const std::uint32_t k = live_[r], a = ia_[k];
    bon_[k] = 0;
    if (b_.broken[k] || !sync[a]) continue;
    bon_[k] = evaluate(k, sp, static_cast<double>(step - topen[a]) * dt, bf_[k], bta_[k], btb_[k]) ? 1 : 0;
    broke += bon_[k] ? 0 : 1;
  }
  breaks_ += broke;
  gather(sp.size(), sync.data(), F, T);
}

void BondSystem::compute_one(std::size_t k, const Spheres& sp, double h, std::vector<Vec3>& F,
                             std::vector<Vec3>& T) {
  Vec3 f, ta, tb;
  if (!evaluate(k, sp, h, f, ta, tb)) {
    ++breaks_;
    return;
  }
  const std::uint32_t a = ia_[k], b = ib_[k];
  F[a] += f;
  F[b] -= f;
  T[a] += ta;
  T[b] += tb;
}

bool BondSystem::evaluate(std::size_t k, const Spheres& sp, double h, Vec3& f, Vec3& ta, Vec3& tb) {
  const std::uint32_t a = ia_[k], b = ib_[k];
  const Vec3 rho = sp.x[b] - sp.x[a];
  const double d = rho.norm();
  const Vec3 n = rho / d;
  const double la = (sp.s[a] * sp.s[a] - sp.s[b] * sp.s[b] + d * d) / (2.0 * d), lb = d - la;
  const Vec3 uh = sp.v[b] - sp.v[a] - lb * sp.w[b].cross(n) - la * sp.w[a].cross(n);
  const Vec3 dw = sp.w[b] - sp.w[a];
  const Section q = section(b_.radius[k]);
  // carry the shear force and bending moment with the bond frame, then increment
  const FrameTransport tr(b_.n_old[k], n, sp.w[a] + sp.w[b], h);
  Vec3 Fs = tr(b_.Fs[k]), Mb = tr(b_.Mb[k]);
  b_.n_old[k] = n;
  Fs += (b_.ks[k] * q.A * h) * (uh - uh.dot(n) * n);
  const double dwn = dw.dot(n);
  const double Mt = b_.Mt[k] + b_.ks[k] * q.J * dwn * h;
  Mb += (b_.kn[k] * q.I * h) * (dw - dwn * n);
  const double Fn = b_.kn[k] * q.A * (d - b_.length0[k]);
  b_.Fs[k] = Fs;
  b_.Mb[k] = Mb;
  b_.Mt[k] = Mt;
  const double rb = b_.radius[k];
  const double sigma = Fn / q.A + Mb.norm() * rb / q.I;
  const double tau = Fs.norm() / q.A + std::fabs(Mt) * rb / q.J;
  if (sigma > b_.sigma_c[k] || tau > b_.tau_c[k]) {
    b_.released[k] = (b_.kn[k] > 0 ? Fn * Fn / (2.0 * b_.kn[k] * q.A) + Mb.squaredNorm() / (2.0 * b_.kn[k] * q.I) : 0.0) +
                     (b_.ks[k] > 0 ? Fs.squaredNorm() / (2.0 * b_.ks[k] * q.A) + Mt * Mt / (2.0 * b_.ks[k] * q.J) : 0.0);
    b_.broken[k] = 1;
    b_.Fs[k].setZero();
    b_.Mb[k].setZero();
    b_.Mt[k] = 0.0;
    return false;
  }
  f = Fn * n + Fs;
  const Vec3 nxF = n.cross(Fs);
  ta = la * nxF + Mt * n + Mb;
  tb = lb * nxF - Mt * n - Mb;
  return true;
}

common::ExactSum BondSystem::elastic_sum(const Spheres& sp, const std::vector<std::uint8_t>* keep) const {
  common::ExactSum e;
  for (std::size_t k = 0; k < b_.size(); ++k)
    if (!b_.broken[k] && (!keep || (*keep)[k])) e.add(energy(k, sp));
  return e;
}

double BondSystem::energy(std::size_t k, const Spheres& sp) const {
  if (b_.broken[k]) return 0.0;
  const Section q = section(b_.radius[k]);
  const double Fn = b_.kn[k] * q.A * ((sp.x[ib_[k]] - sp.x[ia_[k]]).norm() - b_.length0[k]);
  double e = 0.0;
  if (b_.kn[k] > 0) e += Fn * Fn / (2.0 * b_.kn[k] * q.A) + b_.Mb[k].squaredNorm() / (2.0 * b_.kn[k] * q.I);
  if (b_.ks[k] > 0) e += b_.Fs[k].squaredNorm() / (2.0 * b_.ks[k] * q.A) + b_.Mt[k] * b_.Mt[k] / (2.0 * b_.ks[k] * q.J);
  return e;
}

double BondSystem::mode_time(std::size_t k, const Spheres& sp) const {
  const std::uint32_t a = ia_[k], b = ib_[k];
  return bond_time(b_, k, sp.m[a], sp.m[b], sp.s[a], sp.s[b]);
}

double BondSystem::bytes_per_sphere(std::size_t n) const {
  if (n == 0) return 0.0;
  // ids 16, kn ks sc tc radius L0 48, broken 1, Fs Mb n_old 72, Mt 8, released 8, indices 8; the
  // parallel path's per-bond terms and flag 73 and index 8 per bond plus 4 per sphere
  double b = static_cast<double>(b_.size()) * 161.0;
  if (!srow_.empty()) b += static_cast<double>(b_.size()) * 81.0 + 4.0 * static_cast<double>(srow_.size());
  return b / static_cast<double>(n);
}

}  // namespace ssdem
