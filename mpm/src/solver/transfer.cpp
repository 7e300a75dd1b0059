/// @file transfer.cpp
/// Particle <-> grid transfers of the explicit MPM step (Uintah explicit step, mpm.md §1.2–1.6;
/// Sulsky, Chen & Schreyer 1994; Sulsky, Zhou & Schreyer 1995 for MUSL; Bardenhagen & Kober 2004
/// for GIMP):
///
///   P2G:   m_i = sum_p S_ip m_p,  (mv)_i = sum_p S_ip m_p v_p,
///          f_i = -sum_p V_p (sigma_p - q_p I) . grad S_ip + sum_p S_ip m_p b_p
///   G2P:   v_p <- alpha (v_p + sum S (v* - v)) + (1 - alpha) sum S v*   (alpha = FLIP fraction)
///          x_p <- x_p + dt sum S v*
///          L_p = sum_i v^L_i (x) grad S_ip,  F <- (I + L dt) F,  V = V0 det F, then the material
///          update of the chunk (material_update.cpp)
///   MUSL:  the updated particle momenta are projected again, (m v)_i = sum_p S_ip m_p v_p.
///
/// P2G and the MUSL re-projection run over the 8 block colours in turn (binning.cpp), blocks of
/// one colour in parallel, particles of a block in index order: every nodal sum is accumulated
/// in the same order for any thread count.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "kernels.hpp"

namespace mpmfrag {

using namespace detail;

// ------------------------------------------------------------------------------------------
// P2G scatter, 8 colour passes; MODE (detail::P2G) selects mass, momentum and/or force.
template <int NPA, int MODE>
void Solver::scatter() {
  const int sx = sub_.shape[0], sy = sub_.shape[1];
  const std::size_t shift = shift_;
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
        const Stencil st = particle_stencil(kind, x + 3 * p, lp + 3 * p, o, h, sx, sy, shift);
        const AxisWeights &X = st.X, &Y = st.Y, &Z = st.Z;
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
        // Tensor-product factorisation: node (a,b,c) gets W = wx_a wyz, grad = (dwx_a wyz, wx_a dyz, wx_a ydz),
        // so f_i += dwx_a (s_i0 wyz) + wx_a (s_i1 dyz + s_i2 ydz + fe_i wyz).
        for (int c = 0; c < NPA; ++c) {
          for (int bb = 0; bb < NPA; ++bb) {
            const double wyz = Y.w[bb] * Z.w[c];
            Node* row = nodes + st.row(sx, sy, bb, c);
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
                double* mv = nd.momentum();
                mv[0] += wx * cp0;
                mv[1] += wx * cp1;
                mv[2] += wx * cp2;
              }
              if constexpr ((MODE & kForce) != 0) {
                const double dx = X.dw[a];
                double* f = nd.force();
                f[0] += dx * A0 + wx * B0;
                f[1] += dx * A1 + wx * B1;
                f[2] += dx * A2 + wx * B2;
              }
            }
          }
        }
      }
    }
  }
}

// ------------------------------------------------------------------------------------------
// G2P over the material chunks; flags (detail::G2P): kVel FLIP/PIC velocity, kPos position
// (both from v*), kGrad velocity gradient L from the grid velocity slot Lfrom, then F, the volume
// and the material update of the chunk.
template <int NPA, int flags, GridSlot Lfrom>
void Solver::g2p(double dt) {
  constexpr bool kLfromVelocity = Lfrom == GridSlot::velocity;  // L from v_i
  // midpoint: L from v*_i (the USL step), and the energy from L at (v_i + v*_i)/2 (energy_budget.hpp)
  constexpr bool kLfromMid = Lfrom == GridSlot::midpoint;
  constexpr bool kHeat = kLfromMid && (flags & kVel) != 0;       // energy-consistent scheme: transfer heat
  const ShapeKind kind = cfg_.shape;
  const int sx = sub_.shape[0], sy = sub_.shape[1];
  const std::size_t shift = shift_;
  const Eigen::Vector3d o = grid_.origin, h = grid_.cell_size;
  const Node* nodes = nodes_.data();
  const double alpha = cfg_.flip;
  const std::size_t nch = chunks_.size();
  std::fill(chunk_fail_.begin(), chunk_fail_.end(), 0);
#pragma omp parallel
  {
    std::vector<double> Lb(9 * kChunk), wpre(2 * kChunk), ws(kChunk), bs(kChunk), econs(3 * kChunk);
    // Dynamic: a material update's cost varies by orders of magnitude between particles (the
    // Tonge-Ramesh sub-steps concentrate in the shocked region), so equal static shares leave
    // threads idle. Chunks are independent (per-chunk results, reduced in chunk order later), so
    // the result does not depend on the schedule. Measured on the TR impact (fragment.toml,
    // 700 m, ppc 2, 191 258 particles, 14 steps, 2 threads, 3 interleaved rounds): 36.5 -> 26.0 s
    // (medians), final snapshot h5diff-identical.
#pragma omp for schedule(dynamic, 1)
    for (std::size_t c = 0; c < nch; ++c) {
      const Chunk ch = chunks_[c];
      std::size_t fails = 0;
      for (std::size_t p = ch.begin; p < ch.end; ++p) {
        double* xp = ps_.x.data() + 3 * p;
        double* vp = ps_.v.data() + 3 * p;
        const double* lp = ps_.half_width.data() + 3 * p;
        const Stencil st = particle_stencil(kind, xp, lp, o, h, sx, sy, shift);
        const AxisWeights &X = st.X, &Y = st.Y, &Z = st.Z;
        double vs0 = 0, vs1 = 0, vs2 = 0, vo0 = 0, vo1 = 0, vo2 = 0, dv2 = 0;
        double L00 = 0, L01 = 0, L02 = 0, L10 = 0, L11 = 0, L12 = 0, L20 = 0, L21 = 0, L22 = 0;
        [[maybe_unused]] double M00 = 0, M01 = 0, M02 = 0, M10 = 0, M11 = 0, M12 = 0, M20 = 0, M21 = 0, M22 = 0;  // L(v)
        // Tensor-product factorisation: per node row (b,c) first sum over a with wx_a and dwx_a.
        for (int cc = 0; cc < NPA; ++cc) {
          for (int bb = 0; bb < NPA; ++bb) {
            const double wyz = Y.w[bb] * Z.w[cc];
            const Node* row = nodes + st.row(sx, sy, bb, cc);
            double s0 = 0, s1 = 0, s2 = 0, o0 = 0, o1 = 0, o2 = 0, d0 = 0, d1 = 0, d2 = 0, t0 = 0, t1 = 0, t2 = 0, q2 = 0;
            [[maybe_unused]] double g0 = 0, g1 = 0, g2 = 0;
#pragma GCC unroll 3
            for (int a = 0; a < NPA; ++a) {
              const Node& nd = row[a];
              const double wx = X.w[a];
              if constexpr (kHeat) {  // sum_i S_ip |v*_i - v_i|^2 (the transfer heat below)
                const double *va = nd.velocity(), *vb = nd.updated_velocity();
                const double e0 = vb[0] - va[0], e1 = vb[1] - va[1], e2 = vb[2] - va[2];
                q2 += wx * (e0 * e0 + e1 * e1 + e2 * e2);
              }
              if constexpr ((flags & (kVel | kPos)) != 0 || !kLfromVelocity) {
                const double* vstar = nd.updated_velocity();
                s0 += wx * vstar[0];
                s1 += wx * vstar[1];
                s2 += wx * vstar[2];
              }
              if constexpr ((flags & kVel) != 0 || kLfromVelocity || kLfromMid) {
                const double* vold = nd.velocity();
                o0 += wx * vold[0];
                o1 += wx * vold[1];
                o2 += wx * vold[2];
              }
              if constexpr ((flags & kGrad) != 0 && kLfromMid) {
                const double dx = X.dw[a];
                const double *va = nd.velocity(), *vb = nd.updated_velocity();
                d0 += dx * vb[0];
                d1 += dx * vb[1];
                d2 += dx * vb[2];
                g0 += dx * va[0];
                g1 += dx * va[1];
                g2 += dx * va[2];
              } else if constexpr ((flags & kGrad) != 0) {
                const double dx = X.dw[a];
                const double* vl = nd.*Node::slot(Lfrom);
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
            if constexpr (kHeat) dv2 += wyz * q2;
            if constexpr ((flags & kVel) != 0) {
              vo0 += wyz * o0;
              vo1 += wyz * o1;
              vo2 += wyz * o2;
            }
            if constexpr ((flags & kGrad) != 0) {
              if constexpr (kLfromMid) {
                t0 = s0; t1 = s1; t2 = s2;
                const double dyo = Y.dw[bb] * Z.w[cc], ydo = Y.w[bb] * Z.dw[cc];
                M00 += wyz * g0; M01 += dyo * o0; M02 += ydo * o0;
                M10 += wyz * g1; M11 += dyo * o1; M12 += ydo * o1;
                M20 += wyz * g2; M21 += dyo * o2; M22 += ydo * o2;
              } else if constexpr (kLfromVelocity) {
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
        if constexpr (kHeat) {
          // Kinetic-energy fix-up of the transfer (DeBar 1974; energy_budget.hpp): the part of the
          // grid's kinetic-energy change that the particle velocities cannot hold becomes heat.
          const double e0 = vs0 - vo0, e1 = vs1 - vo1, e2 = vs2 - vo2;
          const double w0 = vp[0] + e0, w1 = vp[1] + e1, w2 = vp[2] + e2;  // the FLIP velocity
          flip_blend(vp, alpha, vs0, vs1, vs2, vo0, vo1, vo2);
          const double heat = 0.5 * (dv2 - (e0 * e0 + e1 * e1 + e2 * e2)) +
                              0.5 * (w0 * w0 + w1 * w1 + w2 * w2 - vp[0] * vp[0] - vp[1] * vp[1] - vp[2] * vp[2]);
          ps_.energy[p] += heat;
          ps_.heat_transfer[p] += heat;
        } else if constexpr ((flags & kVel) != 0) {
          flip_blend(vp, alpha, vs0, vs1, vs2, vo0, vo1, vo2);
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
          if constexpr (kLfromMid) {
            // power of the grid force V_n (sigma_n - q_n I) : L(v_mid) as specific energy increments:
            // total, its deviatoric part, the artificial-viscosity part
            const double lm[9] = {0.5 * (L00 + M00), 0.5 * (L01 + M01), 0.5 * (L02 + M02),
                                  0.5 * (L10 + M10), 0.5 * (L11 + M11), 0.5 * (L12 + M12),
                                  0.5 * (L20 + M20), 0.5 * (L21 + M21), 0.5 * (L22 + M22)};
            const double* sg = ps_.stress.data() + 6 * p;
            const double trm = lm[0] + lm[4] + lm[8], pw = stress_power(sg, lm);
            const double qn = ps_.q.empty() ? 0.0 : ps_.q[p], f = dt * ps_.volume[p] / ps_.mass[p];
            double* ec = econs.data() + 3 * (p - ch.begin);
            ec[0] = f * (pw - qn * trm);
            ec[1] = f * (pw - (sg[0] + sg[1] + sg[2]) / 3.0 * trm);
            ec[2] = -f * qn * trm;
          }
          ps_.volume[p] = ps_.volume0[p] * J;
        }
      }
      chunk_fail_[c] += fails;
      if ((flags & kGrad) != 0 && fails == 0) run_material_chunk(c, dt, Lb.data(), wpre.data(), ws.data(), bs.data(), kLfromMid ? econs.data() : nullptr);
    }
  }
  std::size_t total = 0, first = nch;
  for (std::size_t c = 0; c < nch; ++c)
    if (chunk_fail_[c]) {
      total += chunk_fail_[c];
      if (first == nch) first = c;
    }
  // one reduction over the processes of a subdomain run: the failure flag and the signal speed
  double red[2] = {total ? 1.0 : 0.0, (flags & kGrad) != 0 && nch ? *std::max_element(chunk_speed_.begin(), chunk_speed_.end()) : 0.0};
  if (sub_.exchange) sub_.exchange->max(red, 2);
  if (red[0] > 0.0) {
    std::ostringstream os;
    if (total)
      os << total << " particle(s) failed at t = " << time_ << " s, step " << step_ << ": " << chunk_msg_[first];
    else
      os << "particles failed on another MPI rank at t = " << time_ << " s, step " << step_;
    std::fill(chunk_msg_.begin(), chunk_msg_.end(), std::string());
    throw SolverFailure(os.str(), false);
  }
  if ((flags & kGrad) != 0) max_speed_ = red[1];
}

// MUSL: v_p <- alpha (v_p + sum S (v* - v)) + (1 - alpha) sum S v*, and in the same coloured
// pass (m v_p)_i = sum_p S_ip m_p v_p into mom2_; afterwards the node momentum slots hold the
// re-projected momenta. Reads velocity() and updated_velocity() of the nodes, writes only mom2_
// inside the block footprint.
template <int NPA>
void Solver::musl_remap() {
  const int sx = sub_.shape[0], sy = sub_.shape[1];
  const std::size_t shift = shift_;
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
        const Stencil st = particle_stencil(kind, x + 3 * p, lp + 3 * p, o, h, sx, sy, shift);
        const AxisWeights &X = st.X, &Y = st.Y, &Z = st.Z;
        double vs0 = 0, vs1 = 0, vs2 = 0, vo0 = 0, vo1 = 0, vo2 = 0;
        for (int cc = 0; cc < NPA; ++cc)
          for (int bb = 0; bb < NPA; ++bb) {
            const double wyz = Y.w[bb] * Z.w[cc];
            const Node* row = nodes + st.row(sx, sy, bb, cc);
            double s0 = 0, s1 = 0, s2 = 0, o0 = 0, o1 = 0, o2 = 0;
#pragma GCC unroll 3
            for (int a = 0; a < NPA; ++a) {
              const double wx = X.w[a];
              const double* vstar = row[a].updated_velocity();
              const double* vold = row[a].velocity();
              s0 += wx * vstar[0];
              s1 += wx * vstar[1];
              s2 += wx * vstar[2];
              o0 += wx * vold[0];
              o1 += wx * vold[1];
              o2 += wx * vold[2];
            }
            vs0 += wyz * s0;
            vs1 += wyz * s1;
            vs2 += wyz * s2;
            vo0 += wyz * o0;
            vo1 += wyz * o1;
            vo2 += wyz * o2;
          }
        double* vp = v + 3 * p;
        flip_blend(vp, alpha, vs0, vs1, vs2, vo0, vo1, vo2);
        if (!std::isfinite(vp[0] + vp[1] + vp[2])) first_bad = std::min(first_bad, p);
        const double m = ps_.mass[p];
        const double mv0 = m * vp[0], mv1 = m * vp[1], mv2 = m * vp[2];
        for (int cc = 0; cc < NPA; ++cc)
          for (int bb = 0; bb < NPA; ++bb) {
            const double wyz = Y.w[bb] * Z.w[cc];
            const double c0 = mv0 * wyz, c1 = mv1 * wyz, c2 = mv2 * wyz;
            double* row = m2 + 3 * st.row(sx, sy, bb, cc);
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
  if (any_process(first_bad < ps_.size())) {
    std::ostringstream os;
    if (first_bad < ps_.size())
      os << "non-finite velocity at particle id " << ps_.id[first_bad] << " at t = " << time_ << " s, step " << step_;
    else
      os << "non-finite velocity on another MPI rank at t = " << time_ << " s, step " << step_;
    throw SolverFailure(os.str(), false);
  }
  Node* nd = nodes_.data();
  const std::size_t nn = nodes_.size();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < nn; ++i) {
    double* mv = nd[i].momentum();  // the re-projected momentum replaces the grid velocity
    mv[0] = m2[3 * i];
    mv[1] = m2[3 * i + 1];
    mv[2] = m2[3 * i + 2];
  }
}

// The instantiations Solver::step uses (step.cpp): NPA = 2 (linear) or 3 (uGIMP); the
// scatter modes and G2P flag/slot combinations of the USL, MUSL and USF schedules.
#define MPM_TRANSFER_INSTANTIATE(NPA)                                                         \
  template void Solver::scatter<NPA, kMass | kMom | kForce>();                                \
  template void Solver::scatter<NPA, kMass | kMom>();                                         \
  template void Solver::scatter<NPA, kForce>();                                               \
  template void Solver::g2p<NPA, kVel | kPos | kGrad, GridSlot::updated_velocity>(double);    \
  template void Solver::g2p<NPA, kPos | kGrad, GridSlot::velocity>(double);                  \
  template void Solver::g2p<NPA, kGrad, GridSlot::velocity>(double);                         \
  template void Solver::g2p<NPA, kVel | kPos, GridSlot::updated_velocity>(double);           \
  template void Solver::g2p<NPA, kVel | kPos | kGrad, GridSlot::midpoint>(double);           \
  template void Solver::musl_remap<NPA>();
MPM_TRANSFER_INSTANTIATE(2)
MPM_TRANSFER_INSTANTIATE(3)
#undef MPM_TRANSFER_INSTANTIATE

}  // namespace mpmfrag
