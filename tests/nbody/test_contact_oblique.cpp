/// @file test_contact_oblique.cpp
/// Oblique impacts with the tangential spring + Coulomb friction (ssdem.md §1.3, §3.1, §3.3:
/// Chung & Ooi 2011 tests 4 and 5): a sphere hitting a flat wall at a sweep of incidence angles and of
/// tangential speeds, and two equal spheres.
///
/// Analytic results used (sphere of mass m, radius R, I = (2/5) m R^2, no initial spin; v_n, v_t
/// incident normal and tangential speeds, psi = v_t / (mu v_n) the normalised incidence, J_t the
/// tangential impulse, j = J_t / (m mu v_n)):
///  * The contact-point slip g = v_t - R w obeys dg/dt = -(7/2) F_T / m, the overlap
///    d2x/dt2 = -F_N / m, so with the linear springs the tangential and normal frequencies are
///    w_t / w_n = sqrt((7/2) kappa), kappa = k_t / k_n. For kappa = 2/7 (the default) they are
///    equal and, undamped, F_T / F_N = kappa psi mu is constant while sticking. Hence (e_n = 1):
///      tan(theta) <= (7/2) mu  (psi <= 7/2): the contact sticks throughout, the slip reverses
///        (g' = -g), j = (4/7) psi;
///      psi > 7/2: it slides throughout, j = mu J_n / (m mu v_n) = 1 + e_n = 2 (gross sliding).
///    So R w' / (mu v_n) = (5/2) j = min((10/7) psi, 5) and v_t' / (mu v_n) = psi - j. The spring
///    model reaches the sliding branch at psi = 7/2, half the rigid-body value (7/2)(1 + e_n).
///  * Any kappa, undamped: sliding throughout (j = 2 exactly) iff the slider never recovers, i.e.
///    kappa g(t) >= mu dx/dt for all t with g(t) = v_t - (7/2) mu v_n (1 - cos w_n t), which gives
///    psi > psi_gs = 7/2 + |1/kappa - 7/2|. Below psi_gs the contact sticks part of the time and
///    j < 2; there the result is not closed-form and is compared with a converged continuous-time
///    1D integration of the same law (exact normal motion, tiny steps; wall_reference below).
///  * No-slip limit (mu -> infinity), undamped: the slip is a harmonic oscillator cut off at the
///    end of the contact, g' / g = cos(pi w_t / w_n) = cos(pi sqrt(3.5 kappa)) (cf. Schwartz+2012
///    eq. 35, which adds the tangential dashpot).
///  * With the normal dashpot (e_n < 1) the Coulomb limit uses |F_N|, which goes tensile after the
///    rebound velocity peaks (ssdem.md §1.2-1.3), so in gross sliding
///    J_t = mu int |F_N| dt = mu m (v_n (1 + e_n) + 2 (v_peak - e_n v_n)).
/// Two equal spheres: the same formulas in relative velocities with j = J_t / (m mu v_n,rel) =
/// min((2/7) psi, 1), and momentum and angular momentum (orbital + spin) conserved to round-off.
/// Discretisation: where the contact sticks or slides throughout, the result is second order in dt
/// (at 400 steps per contact the closed forms hold to 2e-4 of mu v_n, the rest being the lever arm
/// R - x); stick-slip transitions and the cut-off of a loaded spring at separation are first order
/// (sim - reference 1e-3 of mu v_n at 800 steps per contact, halving with dt).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "ssdem/contact_params.hpp"
#include "ssdem/simulation.hpp"

using namespace ssdem;

namespace {

struct Rebound {
  double vt = 0, vn = 0, Rw = 0;  ///< tangential and normal (outward) centre speed, R * spin
};

ContactParams friction(double mu, double kappa, double kn, double en = 1.0, double et = 1.0) {
  ContactParams p;
  p.parts = kPartTangential | (en < 1.0 || et < 1.0 ? kPartDamping : 0u);
  p.kn = kn;
  p.kt_over_kn = kappa;
  p.mu_s = mu;
  p.en = en;
  p.et = et;
  return p;
}

// Sphere (radius R, density rho) hitting the wall z = 0 with velocity (v_t, 0, -v_n), no spin;
// the motion is in the x-z plane, the spin along y (R w_y > 0 for friction opposing +x slip).
Rebound wall_sim(const ContactParams& p, double R, double rho, double vn, double vt,
                 double steps_per_contact) {
  const double m = rho * 4.0 / 3.0 * M_PI * R * R * R;
  const double dt = p.contact_time(m) / steps_per_contact;
  Spheres sp;
  sp.push(0, Vec3(0, 0, R + 2.5 * vn * dt), Vec3(vt, 0, -vn), Vec3::Zero(), m, R);
  SimConfig c;
  c.contacts = true;
  c.contact = p;
  c.walls.push_back(Plane{Vec3::Zero(), Vec3::UnitZ()});
  c.dt = dt;
  Simulation sim(sp, c);
  bool touched = false, left = false;
  for (int k = 0; k < 20 * steps_per_contact && !left; ++k) {
    sim.step();
    const double z = sim.spheres().x[0].z();
    touched = touched || z < R;
    left = touched && z > R;
  }
  EXPECT_TRUE(left) << "the sphere did not leave the wall";
  sim.step();
  const auto& S = sim.spheres();
  return {S.v[0].x(), S.v[0].z(), S.s[0] * S.w[0].y()};
}

// Continuous-time reference for the same law in 1D: exact damped normal motion
// x = (v_n/w1) e^{-a t} sin(w1 t) over t in [0, pi/w1], lever arm l = R - x; tangential spring
// S and dashpot with the Coulomb return mapping (|k_t S + c_t g| <= mu |F_N|, S re-set on slip),
// integrated with n tiny steps (error O(1/n)).
Rebound wall_reference(const ContactParams& p, double R, double rho, double vn, double vt,
                       int n = 400000) {
  const double m = rho * 4.0 / 3.0 * M_PI * R * R * R, I = 0.4 * m * R * R;
  const double cn = p.cn_pre() * std::sqrt(m), ct = p.ct_pre() * std::sqrt(m), kt = p.kt();
  const double a = cn / (2 * m), w1 = std::sqrt(p.kn / m - a * a), T = M_PI / w1, h = T / n;
  double v = vt, w = 0, S = 0;
  for (int i = 0; i < n; ++i) {
    const double t = (i + 0.5) * h, ea = std::exp(-a * t);
    const double x = vn / w1 * ea * std::sin(w1 * t);
    const double xd = vn * ea * (std::cos(w1 * t) - a / w1 * std::sin(w1 * t));
    const double fmax = p.mu_s * std::fabs(p.kn * x + cn * xd), l = R - x;
    const double g = v - l * w;
    S += g * h;
    double F = kt * S + ct * g;
    if (std::fabs(F) > fmax) {
      F = std::copysign(fmax, F);
      S = (F - ct * g) / kt;
    }
    v -= F / m * h;
    w += l * F / I * h;
  }
  return {v, vn * std::exp(-a * T), R * w};
}

// int |F_N| dt / (m v_n) for the linear spring-dashpot: (1 + e) + 2 (v_peak/v_n - e), where
// v_peak is the largest rebound speed (at d2x/dt2 = 0, w1 t* = pi - atan(2 a w1 / (w1^2 - a^2))).
double abs_normal_impulse(const ContactParams& p, double m) {
  const double cn = p.cn_pre() * std::sqrt(m);
  const double a = cn / (2 * m), w1 = std::sqrt(p.kn / m - a * a);
  const double ts = (M_PI - std::atan2(2 * a * w1, w1 * w1 - a * a)) / w1;
  const double vpeak = -std::exp(-a * ts) * (std::cos(w1 * ts) - a / w1 * std::sin(w1 * ts));
  const double e = std::exp(-a * M_PI / w1);
  return (1 + e) + 2 * (vpeak - e);
}

}  // namespace

TEST(ContactOblique, WallAngleSweepUndampedMatchesClosedForm) {
  // Chung & Ooi test 4 geometry: alumina sphere R = 2.5 mm, rho = 4000, |v| = 3.9 m/s,
  // mu = 0.092, angle 5-85 deg from the normal; e_n = 1 and k_t = (2/7) k_n so that the
  // closed form above holds at every angle (sticking below 17.8 deg, gross sliding above).
  // k_n = 1e11 N/m: max overlap 3e-5 R, so l = R - x is R to that accuracy.
  const double R = 2.5e-3, rho = 4000, V = 3.9, mu = 0.092;
  const ContactParams p = friction(mu, 2.0 / 7.0, 1e11);
  std::printf("deg    psi     e_t (exp)            Rw/(mu vn) (exp)     vn'/vn\n");
  double worst_et = 0, worst_w = 0;
  for (double deg : {5.0, 10.0, 15.0, 17.0, 18.5, 20.0, 25.0, 30.0, 35.0, 45.0, 60.0, 75.0, 85.0}) {
    const double th = deg * M_PI / 180, vn = V * std::cos(th), vt = V * std::sin(th);
    const double psi = vt / (mu * vn);
    const Rebound r = wall_sim(p, R, rho, vn, vt, 400);
    const double j = std::min(4.0 / 7.0 * psi, 2.0);
    const double et = r.vt / vt, et_exp = 1 - j / psi;
    const double wn = r.Rw / (mu * vn), wn_exp = 2.5 * j;
    std::printf("%4.1f  %6.3f  %+.6f (%+.6f)  %.6f (%.6f)  %.6f\n", deg, psi, et, et_exp, wn,
                wn_exp, r.vn / vn);
    // errors in units of mu v_n (the natural scale of the friction impulse)
    worst_et = std::max(worst_et, std::fabs(et - et_exp) * psi);
    worst_w = std::max(worst_w, std::fabs(wn - wn_exp));
    EXPECT_NEAR((et - et_exp) * psi, 0.0, 5e-4) << deg;
    EXPECT_NEAR(wn, wn_exp, 1e-3) << deg;
    EXPECT_NEAR(r.vn / vn, 1.0, 1e-4) << deg;
  }
  std::printf("worst |dv_t|/(mu v_n) = %.2e, worst |d(R w)|/(mu v_n) = %.2e\n", worst_et, worst_w);
}

TEST(ContactOblique, WallAngleSweepKharazMatchesReferenceAndSlidingBranch) {
  // Chung & Ooi test 4 as specified (e_n = 0.98, tangential dashpot off): against the 1D
  // reference at every angle; at large angles the sliding branch J_t -> mu int|F_N| dt (the
  // dashpot makes F_N jump to c_n v_n at first touch, so a short sticking phase always precedes
  // sliding and the branch is reached only as psi grows); e_n is recovered at every angle.
  // Sim - reference is first order in dt at the stick-slip transitions (1.2e-3 at 400 steps,
  // 3.3e-4 at 1600, measured at 17 deg).
  const double R = 2.5e-3, rho = 4000, V = 3.9, mu = 0.092;
  const ContactParams p = friction(mu, 2.0 / 7.0, 1e11, 0.98);
  const double m = rho * 4.0 / 3.0 * M_PI * R * R * R;
  const double jslide = abs_normal_impulse(p, m);
  std::printf("e_n = 0.98: sliding branch j = int|F_N|/(m v_n) = %.6f (1 + e_n = 1.98)\n", jslide);
  std::printf("deg    psi     j (reference)        e_n\n");
  for (double deg : {5.0, 10.0, 15.0, 17.0, 18.5, 20.0, 25.0, 30.0, 45.0, 60.0, 85.0}) {
    const double th = deg * M_PI / 180, vn = V * std::cos(th), vt = V * std::sin(th);
    const Rebound r = wall_sim(p, R, rho, vn, vt, 400), ref = wall_reference(p, R, rho, vn, vt);
    const double j = (vt - r.vt) / (mu * vn), jref = (vt - ref.vt) / (mu * vn);
    std::printf("%4.1f  %6.3f  %.6f (%.6f)  %.6f\n", deg, vt / (mu * vn), j, jref, r.vn / vn);
    EXPECT_NEAR(j, jref, 2.5e-3) << deg;
    EXPECT_NEAR(r.Rw / (mu * vn), 2.5 * jref, 6e-3) << deg;
    EXPECT_NEAR(r.vn / vn, 0.98, 1e-4) << deg;
    if (deg >= 45) {
      EXPECT_LT(jslide - jref, 1e-4) << deg;  // below the branch by 4e-5 at 45 deg
      EXPECT_GE(jslide - jref, 0.0) << deg;
      EXPECT_NEAR(j, jslide, 5e-4) << deg;
      EXPECT_NEAR(r.Rw / (mu * vn), 2.5 * jslide, 1.5e-3) << deg;
    }
  }
}

namespace {
// Chung & Ooi test 5 inputs: steel sphere R = 10 um, rho = 7850, v_n = 5 m/s, mu = 0.3; k_n such
// that the overlap stays below 3e-5 R. Sweep of psi = v_t / (mu v_n) for one contact law;
// returns the simulated and reference j = J_t / (m mu v_n).
struct SweepRow {
  double psi, j, jref, Rw;
};
std::vector<SweepRow> tangential_sweep(const ContactParams& p, const std::vector<double>& psis,
                                       double steps = 400) {
  const double R = 10e-6, rho = 7850, vn = 5.0, mu = p.mu_s;
  std::vector<SweepRow> rows;
  std::printf("kappa = %.4f, e_n = %.2f, e_t = %.2f\n  psi      j (reference)          "
              "Rw'/(mu vn)   vt'/(mu vn)\n", p.kt_over_kn, p.en, p.et);
  for (double psi : psis) {
    const double vt = psi * mu * vn;
    const Rebound r = wall_sim(p, R, rho, vn, vt, steps), ref = wall_reference(p, R, rho, vn, vt);
    rows.push_back({psi, (vt - r.vt) / (mu * vn), (vt - ref.vt) / (mu * vn), r.Rw / (mu * vn)});
    std::printf("  %6.3f  %.6f (%.6f)  %.5f      %.5f\n", psi, rows.back().j, rows.back().jref,
                rows.back().Rw, r.vt / (mu * vn));
  }
  return rows;
}
constexpr double kKnTest5 = 1e10;
}  // namespace

TEST(ContactOblique, WallTangentialSweepSpringRatioSetsTheRegimes) {
  // Chung & Ooi test 5 style, e_n = 1, three spring ratios kappa = k_t/k_n. Gross sliding
  // (j = 2, R w'/(mu v_n) = 5 exactly) iff psi > psi_gs = 7/2 + |1/kappa - 7/2|: 3.5 (kappa
  // 2/7), 6 (kappa 1), 10 (kappa 0.1). Below it the contact sticks part of the time and j < 2;
  // every point is compared with the 1D reference, and the kappa = 2/7 points with the closed
  // form min((4/7) psi, 2).
  for (double kappa : {2.0 / 7.0, 1.0, 0.1}) {
    const ContactParams p = friction(0.3, kappa, kKnTest5);
    const double psi_gs = 3.5 + std::fabs(1.0 / kappa - 3.5);
    std::vector<double> psis = {0.2, 1.0, 2.0, 3.0, 0.8 * psi_gs, 0.95 * psi_gs, 1.05 * psi_gs,
                                1.3 * psi_gs, 15.0, 46.7};
    const auto rows = tangential_sweep(p, psis, 800);
    for (const SweepRow& r : rows) {
      EXPECT_NEAR(r.j, r.jref, 2.5e-3) << kappa << " " << r.psi;
      EXPECT_NEAR(r.Rw, 2.5 * r.jref, 6e-3) << kappa << " " << r.psi;
      if (kappa == 2.0 / 7.0) {
        EXPECT_NEAR(r.j, std::min(4.0 / 7.0 * r.psi, 2.0), 1e-4) << r.psi;
      }
      if (r.psi > psi_gs) {
        EXPECT_NEAR(r.jref, 2.0, 1e-4) << kappa << " " << r.psi;
        EXPECT_NEAR(r.j, 2.0, 5e-4) << kappa << " " << r.psi;
        EXPECT_NEAR(r.Rw, 5.0, 1.5e-3) << kappa << " " << r.psi;
      }
    }
    // just below the boundary the contact recovers from sliding at some point: j < 2
    if (kappa != 2.0 / 7.0) {
      EXPECT_LT(rows[4].jref, 2.0 - 0.01) << kappa;  // 0.8 psi_gs
      EXPECT_LT(rows[4].j, 2.0 - 0.01) << kappa;
    }
  }
}

TEST(ContactOblique, WallNoSlipLimitTangentialRestitutionDependsOnSpringRatio) {
  // mu -> infinity, e_n = 1: the slip velocity g = v_t - R w oscillates at w_t = sqrt(3.5 kappa)
  // w_n and is frozen when the contact ends: g'/g = cos(pi sqrt(3.5 kappa)): -1 for the default
  // kappa = 2/7 (the rigid no-slip value would be 0: rolling), -0.284 for 0.1, +0.917 for 1.
  for (double kappa : {0.1, 2.0 / 7.0, 0.5, 1.0}) {
    const ContactParams p = friction(1e4, kappa, kKnTest5);
    const double R = 10e-6, vn = 5.0, vt = 2.0;
    const Rebound r = wall_sim(p, R, 7850, vn, vt, 2000);
    const double g = (r.vt - r.Rw) / vt, g_exp = std::cos(M_PI * std::sqrt(3.5 * kappa));
    std::printf("no slip, kappa = %.4f: g'/g = %+.6f (exp %+.6f)\n", kappa, g, g_exp);
    EXPECT_NEAR(g, g_exp, 2e-3) << kappa;
  }
}

TEST(ContactOblique, WallGravelDampedSlidingBranchUsesAbsNormalForce) {
  // Gravel-like dashpots (e_n = e_t = 0.55, k_t = (2/7) k_n): sim against the 1D reference over
  // the whole psi range, and for large psi the sliding branch j = int|F_N| dt / (m v_n) =
  // (1 + e_n) + 2 (v_peak/v_n - e_n): the Coulomb limit follows |F_N| through the tensile end of
  // the dashpot contact (ssdem.md §1.2-1.3). A limit of mu max(F_N, 0) would give 1 + e_n + the
  // tensile impulse less, i.e. 2 (v_peak/v_n - e_n) lower.
  ContactParams p = friction(0.3, 2.0 / 7.0, kKnTest5, 0.55, 0.55);
  const double m = 7850 * 4.0 / 3.0 * M_PI * 1e-15;
  const double jslide = abs_normal_impulse(p, m);
  std::printf("e_n = 0.55: sliding branch j = %.6f (1 + e_n = 1.55)\n", jslide);
  ASSERT_GT(jslide - 1.55, 0.05);  // the tensile part is not negligible here
  const auto rows = tangential_sweep(p, {0.2, 1.0, 2.0, 3.0, 4.0, 6.0, 10.0, 20.0, 46.7});
  for (const SweepRow& r : rows) {
    EXPECT_NEAR(r.j, r.jref, 2.5e-3) << r.psi;
    EXPECT_NEAR(r.Rw, 2.5 * r.jref, 6e-3) << r.psi;
    if (r.psi >= 10) {
      EXPECT_NEAR(r.jref, jslide, 1e-3) << r.psi;
      EXPECT_NEAR(r.j, jslide, 2e-3) << r.psi;
    }
  }
}

namespace {
struct PairRun {
  Vec3 v0, v1, w0, w1;
  double maxP = 0, maxL = 0, E0 = 0, E1 = 0;
};
// Two spheres (radii R0, R1, same density) meeting with relative velocity (-vn, vt_y, vt_z) and
// spins w0, w1; the line of centres is exactly x at first touch (t0 = 2.5 dt), the pair centred
// at c. Momentum and angular momentum (orbital + spin, about the origin) are checked every step
// against their initial values, relative to sum m|v| and sum (m |x||v| + I |w|).
PairRun pair_impact(const ContactParams& p, double R0, double R1, double vn, const Vec3& vt,
                    const Vec3& w0, const Vec3& w1, const Vec3& c, double steps = 400) {
  const double rho = 4000, m0 = rho * 4.0 / 3.0 * M_PI * R0 * R0 * R0,
               m1 = rho * 4.0 / 3.0 * M_PI * R1 * R1 * R1;
  const double mu = m0 * m1 / (m0 + m1), dt = p.contact_time(mu) / steps, t0 = 2.5 * dt;
  const Vec3 vrel(-vn, vt.y(), vt.z());
  const Vec3 rho0 = Vec3(R0 + R1, 0, 0) - t0 * vrel;
  Spheres sp;
  sp.push(0, c - m1 / (m0 + m1) * rho0, -m1 / (m0 + m1) * vrel, w0, m0, R0);
  sp.push(1, c + m0 / (m0 + m1) * rho0, m0 / (m0 + m1) * vrel, w1, m1, R1);
  SimConfig cfg;
  cfg.contacts = true;
  cfg.contact = p;
  cfg.dt = dt;
  Simulation sim(sp, cfg);
  const Diagnostics d0 = sim.diagnostics();
  double pscale = 0, lscale = 0;
  for (std::size_t i = 0; i < 2; ++i) {
    pscale += sp.m[i] * sp.v[i].norm();
    lscale += sp.m[i] * sp.x[i].norm() * sp.v[i].norm() + sp.inertia(i) * sp.w[i].norm();
  }
  PairRun out;
  out.E0 = d0.total();
  bool touched = false, left = false;
  for (int k = 0; k < 20 * steps && !left; ++k) {
    sim.step();
    const double gap = (sim.spheres().x[1] - sim.spheres().x[0]).norm() - R0 - R1;
    touched = touched || gap < 0;
    left = touched && gap > 0;
    const Diagnostics d = sim.diagnostics();
    out.maxP = std::max(out.maxP, (d.momentum - d0.momentum).norm() / pscale);
    out.maxL = std::max(out.maxL, (d.angular_momentum - d0.angular_momentum).norm() / lscale);
  }
  EXPECT_TRUE(left);
  sim.step();
  const auto& S = sim.spheres();
  out.v0 = S.v[0];
  out.v1 = S.v[1];
  out.w0 = S.w[0];
  out.w1 = S.w[1];
  out.E1 = sim.diagnostics().total();
  return out;
}
}  // namespace

TEST(ContactOblique, TwoEqualSpheresStickingAndSlidingBranches) {
  // Equal alumina spheres R = 2.5 mm, relative v_n = 1 m/s, e_n = 1, mu = 0.3, kappa = 2/7:
  // j = J_t / (m mu v_n) = min((2/7) psi, 1), each sphere's velocity changes by J_t/m along the
  // tangent and both spin the same way, R w_z = (5/2) J_t / m. Energy: sticking returns the
  // spring energy (none lost); sliding loses the friction work int F_T g dt with
  // g = u_t0 - (7/2) mu v_n (1 - cos w t): dE = -2 mu m_red v_n (u_t0 - (7/2) mu v_n).
  // k_n = 1e12: the contact normal turns by v_t t_c / (2R) < 3e-5 rad during the contact,
  // which the fixed-frame formulas ignore.
  const ContactParams p = friction(0.3, 2.0 / 7.0, 1e12);
  const double R = 2.5e-3, vn = 1.0, mu = 0.3;
  const double mred = 0.5 * 4000 * 4.0 / 3.0 * M_PI * R * R * R;
  std::printf("psi     j (exp)             R w0, R w1 / (mu vn)   |dP|      |dL|      "
              "dE/(m_red mu^2 vn^2) (exp)\n");
  for (double psi : {0.5, 2.0, 3.2, 3.8, 6.0, 12.0}) {
    const double vt = psi * mu * vn;
    const PairRun r = pair_impact(p, R, R, vn, Vec3(0, vt, 0), Vec3::Zero(), Vec3::Zero(),
                                  Vec3(0.1, -0.2, 0.05));
    const double j = -(r.v1.y() - 0.5 * vt) / (mu * vn), j0 = (r.v0.y() + 0.5 * vt) / (mu * vn);
    const double j_exp = std::min(2.0 / 7.0 * psi, 1.0);
    const double dE = (r.E1 - r.E0) / (mred * mu * mu * vn * vn);
    const double dE_exp = psi < 3.5 ? 0.0 : -2 * (psi - 3.5);
    std::printf("%5.2f  %.6f (%.6f)  %.6f %.6f  %.1e  %.1e  %+.6f (%+.6f)\n", psi, j, j_exp,
                R * r.w0.z() / (mu * vn), R * r.w1.z() / (mu * vn), r.maxP, r.maxL, dE, dE_exp);
    EXPECT_NEAR(j, j_exp, 2.5e-4) << psi;
    EXPECT_NEAR(j0, j_exp, 2.5e-4) << psi;
    EXPECT_NEAR(R * r.w0.z() / (mu * vn), 2.5 * j_exp, 6e-4) << psi;
    EXPECT_NEAR(R * r.w1.z() / (mu * vn), 2.5 * j_exp, 6e-4) << psi;
    EXPECT_NEAR(r.v1.x() - r.v0.x(), vn, 1e-4 * vn) << psi;  // e_n = 1
    EXPECT_LT(r.maxP, 1e-14);
    EXPECT_LT(r.maxL, 1e-14);
    EXPECT_NEAR(dE, dE_exp, 2e-4 * std::max(1.0, std::fabs(dE_exp))) << psi;
  }
}

TEST(ContactOblique, TwoSpheresAllPartsConserveMomentumAndAngularMomentum) {
  // General 3D oblique impacts with spins and every part on (gravel-like: dashpots, Coulomb
  // tangential, rolling and twisting springs with sliders), equal and unequal radii (unequal
  // lever arms): P and L = sum (x x m v + I w) to round-off at every step; energy only lost.
  ContactParams p = gravel_preset(1e11);
  for (double R1 : {2.5e-3, 5e-3}) {
    for (double vt : {0.2, 3.0}) {
      const PairRun r = pair_impact(p, 2.5e-3, R1, 1.0, Vec3(0, vt, 0.6 * vt),
                                    Vec3(30, -50, 80), Vec3(-60, 20, 10), Vec3(0.3, -0.2, 0.1));
      std::printf("R1 = %.1e, v_t = %.1f: |dP| = %.1e, |dL| = %.1e, E1/E0 - 1 = %+.3e\n", R1, vt,
                  r.maxP, r.maxL, r.E1 / r.E0 - 1);
      EXPECT_LT(r.maxP, 1e-14);
      EXPECT_LT(r.maxL, 1e-14);
      EXPECT_LT(r.E1, r.E0);
    }
  }
}
