/// @file bonds.hpp
/// Parallel bonds between spheres (Potyondy & Cundall 2004, "A bonded-particle model for rock",
/// Int. J. Rock Mech. Min. Sci. 41:1329, §2.2 "parallel bond", eqs 5-12 in their numbering of the
/// force-displacement law; LAMMPS BPM "bpm/rotational" as a reference for the mechanics).
///
/// A bond between spheres a and b is a cylinder of radius R_b = lambda min(s_a, s_b) (key
/// bonds.radius_ratio) between the centres, created at rest with length L0 = |x_b - x_a|. With
///   A = pi R_b^2, I = pi R_b^4 / 4, J = pi R_b^4 / 2 (area, second moment, polar moment) and
///   k_n, k_s the normal and shear stiffness per unit area [N/m^3]:
///   n = (x_b - x_a)/d, d = |x_b - x_a|, lever arms l_a, l_b as for contacts (contact_law.hpp)
///   normal force  F_n = k_n A (d - L0)              (total form: exact, energy-conserving;
///                                                    P&C write it incrementally, same thing)
///   shear force   F_s += k_s A du_s,  du_s = (u_h - (u_h.n) n) h     (P&C eq. for dF^s)
///   twist moment  M_t += k_s J (dw.n) h,  bending M_b += k_n I (dw - (dw.n) n) h,
///                 dw = w_b - w_a (half-step spins)                   (P&C eqs for dM^n, dM^s)
///   F_s and M_b are carried with the bond frame each step like the contact history
///   (FrameTransport, contact/part.hpp).
///   on a: force F_n n + F_s, torque l_a n x F_s + M_t n + M_b; on b the force's negative and
///   torque l_b n x F_s - M_t n - M_b (angular momentum conserved, as for contacts).
///   Stresses (tension positive): sigma = F_n / A + |M_b| R_b / I, tau = |F_s| / A + |M_t| R_b / J.
///   The bond breaks irreversibly in the step in which sigma > sigma_c or tau > tau_c (P&C §2.2);
///   its force is then not applied and its stored elastic energy
///     E_b = F_n^2 / (2 k_n A) + |F_s|^2 / (2 k_s A) + M_t^2 / (2 k_s J) + |M_b|^2 / (2 k_n I)
///   is added to the released-energy account (Diagnostics::bond_released), not lost silently:
///   each bond keeps the energy it released, and the account is their exact sum (common/exact_sum.hpp),
///   so it does not depend on the order in which bonds broke or on which MPI rank holds them.
/// Contacts act in parallel with bonds (as in P&C's parallel bond: the bond adds to the contact).
/// Bonds are stored by sphere ids (BondSet): indices are resolved once per Simulation, so they
/// survive reordering, checkpoints and restarts (bit-identical).
/// Time step: the stiffest bond's modes must be resolved like a contact (dt_rule.hpp):
///   axial pi sqrt(mu / (k_n A)), shear pi sqrt(mu / (k_s A)), bending pi sqrt(I_r / (k_n I)),
///   twist pi sqrt(I_r / (k_s J)); mu = reduced mass, I_r = reduced moment of inertia of the two
///   spheres; check_bond_dt refuses a dt with fewer than time.min_steps_per_contact steps
///   (InputError naming bonds.kn / bonds.ks, exit 2).
/// Equivalent beam of a straight chain of spheres of spacing L0 (test_nbody_bonds): Young's
/// modulus E = k_n L0, shear modulus G = k_s L0, cross-section A, I of the bond, mass per
/// length m / L0 (each bond is a beam segment of length L0 with axial stiffness E A / L0 = k_n A
/// and bending stiffness E I / L0 = k_n I).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/exact_sum.hpp"
#include "ssdem/spheres.hpp"

namespace ssdem {

/// Bond list keyed by sphere ids (structure of arrays), with the bond state.
struct BondSet {
  std::vector<std::uint64_t> id_a, id_b;
  std::vector<double> kn, ks;           ///< stiffness per unit area [N/m^3]
  std::vector<double> sigma_c, tau_c;   ///< tensile and shear strength [Pa]
  std::vector<double> radius, length0;  ///< bond radius R_b, length at rest [m]
  std::vector<std::uint8_t> broken;     ///< 1 once broken (irreversible)
  std::vector<Vec3> Fs, Mb, n_old;      ///< shear force [N], bending moment [N m], last normal
  std::vector<double> Mt;               ///< twisting moment [N m]
  std::vector<double> released;         ///< stored energy the bond released when it broke [J] (0: intact)
  /// Released energy not held per bond [J]: that of a checkpoint written before bonds kept their own.
  double released_base = 0.0;
  std::size_t size() const { return id_a.size(); }
  bool empty() const { return id_a.empty(); }
  /// Append an intact bond at rest.
  void add(std::uint64_t a, std::uint64_t b, double kn_, double ks_, double sc, double tc, double rb,
           double L0, const Vec3& n0);
  /// Append bond k of `o` with its state.
  void append(const BondSet& o, std::size_t k);
  std::size_t broken_count() const;
  /// Stored energy of the bonds broken so far [J]: released_base + the exact sum of `released`.
  double released_total() const;
  /// f(array of s, ...) for every per-bond array, of one or more sets side by side.
  template <class F, class... S>
  static void zip_arrays(F&& f, S&... s) {
    f(s.id_a...), f(s.id_b...), f(s.kn...), f(s.ks...), f(s.sigma_c...), f(s.tau_c...), f(s.radius...);
    f(s.length0...), f(s.broken...), f(s.Fs...), f(s.Mb...), f(s.n_old...), f(s.Mt...), f(s.released...);
  }
};

/// Parameters of generated bonds (scene keys bonds.*).
struct BondParams {
  double kn = 0.0, ks = 0.0;          ///< [N/m^3]
  double sigma_c = 0.0, tau_c = 0.0;  ///< [Pa]
  double radius_ratio = 1.0;          ///< R_b / min(s_a, s_b)
  double gap = 0.01;                  ///< bond pairs whose gap is below gap * min(s_a, s_b)
};

/// Bonds between every pair of spheres closer than s_a + s_b + gap min(s_a, s_b) (a bonded body).
BondSet generate_bonds(const Spheres& sp, const BondParams& p);

/// Shortest mode period / 2 of any intact bond (the "contact time" of the dt rule); INFINITY if none.
double shortest_bond_time(const BondSet& b, const Spheres& sp);
/// InputError naming bonds.kn / bonds.ks if dt resolves the stiffest bond with fewer than
/// min_steps steps.
void check_bond_dt(const BondSet& b, const Spheres& sp, double dt, double min_steps);

class BondSystem {
 public:
  /// Resolve the ids of `b` against the spheres (InputError naming the id if one is unknown).
  BondSystem(BondSet b, const Spheres& sp);
  /// Add the bond forces and torques to F and T (each sphere's terms in bond order, whatever the
  /// thread count: deterministic); break the bonds whose stress exceeds their strength. h: step;
  /// sp.v / sp.w half-step.
  void compute(const Spheres& sp, double h, std::vector<Vec3>& F, std::vector<Vec3>& T);
  /// Multi-rate steps (multirate.hpp): the same for the bonds whose two spheres are both
  /// synchronised (sync[i] != 0), each with the step of its spheres, (step - topen[a]) dt; in bond
  /// order. std::logic_error if an intact bond has only one synchronised sphere (the level rule
  /// keeps both ends of every intact bond on one level).
  void compute_synchronised(const Spheres& sp, const std::vector<std::uint8_t>& sync,
                            const std::vector<std::int64_t>& topen, std::int64_t step, double dt,
                            std::vector<Vec3>& F, std::vector<Vec3>& T);
  /// Elastic energy stored in the intact bonds [J] (an exact sum: independent of the bond order).
  double elastic_energy(const Spheres& sp) const { return elastic_sum(sp, nullptr).value(); }
  /// The exact sum of the intact bonds' elastic energies; only bonds k with keep[k] != 0 if keep is
  /// given (an MPI rank's own bonds).
  common::ExactSum elastic_sum(const Spheres& sp, const std::vector<std::uint8_t>* keep) const;
  /// Elastic energy stored in bond k [J] (0 once broken).
  double energy(std::size_t k, const Spheres& sp) const;
  /// Shortest mode half-period of bond k [s] (the dt rule's bond time; INFINITY if kn = ks = 0).
  double mode_time(std::size_t k, const Spheres& sp) const;
  /// Sphere indices of the bonds' ends (resolved from the ids).
  const std::vector<std::uint32_t>& index_a() const { return ia_; }
  const std::vector<std::uint32_t>& index_b() const { return ib_; }
  /// Number of bonds broken by this BondSystem so far (changes when a bond breaks).
  std::size_t breaks() const { return breaks_; }
  const BondSet& bonds() const { return b_; }
  std::size_t broken_count() const { return b_.broken_count(); }
  double released_energy() const { return b_.released_total(); }
  double bytes_per_sphere(std::size_t n) const;

 private:
  BondSet b_;
  std::vector<std::uint32_t> ia_, ib_;
  std::vector<std::uint32_t> live_;  ///< intact bonds, ascending (rebuilt after a break)
  std::size_t breaks_ = 0, live_at_ = SIZE_MAX;  ///< breaks so far; breaks_ when live_ was built
  void refresh_live();
  /// Bond k's increments over h and its breakage; its force on a and torques on a and b (the
  /// force on b is -f). False if the bond broke now (nothing to apply).
  bool evaluate(std::size_t k, const Spheres& sp, double h, Vec3& f, Vec3& ta, Vec3& tb);
  void compute_one(std::size_t k, const Spheres& sp, double h, std::vector<Vec3>& F, std::vector<Vec3>& T);
  // Parallel evaluation (at least kParallelBonds intact bonds and more than one thread): every
  // bond evaluated on its own into bf_/bta_/btb_ (bon_: applied), then each sphere adds its
  // bonds' terms in ascending bond order from the index srow_/sadj_ (2 k + 1 for end b): the
  // additions of the serial loop, in its order, so the bits do not depend on the thread count.
  static constexpr std::size_t kParallelBonds = 2048;
  std::vector<Vec3> bf_, bta_, btb_;
  std::vector<std::uint8_t> bon_;
  std::vector<std::uint32_t> srow_, sadj_;
  bool parallel(std::size_t n);  ///< take the parallel path (and size its arrays for n spheres)
  void gather(std::size_t n, const std::uint8_t* only, std::vector<Vec3>& F, std::vector<Vec3>& T) const;
};

}  // namespace ssdem
