/// @file solver.cpp
/// Explicit MPM step (see solver.hpp for the equations and references: Uintah explicit step,
/// shared/reference/mpm.md §1.2–1.6; Sulsky, Chen & Schreyer 1994; Sulsky, Zhou & Schreyer 1995
/// for MUSL; Bardenhagen & Kober 2004 for GIMP).
#include "mpm/solver.hpp"

#include <omp.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace mpmfrag {

namespace {
constexpr int kBlock = 4;         // cells per block edge (>= 2 needed for 3-node stencils)
constexpr std::size_t kChunk = 256;  // particles per material batch
constexpr std::size_t kReduceChunk = 4096;
enum Mode { kMass = 1, kMom = 2, kForce = 4 };
enum Flags { kVel = 1, kPos = 2, kGrad = 4 };
}  // namespace

Scheme parse_scheme(const std::string& s) {
  if (s == "usl") return Scheme::usl;
  if (s == "usf") return Scheme::usf;
  if (s == "musl") return Scheme::musl;
  throw std::invalid_argument("unknown update scheme '" + s + "' (usl, usf, musl)");
}
const char* scheme_name(Scheme s) {
  return s == Scheme::usl ? "usl" : s == Scheme::usf ? "usf" : "musl";
}
BoundaryType parse_boundary(const std::string& s) {
  if (s == "free") return BoundaryType::free;
  if (s == "fixed") return BoundaryType::fixed;
  if (s == "symmetry") return BoundaryType::symmetry;
  throw std::invalid_argument("unknown boundary type '" + s + "' (free, fixed, symmetry)");
}

common::GridInfo make_grid(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double h, int ghost) {
  common::GridInfo g;
  g.cell_size = Eigen::Vector3d::Constant(h);
  g.origin = lo - Eigen::Vector3d::Constant(ghost * h);
  for (int d = 0; d < 3; ++d) {
    const int cells = std::max(1, static_cast<int>(std::ceil((hi[d] - lo[d]) / h - 1e-9)));
    g.shape[d] = cells + 1 + 2 * ghost;
  }
  return g;
}

Solver::Solver(SolverConfig cfg, common::GridInfo grid, ParticleSet particles,
               std::vector<MaterialSlot> materials)
    : cfg_(std::move(cfg)), grid_(grid), ps_(std::move(particles)), mats_(std::move(materials)) {
  const std::size_t n = ps_.size();
  if (n == 0) throw common::InputError("no particles in the scene");
  if (n >= std::numeric_limits<std::uint32_t>::max()) throw common::InputError("too many particles (> 2^32)");
  if (cfg_.artificial_viscosity && ps_.q.size() != n) ps_.q.assign(n, 0.0);
  if (!cfg_.artificial_viscosity) ps_.q.clear();
  for (std::size_t m = 0; m < mats_.size(); ++m) {
    MaterialSlot& s = mats_[m];
    if (!s.model || !s.style) throw common::InputError("material '" + s.name + "' has no model");
    for (std::size_t p = s.begin; p < s.end; ++p)
      if (ps_.material[p] != static_cast<std::int32_t>(m))
        throw common::InputError("particles of material '" + s.name + "' are not contiguous");
    if (s.state.size() != s.style->state_fields.size()) s.allocate_state();
  }
  build_chunks();
  h_min_ = grid_.cell_size.minCoeff();
  for (int d = 0; d < 3; ++d)
    for (std::size_t p = 0; p < n; ++p)
      if (cfg_.shape == ShapeKind::ugimp && !(ps_.half_width[3 * p + d] > 0.0 && ps_.half_width[3 * p + d] <= 0.5 * grid_.cell_size[d] * (1 + 1e-12)))
        throw common::InputError("particle half-width must be in (0, h/2] (at least 1 particle per cell per axis)");
  m_min_ = cfg_.min_mass_fraction * *std::min_element(ps_.mass.begin(), ps_.mass.end());
  nodes_.assign(node_count(grid_), Node{});
  for (int d = 0; d < 3; ++d) nblocks_[d] = (grid_.shape[d] + kBlock - 1) / kBlock;
}

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
      f[d] = a.first;
      if (!(a.first >= 0 && a.first + NPA <= grid_.shape[d])) ok = false;
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
  if (n_out > 0 && cfg_.outflow_remove) {
    remove_particles(out_flag_);
    bin<NPA>();
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

// ------------------------------------------------------------------------------------------
// P2G scatter, 8 colour passes.
template <int NPA, int MODE>
void Solver::scatter() {
  const int sx = grid_.shape[0], sy = grid_.shape[1];
  const double* x = ps_.x.data();
  const double* v = ps_.v.data();
  const double* sg = ps_.stress.data();
  const double* q = ps_.q.empty() ? nullptr : ps_.q.data();
  const double* lp = ps_.half_width.data();
  const double* ba = body_accel_.empty() ? nullptr : body_accel_.data();
  Node* nodes = nodes_.data();
  const ShapeKind kind = cfg_.shape;
  const Eigen::Vector3d o = grid_.origin, h = grid_.cell_size;
  for (int colour = 0; colour < 8; ++colour) {
    const std::vector<std::uint32_t>& blocks = colour_blocks_[colour];
    const std::size_t nbk = blocks.size();
#pragma omp parallel for schedule(dynamic, 1)
    for (std::size_t ib = 0; ib < nbk; ++ib) {
      const std::uint32_t b = blocks[ib];
      for (std::uint32_t k = block_start_[b]; k < block_start_[b + 1]; ++k) {
        const std::size_t p = order_[k];
        const AxisWeights X = axis_weights(kind, x[3 * p], o[0], h[0], lp[3 * p]);
        const AxisWeights Y = axis_weights(kind, x[3 * p + 1], o[1], h[1], lp[3 * p + 1]);
        const AxisWeights Z = axis_weights(kind, x[3 * p + 2], o[2], h[2], lp[3 * p + 2]);
        const double m = ps_.mass[p];
        double mv0 = 0, mv1 = 0, mv2 = 0;
        if constexpr (MODE & kMom) {
          mv0 = m * v[3 * p];
          mv1 = m * v[3 * p + 1];
          mv2 = m * v[3 * p + 2];
        }
        double s00 = 0, s11 = 0, s22 = 0, s12 = 0, s02 = 0, s01 = 0, fe0 = 0, fe1 = 0, fe2 = 0;
        if constexpr (MODE & kForce) {
          const double V = ps_.volume[p];
          const double qq = q ? q[p] : 0.0;
          const double* s = sg + 6 * p;
          s00 = -V * (s[0] - qq);
          s11 = -V * (s[1] - qq);
          s22 = -V * (s[2] - qq);
          s12 = -V * s[3];
          s02 = -V * s[4];
          s01 = -V * s[5];
          if (ba) {
            fe0 = m * ba[3 * p];
            fe1 = m * ba[3 * p + 1];
            fe2 = m * ba[3 * p + 2];
          }
        }
        const std::size_t base = static_cast<std::size_t>(X.first) + static_cast<std::size_t>(sx) * (Y.first + static_cast<std::size_t>(sy) * Z.first);
        // Tensor-product factorisation: node (a,b,c) gets W = wx_a wyz, grad = (dwx_a wyz, wx_a dyz, wx_a ydz),
        // so f_i += dwx_a (s_i0 wyz) + wx_a (s_i1 dyz + s_i2 ydz + fe_i wyz).
        for (int c = 0; c < NPA; ++c) {
          for (int bb = 0; bb < NPA; ++bb) {
            const double wyz = Y.w[bb] * Z.w[c];
            Node* row = nodes + base + static_cast<std::size_t>(sx) * (bb + static_cast<std::size_t>(sy) * c);
            [[maybe_unused]] const double cm = m * wyz;
            [[maybe_unused]] const double cp0 = mv0 * wyz, cp1 = mv1 * wyz, cp2 = mv2 * wyz;
            double A0 = 0, A1 = 0, A2 = 0, B0 = 0, B1 = 0, B2 = 0;
            if constexpr ((MODE & kForce) != 0) {
              const double dyz = Y.dw[bb] * Z.w[c];
              const double ydz = Y.w[bb] * Z.dw[c];
              A0 = s00 * wyz;
              A1 = s01 * wyz;
              A2 = s02 * wyz;
              B0 = s01 * dyz + s02 * ydz + fe0 * wyz;
              B1 = s11 * dyz + s12 * ydz + fe1 * wyz;
              B2 = s12 * dyz + s22 * ydz + fe2 * wyz;
            }
#pragma GCC unroll 3
            for (int a = 0; a < NPA; ++a) {
              Node& nd = row[a];
              const double wx = X.w[a];
              if constexpr ((MODE & kMass) != 0) nd.m += wx * cm;
              if constexpr ((MODE & kMom) != 0) {
                nd.p[0] += wx * cp0;
                nd.p[1] += wx * cp1;
                nd.p[2] += wx * cp2;
              }
              if constexpr ((MODE & kForce) != 0) {
                const double dx = X.dw[a];
                nd.f[0] += dx * A0 + wx * B0;
                nd.f[1] += dx * A1 + wx * B1;
                nd.f[2] += dx * A2 + wx * B2;
              }
            }
          }
        }
      }
    }
  }
}

// ------------------------------------------------------------------------------------------
// Grid operations.
void Solver::grid_velocity() {
  const std::size_t nn = nodes_.size();
  Node* nodes = nodes_.data();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < nn; ++i) {
    Node& n = nodes[i];
    if (n.m > 0.0) {
      const double im = 1.0 / n.m;
      n.p[0] *= im;
      n.p[1] *= im;
      n.p[2] *= im;
    } else {
      n.p[0] = n.p[1] = n.p[2] = 0.0;
    }
  }
}

void Solver::grid_integrate(double dt) {
  const std::size_t nn = nodes_.size();
  Node* nodes = nodes_.data();
  const double mmin = m_min_;
  const Eigen::Vector3d g = cfg_.gravity;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < nn; ++i) {
    Node& n = nodes[i];
    if (n.m > mmin) {
      const double im = dt / n.m;
      n.f[0] = n.p[0] + n.f[0] * im + g[0] * dt;
      n.f[1] = n.p[1] + n.f[1] * im + g[1] * dt;
      n.f[2] = n.p[2] + n.f[2] * im + g[2] * dt;
    } else {
      n.f[0] = n.p[0];
      n.f[1] = n.p[1];
      n.f[2] = n.p[2];
    }
  }
}

void Solver::apply_bc(int slot) {
  const int S[3] = {grid_.shape[0], grid_.shape[1], grid_.shape[2]};
  const int g = cfg_.ghost_layers;
  auto at = [&](int i, int j, int k) -> double* {
    return reinterpret_cast<double*>(&nodes_[node_index(grid_, i, j, k)]) + slot;
  };
  for (int d = 0; d < 3; ++d) {
    const int d1 = (d + 1) % 3, d2 = (d + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      const BoundaryType t = cfg_.boundary[2 * d + side];
      if (t == BoundaryType::free) continue;
      const int plane = side == 0 ? g : S[d] - 1 - g;
      const int dir = side == 0 ? -1 : 1;  // outward
#pragma omp parallel for schedule(static)
      for (int a = 0; a < S[d1]; ++a) {
        for (int b = 0; b < S[d2]; ++b) {
          int idx[3];
          idx[d1] = a;
          idx[d2] = b;
          for (int layer = 0; layer <= g; ++layer) {
            idx[d] = plane + dir * layer;
            double* vv = at(idx[0], idx[1], idx[2]);
            if (t == BoundaryType::fixed) {
              vv[0] = vv[1] = vv[2] = 0.0;
            } else if (layer == 0) {
              vv[d] = 0.0;
            } else {
              int jdx[3] = {idx[0], idx[1], idx[2]};
              jdx[d] = plane - dir * layer;
              const double* src = at(jdx[0], jdx[1], jdx[2]);
              vv[d] = -src[d];
              vv[d1] = src[d1];
              vv[d2] = src[d2];
            }
          }
        }
      }
    }
  }
}

// ------------------------------------------------------------------------------------------
// G2P (+ velocity gradient, F, volume and the material update per chunk).
void Solver::run_material_chunk(std::size_t c, double dt, const double* L, double* wpre, double* ws, double* bs) {
  const Chunk ch = chunks_[c];
  const MaterialSlot& slot = mats_[ch.mat];
  const std::size_t n = ch.end - ch.begin;
  double* stress = ps_.stress.data() + 6 * ch.begin;
  // stress power before the update (trapezoidal energy integration)
  for (std::size_t k = 0; k < n; ++k) {
    const double* s = stress + 6 * k;
    const double* l = L + 9 * k;
    wpre[k] = s[0] * l[0] + s[1] * l[4] + s[2] * l[8] + s[3] * (l[5] + l[7]) + s[4] * (l[2] + l[6]) + s[5] * (l[1] + l[3]);
  }
  double* sptr[16];
  std::vector<double*> sbig;
  double** sp = sptr;
  if (slot.state.size() > 16) {
    sbig.resize(slot.state.size());
    sp = sbig.data();
  }
  for (std::size_t f = 0; f < slot.state.size(); ++f)
    sp[f] = const_cast<double*>(slot.state[f].data()) + static_cast<std::size_t>(slot.style->state_fields[f].ncomp) * (ch.begin - slot.begin);
  MaterialBatch b;
  b.n = n;
  b.first = ch.begin;
  b.dt = dt;
  b.time = time_;
  b.cell_size = h_min_;
  b.seed = cfg_.seed;
  b.L = L;
  b.F = ps_.F.data() + 9 * ch.begin;
  b.stress = stress;
  b.mass = ps_.mass.data() + ch.begin;
  b.volume = ps_.volume.data() + ch.begin;
  b.volume0 = ps_.volume0.data() + ch.begin;
  b.energy = ps_.energy.data() + ch.begin;
  b.id = ps_.id.data() + ch.begin;
  b.state = sp;
  b.wave_speed = ws;
  b.bulk_speed = cfg_.artificial_viscosity ? bs : nullptr;
  const BatchResult r = dt > 0.0 ? slot.model->update(b) : (slot.model->initialize(b), BatchResult{});
  std::size_t fails = r.failed;
  std::string msg;
  if (r.failed) {
    const std::size_t p = ch.begin + r.first_failed;
    std::ostringstream os;
    os << "material '" << slot.name << "' (" << slot.style->name << ") failed at particle id " << ps_.id[p] << ": "
       << r.reason;
    msg = os.str();
  }
  double vmax = 0.0;
  double* e = ps_.energy.data() + ch.begin;
  double* q = cfg_.artificial_viscosity ? ps_.q.data() + ch.begin : nullptr;
  const double* v = ps_.v.data() + 3 * ch.begin;
  for (std::size_t k = 0; k < n; ++k) {
    const double* s = stress + 6 * k;
    const double* l = L + 9 * k;
    const double rho = b.mass[k] / b.volume[k];
    const double trD = l[0] + l[4] + l[8];
    if (dt > 0.0) {
      const double wpost = s[0] * l[0] + s[1] * l[4] + s[2] * l[8] + s[3] * (l[5] + l[7]) + s[4] * (l[2] + l[6]) + s[5] * (l[1] + l[3]);
      e[k] += 0.5 * dt * (wpre[k] + wpost) / rho;
    }
    if (q) {
      double qq = 0.0;
      if (trD < 0.0) {
        const double hh = h_min_;
        qq = rho * (cfg_.av_a1 * bs[k] * (-trD) * hh + cfg_.av_a2 * trD * trD * hh * hh);
      }
      q[k] = qq;
      if (dt > 0.0) e[k] += qq * (-trD) * dt / rho;
    }
    const double sp2 = ws[k] + std::sqrt(v[3 * k] * v[3 * k] + v[3 * k + 1] * v[3 * k + 1] + v[3 * k + 2] * v[3 * k + 2]);
    const bool finite = std::isfinite(s[0] + s[1] + s[2] + s[3] + s[4] + s[5] + e[k] + sp2);
    if (!finite) {
      if (!fails++) {
        std::ostringstream os;
        os << "non-finite stress/energy/wave speed at particle id " << ps_.id[ch.begin + k] << " (material '" << slot.name << "')";
        msg = os.str();
      }
      continue;
    }
    vmax = std::max(vmax, sp2);
  }
  chunk_speed_[c] = vmax;
  if (fails) {
    chunk_fail_[c] += fails;
    if (chunk_msg_[c].empty()) chunk_msg_[c] = msg;
  }
}

template <int NPA, int flags, int lslot>
void Solver::g2p(double dt) {
  const ShapeKind kind = cfg_.shape;
  const int sx = grid_.shape[0], sy = grid_.shape[1];
  const Eigen::Vector3d o = grid_.origin, h = grid_.cell_size;
  const Node* nodes = nodes_.data();
  const double alpha = cfg_.flip;
  const std::size_t nch = chunks_.size();
  std::fill(chunk_fail_.begin(), chunk_fail_.end(), 0);
#pragma omp parallel
  {
    std::vector<double> Lb(9 * kChunk), wpre(kChunk), ws(kChunk), bs(kChunk);
#pragma omp for schedule(static)
    for (std::size_t c = 0; c < nch; ++c) {
      const Chunk ch = chunks_[c];
      std::size_t fails = 0;
      for (std::size_t p = ch.begin; p < ch.end; ++p) {
        double* xp = ps_.x.data() + 3 * p;
        double* vp = ps_.v.data() + 3 * p;
        const double* lp = ps_.half_width.data() + 3 * p;
        const AxisWeights X = axis_weights(kind, xp[0], o[0], h[0], lp[0]);
        const AxisWeights Y = axis_weights(kind, xp[1], o[1], h[1], lp[1]);
        const AxisWeights Z = axis_weights(kind, xp[2], o[2], h[2], lp[2]);
        const std::size_t base = static_cast<std::size_t>(X.first) + static_cast<std::size_t>(sx) * (Y.first + static_cast<std::size_t>(sy) * Z.first);
        double vs0 = 0, vs1 = 0, vs2 = 0, vo0 = 0, vo1 = 0, vo2 = 0;
        double L00 = 0, L01 = 0, L02 = 0, L10 = 0, L11 = 0, L12 = 0, L20 = 0, L21 = 0, L22 = 0;
        // Tensor-product factorisation: per node row (b,c) first sum over a with wx_a and dwx_a.
        for (int cc = 0; cc < NPA; ++cc) {
          for (int bb = 0; bb < NPA; ++bb) {
            const double wyz = Y.w[bb] * Z.w[cc];
            const Node* row = nodes + base + static_cast<std::size_t>(sx) * (bb + static_cast<std::size_t>(sy) * cc);
            double s0 = 0, s1 = 0, s2 = 0, o0 = 0, o1 = 0, o2 = 0, d0 = 0, d1 = 0, d2 = 0, t0 = 0, t1 = 0, t2 = 0;
#pragma GCC unroll 3
            for (int a = 0; a < NPA; ++a) {
              const Node& nd = row[a];
              const double wx = X.w[a];
              if constexpr ((flags & (kVel | kPos)) != 0 || lslot == 4) {
                s0 += wx * nd.f[0];
                s1 += wx * nd.f[1];
                s2 += wx * nd.f[2];
              }
              if constexpr ((flags & kVel) != 0 || lslot == 1) {
                o0 += wx * nd.p[0];
                o1 += wx * nd.p[1];
                o2 += wx * nd.p[2];
              }
              if constexpr ((flags & kGrad) != 0) {
                const double dx = X.dw[a];
                const double* vl = lslot == 1 ? nd.p : nd.f;
                d0 += dx * vl[0];
                d1 += dx * vl[1];
                d2 += dx * vl[2];
              }
            }
            if constexpr ((flags & (kVel | kPos)) != 0) {
              vs0 += wyz * s0;
              vs1 += wyz * s1;
              vs2 += wyz * s2;
            }
            if constexpr ((flags & kVel) != 0) {
              vo0 += wyz * o0;
              vo1 += wyz * o1;
              vo2 += wyz * o2;
            }
            if constexpr ((flags & kGrad) != 0) {
              if constexpr (lslot == 1) {
                t0 = o0; t1 = o1; t2 = o2;
              } else {
                t0 = s0; t1 = s1; t2 = s2;
              }
              const double dyz = Y.dw[bb] * Z.w[cc];
              const double ydz = Y.w[bb] * Z.dw[cc];
              L00 += wyz * d0; L01 += dyz * t0; L02 += ydz * t0;
              L10 += wyz * d1; L11 += dyz * t1; L12 += ydz * t1;
              L20 += wyz * d2; L21 += dyz * t2; L22 += ydz * t2;
            }
          }
        }
        if constexpr ((flags & kVel) != 0) {
          vp[0] = alpha * (vp[0] + vs0 - vo0) + (1.0 - alpha) * vs0;
          vp[1] = alpha * (vp[1] + vs1 - vo1) + (1.0 - alpha) * vs1;
          vp[2] = alpha * (vp[2] + vs2 - vo2) + (1.0 - alpha) * vs2;
        }
        if constexpr ((flags & kPos) != 0) {
          xp[0] += dt * vs0;
          xp[1] += dt * vs1;
          xp[2] += dt * vs2;
        }
        if ((flags & (kVel | kPos)) != 0 && !std::isfinite(vp[0] + vp[1] + vp[2] + xp[0] + xp[1] + xp[2])) {
          if (!fails++ && chunk_msg_[c].empty()) {
            std::ostringstream os;
            os << "non-finite velocity/position at particle id " << ps_.id[p];
            chunk_msg_[c] = os.str();
          }
        }
        if constexpr ((flags & kGrad) != 0) {
          double* l = Lb.data() + 9 * (p - ch.begin);
          l[0] = L00; l[1] = L01; l[2] = L02; l[3] = L10; l[4] = L11; l[5] = L12; l[6] = L20; l[7] = L21; l[8] = L22;
          double* F = ps_.F.data() + 9 * p;
          double Fn[9];
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
              Fn[3 * i + j] = F[3 * i + j] + dt * (l[3 * i] * F[j] + l[3 * i + 1] * F[3 + j] + l[3 * i + 2] * F[6 + j]);
          std::memcpy(F, Fn, sizeof Fn);
          const double J = det3(Fn);
          if (!(J > 0.0) || !std::isfinite(J)) {
            if (!fails++ && chunk_msg_[c].empty()) {
              std::ostringstream os;
              os << "J = det F = " << J << " <= 0 at particle id " << ps_.id[p] << " (material '" << mats_[ch.mat].name
                 << "'): the material was compressed through zero volume (step too large or unresolved impact)";
              chunk_msg_[c] = os.str();
            }
          }
          ps_.volume[p] = ps_.volume0[p] * J;
        }
      }
      chunk_fail_[c] += fails;
      if ((flags & kGrad) != 0 && fails == 0) run_material_chunk(c, dt, Lb.data(), wpre.data(), ws.data(), bs.data());
    }
  }
  std::size_t total = 0, first = nch;
  for (std::size_t c = 0; c < nch; ++c)
    if (chunk_fail_[c]) {
      total += chunk_fail_[c];
      if (first == nch) first = c;
    }
  if (total) {
    std::ostringstream os;
    os << total << " particle(s) failed at t = " << time_ << " s, step " << step_ << ": " << chunk_msg_[first];
    std::fill(chunk_msg_.begin(), chunk_msg_.end(), std::string());
    throw SolverFailure(os.str(), false);
  }
  if ((flags & kGrad) != 0) max_speed_ = *std::max_element(chunk_speed_.begin(), chunk_speed_.end());
}

// MUSL: v_p <- alpha (v_p + sum S (v* - v)) + (1 - alpha) sum S v*, and in the same coloured
// pass (m v_p)_i = sum_p S_ip m_p v_p into mom2_; afterwards the node momentum slots hold the
// re-projected momenta. Reads p/f of nodes, writes only mom2_ inside the block footprint.
template <int NPA>
void Solver::musl_remap() {
  const int sx = grid_.shape[0], sy = grid_.shape[1];
  double* x = ps_.x.data();
  double* v = ps_.v.data();
  const double* lp = ps_.half_width.data();
  const Node* nodes = nodes_.data();
  const ShapeKind kind = cfg_.shape;
  const Eigen::Vector3d o = grid_.origin, h = grid_.cell_size;
  const double alpha = cfg_.flip;
  mom2_.resize(3 * nodes_.size());
  double* m2 = mom2_.data();
  {
    const std::size_t n3 = mom2_.size();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n3; ++i) m2[i] = 0.0;
  }
  std::size_t first_bad = ps_.size();
  for (int colour = 0; colour < 8; ++colour) {
    const std::vector<std::uint32_t>& blocks = colour_blocks_[colour];
    const std::size_t nbk = blocks.size();
#pragma omp parallel for schedule(dynamic, 1) reduction(min : first_bad)
    for (std::size_t ib = 0; ib < nbk; ++ib) {
      const std::uint32_t b = blocks[ib];
      for (std::uint32_t k = block_start_[b]; k < block_start_[b + 1]; ++k) {
        const std::size_t p = order_[k];
        const AxisWeights X = axis_weights(kind, x[3 * p], o[0], h[0], lp[3 * p]);
        const AxisWeights Y = axis_weights(kind, x[3 * p + 1], o[1], h[1], lp[3 * p + 1]);
        const AxisWeights Z = axis_weights(kind, x[3 * p + 2], o[2], h[2], lp[3 * p + 2]);
        const std::size_t base = static_cast<std::size_t>(X.first) + static_cast<std::size_t>(sx) * (Y.first + static_cast<std::size_t>(sy) * Z.first);
        double vs0 = 0, vs1 = 0, vs2 = 0, vo0 = 0, vo1 = 0, vo2 = 0;
        for (int cc = 0; cc < NPA; ++cc)
          for (int bb = 0; bb < NPA; ++bb) {
            const double wyz = Y.w[bb] * Z.w[cc];
            const Node* row = nodes + base + static_cast<std::size_t>(sx) * (bb + static_cast<std::size_t>(sy) * cc);
            double s0 = 0, s1 = 0, s2 = 0, o0 = 0, o1 = 0, o2 = 0;
#pragma GCC unroll 3
            for (int a = 0; a < NPA; ++a) {
              const double wx = X.w[a];
              s0 += wx * row[a].f[0];
              s1 += wx * row[a].f[1];
              s2 += wx * row[a].f[2];
              o0 += wx * row[a].p[0];
              o1 += wx * row[a].p[1];
              o2 += wx * row[a].p[2];
            }
            vs0 += wyz * s0;
            vs1 += wyz * s1;
            vs2 += wyz * s2;
            vo0 += wyz * o0;
            vo1 += wyz * o1;
            vo2 += wyz * o2;
          }
        double* vp = v + 3 * p;
        vp[0] = alpha * (vp[0] + vs0 - vo0) + (1.0 - alpha) * vs0;
        vp[1] = alpha * (vp[1] + vs1 - vo1) + (1.0 - alpha) * vs1;
        vp[2] = alpha * (vp[2] + vs2 - vo2) + (1.0 - alpha) * vs2;
        if (!std::isfinite(vp[0] + vp[1] + vp[2])) first_bad = std::min(first_bad, p);
        const double m = ps_.mass[p];
        const double mv0 = m * vp[0], mv1 = m * vp[1], mv2 = m * vp[2];
        for (int cc = 0; cc < NPA; ++cc)
          for (int bb = 0; bb < NPA; ++bb) {
            const double wyz = Y.w[bb] * Z.w[cc];
            const double c0 = mv0 * wyz, c1 = mv1 * wyz, c2 = mv2 * wyz;
            double* row = m2 + 3 * (base + static_cast<std::size_t>(sx) * (bb + static_cast<std::size_t>(sy) * cc));
#pragma GCC unroll 3
            for (int a = 0; a < NPA; ++a) {
              const double wx = X.w[a];
              row[3 * a] += wx * c0;
              row[3 * a + 1] += wx * c1;
              row[3 * a + 2] += wx * c2;
            }
          }
      }
    }
  }
  if (first_bad < ps_.size()) {
    std::ostringstream os;
    os << "non-finite velocity at particle id " << ps_.id[first_bad] << " at t = " << time_ << " s, step " << step_;
    throw SolverFailure(os.str(), false);
  }
  Node* nd = nodes_.data();
  const std::size_t nn = nodes_.size();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < nn; ++i) {
    nd[i].p[0] = m2[3 * i];
    nd[i].p[1] = m2[3 * i + 1];
    nd[i].p[2] = m2[3 * i + 2];
  }
}

// ------------------------------------------------------------------------------------------
void Solver::initialize() {
  const std::size_t nch = chunks_.size();
  std::fill(chunk_fail_.begin(), chunk_fail_.end(), 0);
  std::vector<double> L(9 * kChunk, 0.0), wpre(kChunk), ws(kChunk), bs(kChunk);
  for (std::size_t p = 0; p < ps_.size(); ++p) ps_.volume[p] = ps_.volume0[p] * det3(ps_.F.data() + 9 * p);
  for (std::size_t c = 0; c < nch; ++c) run_material_chunk(c, 0.0, L.data(), wpre.data(), ws.data(), bs.data());
  for (std::size_t c = 0; c < nch; ++c)
    if (chunk_fail_[c]) throw SolverFailure("initial state invalid: " + chunk_msg_[c], true);
  max_speed_ = *std::max_element(chunk_speed_.begin(), chunk_speed_.end());
}

double Solver::stable_dt() const {
  const double dt = cfg_.courant * h_min_ / std::max(max_speed_, 1e-300);
  dt_capped_ = dt > cfg_.dt_max;
  return std::min(dt, cfg_.dt_max);
}

void Solver::step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw SolverFailure("invalid time step " + std::to_string(dt), true);
  const bool lin = cfg_.shape == ShapeKind::linear;
  if (cfg_.reorder_every > 0 && step_ % cfg_.reorder_every == 0) {
    lin ? bin<2>() : bin<3>();
    reorder();
  }
  lin ? bin<2>() : bin<3>();
  if (body_force_) {
    body_accel_.resize(3 * ps_.size());
    const std::size_t n = ps_.size();
#pragma omp parallel for schedule(static)
    for (std::size_t b = 0; b < n; b += kReduceChunk)
      body_force_(b, std::min(n, b + kReduceChunk), time_, ps_, body_accel_.data() + 3 * b);
  }
  {
    Node* nd = nodes_.data();
    const std::size_t nn = nodes_.size();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < nn; ++i) nd[i] = Node{};
  }
  auto scat = [&](auto mode) {
    constexpr int M = decltype(mode)::value;
    lin ? scatter<2, M>() : scatter<3, M>();
  };
  auto gather = [&](auto fl, auto ls) {
    constexpr int FL = decltype(fl)::value, LS = decltype(ls)::value;
    lin ? g2p<2, FL, LS>(dt) : g2p<3, FL, LS>(dt);
  };
  using std::integral_constant;
  switch (cfg_.scheme) {
    case Scheme::usl:
      scat(std::integral_constant<int, kMass | kMom | kForce>{});
      grid_velocity();
      apply_bc(1);
      grid_integrate(dt);
      apply_bc(4);
      gather(integral_constant<int, kVel | kPos | kGrad>{}, integral_constant<int, 4>{});
      break;
    case Scheme::musl: {
      scat(std::integral_constant<int, kMass | kMom | kForce>{});
      grid_velocity();
      apply_bc(1);
      grid_integrate(dt);
      apply_bc(4);
      // fused: FLIP/PIC velocity update and re-projection of the new particle momenta
      lin ? musl_remap<2>() : musl_remap<3>();
      grid_velocity();
      apply_bc(1);
      gather(integral_constant<int, kPos | kGrad>{}, integral_constant<int, 1>{});
      break;
    }
    case Scheme::usf:
      scat(std::integral_constant<int, kMass | kMom>{});
      grid_velocity();
      apply_bc(1);
      gather(integral_constant<int, kGrad>{}, integral_constant<int, 1>{});
      scat(std::integral_constant<int, kForce>{});
      grid_integrate(dt);
      apply_bc(4);
      gather(integral_constant<int, kVel | kPos>{}, integral_constant<int, 4>{});
      break;
  }
  time_ += dt;
  ++step_;
}

// ------------------------------------------------------------------------------------------
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
  apply(ps_.id, 1, 0, n);
  apply(ps_.material, 1, 0, n);
  apply(ps_.x, 3, 0, n);
  apply(ps_.v, 3, 0, n);
  apply(ps_.F, 9, 0, n);
  apply(ps_.stress, 6, 0, n);
  apply(ps_.mass, 1, 0, n);
  apply(ps_.volume, 1, 0, n);
  apply(ps_.volume0, 1, 0, n);
  apply(ps_.energy, 1, 0, n);
  apply(ps_.half_width, 3, 0, n);
  apply(ps_.q, 1, 0, n);
  if (!body_accel_.empty()) body_accel_.clear();
  for (MaterialSlot& s : mats_)
    for (std::size_t f = 0; f < s.state.size(); ++f)
      apply(s.state[f], static_cast<std::size_t>(s.style->state_fields[f].ncomp), s.begin, s.end - s.begin);
}

void Solver::save_backup() {
  backup_.particles = ps_;
  backup_.materials = mats_;
  backup_.time = time_;
  backup_.step = step_;
  backup_.valid = true;
}

Diagnostics Solver::diagnostics() const {
  const std::size_t n = ps_.size();
  const std::size_t nc = (n + kReduceChunk - 1) / kReduceChunk;
  std::vector<Diagnostics> part(nc);
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < nc; ++c) {
    Diagnostics d;
    for (std::size_t p = c * kReduceChunk; p < std::min(n, (c + 1) * kReduceChunk); ++p) {
      const double m = ps_.mass[p];
      const Eigen::Vector3d x(ps_.x[3 * p], ps_.x[3 * p + 1], ps_.x[3 * p + 2]);
      const Eigen::Vector3d v(ps_.v[3 * p], ps_.v[3 * p + 1], ps_.v[3 * p + 2]);
      d.mass += m;
      d.momentum += m * v;
      d.angular_momentum += m * x.cross(v);
      d.kinetic += 0.5 * m * v.squaredNorm();
      d.internal += m * ps_.energy[p];
    }
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
