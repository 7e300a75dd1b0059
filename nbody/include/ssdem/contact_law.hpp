/// @file contact_law.hpp
/// The soft-sphere pair kernel (force and torques on one contact), specialised at compile time
/// on the set of enabled parts so that parts that are off cost nothing.
///
/// Governing equations (S12 = Schwartz, Richardson & Michel 2012, Granular Matter 14:363;
/// Z17 = Zhang et al. 2017, Icarus 294:98; the pkdgrav implementation `smoothfcn.c:DoDEM` as
/// summarised in shared/reference/ssdem.md §1):
///   rho = x_n - x_p, d = |rho|, n = rho/d, overlap x = s_p + s_n - d  (contact iff x > 0)
///   lever arms l_p = (s_p^2 - s_n^2 + d^2)/(2d), l_n = d - l_p                    (S12 eqs 8-12)
///   u = v_n - v_p - l_n (w_n x n) - l_p (w_p x n), u_n = (u.n) n, u_t = u - u_n
///   F_N = -k_n x n + C_n u_n                                                     (S12 eqs 3, 13)
///   S transported each step: rotate about nbar = (n_old + n)/|.| by (h/2)(w_p + w_n).nbar, then
///   by the rotation taking n_old to n; S += u_t h                               (S12 eqs 17-19)
///   F_T = k_t S + C_t u_t, capped at mu_s |F_N| (SlipRule)                       (S12 eqs 6-7, 14)
///   a = beta Rbar, Rbar = s_p s_n/(s_p + s_n); dw = w_n - w_p
///   v_roll = dw - (dw.n) n + ((l_n - l_p)/(2 l_p l_n)) (n x u);  theta_r += v_roll h
///   M_roll = k_n a^2 theta_r + C_n a^2 v_roll, |k_r theta_r| <= mu_r a |F_N| (else M = crit,
///   increment undone)                                                            (Z17; DoDEM)
///   theta_q += (dw.n) h; M_tw = (2 k_t a^2 theta_q + 2 C_t a^2 dw.n) n,
///   |k_q theta_q| <= mu_t mu_s a |F_N|                                           (Z17; DoDEM)
///   force on p: F_N + F_T (n gets -F); torque on p: l_p n x F_T + M_roll + M_tw;
///   torque on n: l_n n x F_T - M_roll - M_tw                                     (S12 eqs 22-23)
/// Velocities and spins entering the dashpots (and the Coulomb test) are the *predicted* ones at
/// t_{n+1}, as in pkdgrav. The history increments S += u_t h, theta_r += v_roll h and
/// theta_q += (dw.n) h use the half-step (drift) velocities and spins v_{n+1/2}, w_{n+1/2}, so that
/// they are the midpoint rule for int u dt over [t_n, t_{n+1}], like the positions that give the
/// overlap (deviation from pkdgrav, which increments with the predicted u: that puts the springs
/// h/2 ahead of the motion and makes the tangential response first order in h; measured in
/// test_nbody_contact_oblique). The transport rotation uses the half-step spins.
/// A plane wall is the limit s_n -> infinity with zero wall velocity: l_p = distance from the
/// centre to the plane, Rbar = s_p, the lever-arm correction in v_roll becomes 1/(2 l_p), and
/// the wall takes no torque. (Deviation: pkdgrav's wall law differs in details that are not
/// in the reference notes; this limit is the natural one for the sphere-sphere law.)
#pragma once
#include <Eigen/Geometry>
#include <cmath>

#include "ssdem/contact_params.hpp"
#include "ssdem/spheres.hpp"

namespace ssdem {

/// Per-contact history (the part of it that exists for the enabled parts).
struct PairHistoryRef {
  Vec3* S = nullptr;        ///< tangential spring displacement [m]
  Vec3* n_old = nullptr;    ///< normal at the previous step
  Vec3* theta_r = nullptr;  ///< rolling displacement [rad]
  double* theta_q = nullptr;///< twist angle [rad]
};

/// Coefficients shared by all pairs (precomputed once).
struct ContactCoeffs {
  double kn, kt, cn_pre, ct_pre, mu_s, mu_r, mu_t, beta;
  SlipRule slip;
  explicit ContactCoeffs(const ContactParams& p)
      : kn(p.kn), kt(p.kt()), cn_pre(p.cn_pre()), ct_pre(p.ct_pre()), mu_s(p.mu_s),
        mu_r(p.mu_r), mu_t(p.mu_t), beta(p.beta), slip(p.slip) {}
};

/// Rodrigues rotation of v about unit axis k by angle (cos c, sin s).
inline Vec3 rotate_about(const Vec3& v, const Vec3& k, double c, double s) {
  return v * c + k.cross(v) * s + k * (k.dot(v) * (1.0 - c));
}

/// Result of one pair evaluation.
struct PairResult {
  Vec3 F = Vec3::Zero();   ///< force on p (n receives -F)
  Vec3 Tp = Vec3::Zero();  ///< torque on p
  Vec3 Tn = Vec3::Zero();  ///< torque on n
  double overlap = 0.0;
};

/// Evaluate one contact. `active` is the history flag (true if the pair was in contact at the
/// previous step); on return it says whether it is in contact now. Returns false (and zero
/// history) when there is no overlap. For WALL, x_n is the foot of the perpendicular from x_p
/// onto the plane, s_n = 0, v_n = w_n = 0 and mu = m_p. v/w are the predicted velocities and
/// spins at t_{n+1}; v_half/w_half the half-step ones (history increments, transport).
template <unsigned PARTS, bool WALL>
inline bool contact_pair(const ContactCoeffs& c, const Vec3& rho, double sp, double sn,
                         double mu, const Vec3& vp, const Vec3& vn, const Vec3& wp,
                         const Vec3& wn, const Vec3& vp_half, const Vec3& vn_half,
                         const Vec3& wp_half, const Vec3& wn_half, double h, bool& active,
                         PairHistoryRef hist, PairResult& out) {
  constexpr bool DAMP = PARTS & kPartDamping;
  constexpr bool TANG = PARTS & kPartTangential;
  constexpr bool ROLL = PARTS & kPartRolling;
  constexpr bool TWIST = PARTS & kPartTwisting;
  constexpr bool HIST = TANG || ROLL || TWIST;
  const double d2 = rho.squaredNorm();
  const double reach = sp + sn;
  if (d2 >= reach * reach) {
    active = false;
    return false;
  }
  const double d = std::sqrt(d2);
  const double x = reach - d;
  const Vec3 n = rho / d;
  double lp, ln, Rbar;
  if constexpr (WALL) {
    lp = d;
    ln = 0.0;
    Rbar = sp;
  } else {
    lp = (sp * sp - sn * sn + d2) / (2.0 * d);
    ln = d - lp;
    Rbar = sp * sn / reach;
  }
  Vec3 u;
  if constexpr (WALL)
    u = -vp - lp * wp.cross(n);
  else
    u = vn - vp - ln * wn.cross(n) - lp * wp.cross(n);
  const double un_s = u.dot(n);
  // Contact-point relative velocity at the half step: drives the history increments.
  Vec3 uh = Vec3::Zero();
  if constexpr (HIST) {
    if constexpr (WALL)
      uh = -vp_half - lp * wp_half.cross(n);
    else
      uh = vn_half - vp_half - ln * wn_half.cross(n) - lp * wp_half.cross(n);
  }
  (void)vp_half;
  (void)vn_half;
  Vec3 FN = (-c.kn * x) * n;
  double cn = 0.0;
  if constexpr (DAMP) {
    cn = c.cn_pre * std::sqrt(mu);
    FN += (cn * un_s) * n;
  }
  const double FNmag = FN.norm();
  out.F = FN;
  out.Tp.setZero();
  out.Tn.setZero();
  out.overlap = x;

  if constexpr (HIST) {
    if (!active) {
      hist.n_old[0] = n;
      if constexpr (TANG) hist.S[0].setZero();
      if constexpr (ROLL) hist.theta_r[0].setZero();
      if constexpr (TWIST) hist.theta_q[0] = 0.0;
    } else if constexpr (TANG || ROLL) {
      // Transport the tangential and rolling displacements with the contact frame.
      const Vec3& no = hist.n_old[0];
      Vec3 nbar = no + n;
      const double nb = nbar.norm();
      if (nb > 0.0) {
        nbar /= nb;
        double ang;
        if constexpr (WALL)
          ang = 0.5 * h * wp_half.dot(nbar);
        else
          ang = 0.5 * h * (wp_half + wn_half).dot(nbar);
        if (ang != 0.0) {
          const double ca = std::cos(ang), sa = std::sin(ang);
          if constexpr (TANG) hist.S[0] = rotate_about(hist.S[0], nbar, ca, sa);
          if constexpr (ROLL) hist.theta_r[0] = rotate_about(hist.theta_r[0], nbar, ca, sa);
        }
      }
      const Vec3 ax = no.cross(n);
      const double sn2 = ax.norm();
      if (sn2 > 1e-300) {
        const Vec3 k = ax / sn2;
        const double cc = no.dot(n);
        if constexpr (TANG) hist.S[0] = rotate_about(hist.S[0], k, cc, sn2);
        if constexpr (ROLL) hist.theta_r[0] = rotate_about(hist.theta_r[0], k, cc, sn2);
      }
      hist.n_old[0] = n;
    }
  }
  active = true;

  if constexpr (TANG) {
    const Vec3 ut = u - un_s * n;
    Vec3& S = hist.S[0];
    S += (uh - uh.dot(n) * n) * h;
    double ct = 0.0;
    if constexpr (DAMP) ct = c.ct_pre * std::sqrt(mu);
    Vec3 FT = c.kt * S + ct * ut;
    const double Fmax = c.mu_s * FNmag;
    const double ft2 = FT.squaredNorm();
    if (ft2 > Fmax * Fmax) {
      if (c.slip == SlipRule::coulomb) {
        FT *= Fmax / std::sqrt(ft2);
        S = (FT - ct * ut) / c.kt;
      } else {
        S.setZero();
        const double utm = ut.norm();
        FT = utm > 0.0 ? Vec3((std::min(Fmax, ct * utm) / utm) * ut) : Vec3::Zero();
      }
    }
    out.F += FT;
    const Vec3 nxF = n.cross(FT);
    out.Tp = lp * nxF;
    if constexpr (!WALL) out.Tn = ln * nxF;
  }
  if constexpr (ROLL || TWIST) {
    const double a = c.beta * Rbar;
    Vec3 dw, dwh;
    if constexpr (WALL) {
      dw = -wp;
      dwh = -wp_half;
    } else {
      dw = wn - wp;
      dwh = wn_half - wp_half;
    }
    const double dwn = dw.dot(n), dwhn = dwh.dot(n);
    if constexpr (ROLL) {
      double corr;
      if constexpr (WALL)
        corr = 0.5 / lp;
      else
        corr = (ln - lp) / (2.0 * lp * ln);
      const Vec3 vroll = dw - dwn * n + corr * n.cross(u);
      const Vec3 vroll_h = dwh - dwhn * n + corr * n.cross(uh);
      Vec3& th = hist.theta_r[0];
      th += vroll_h * h;
      const double kr = c.kn * a * a;
      const Vec3 spring = kr * th;
      const double crit = c.mu_r * a * FNmag;
      Vec3 M;
      const double sp2 = spring.squaredNorm();
      if (sp2 > crit * crit) {
        M = spring * (crit / std::sqrt(sp2));
        th -= vroll_h * h;
      } else {
        M = spring;
        if constexpr (DAMP) M += (cn * a * a) * vroll;
      }
      out.Tp += M;
      if constexpr (!WALL) out.Tn -= M;
    }
    if constexpr (TWIST) {
      double& q = hist.theta_q[0];
      q += dwhn * h;
      const double kq = 2.0 * c.kt * a * a;
      const double crit = c.mu_t * c.mu_s * a * FNmag;
      double Mq = kq * q;
      if (std::fabs(Mq) > crit) {
        Mq = std::copysign(crit, Mq);
        q -= dwhn * h;
      } else if constexpr (DAMP) {
        Mq += 2.0 * c.ct_pre * std::sqrt(mu) * a * a * dwn;
      }
      out.Tp += Mq * n;
      if constexpr (!WALL) out.Tn -= Mq * n;
    }
  }
  return true;
}

/// Elastic energy stored in one contact: k_n x^2/2 + k_t |S|^2/2 + k_r |theta_r|^2/2 +
/// k_q theta_q^2/2 (parts that are off contribute nothing).
inline double contact_elastic_energy(const ContactCoeffs& c, unsigned parts, double x, double Rbar,
                                     const Vec3* S, const Vec3* th, const double* q) {
  double e = 0.5 * c.kn * x * x;
  const double a = c.beta * Rbar;
  if ((parts & kPartTangential) && S) e += 0.5 * c.kt * S->squaredNorm();
  if ((parts & kPartRolling) && th) e += 0.5 * c.kn * a * a * th->squaredNorm();
  if ((parts & kPartTwisting) && q) e += 0.5 * 2.0 * c.kt * a * a * (*q) * (*q);
  return e;
}

}  // namespace ssdem
