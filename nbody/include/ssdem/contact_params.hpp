/// @file contact_params.hpp
/// Soft-sphere contact parameters and the registry of contact *parts* (styles chosen by name).
///
/// Parts (Schwartz, Richardson & Michel 2012, Granular Matter 14:363 = "S12"; Zhang et al. 2017,
/// Icarus 294:98 = "Z17", after Jiang, Shen & Wang 2015):
///   normal      F_N = -k_n x n                                     (S12 eq. 3)
///   damping     + C_n u_n,  C_n = 2|ln e_n| sqrt(k_n mu / (pi^2 + ln^2 e_n))   (S12 eqs 13, 15-16)
///   tangential  F_T = k_t S + C_t u_t, |F_T| <= mu_s |F_N|, k_t = (2/7) k_n by default,
///               C_t from e_t with k_t in place of k_n                (S12 eqs 6-7, 14, 17-19)
///   rolling     M_r = k_r theta_r + C_r v_roll, k_r = k_n a^2, C_r = C_n a^2,
///               |M_r| <= mu_r a |F_N|, a = beta * Rbar               (Z17 §2, spring-dashpot-slider)
///   twisting    M_q = k_q theta_q + C_q v_twist, k_q = 2 k_t a^2, C_q = 2 C_t a^2,
///               |M_q| <= mu_t mu_s a |F_N|                            (Z17 §2; pkdgrav DoDEM)
/// The "normal" part is mandatory. Every part declares its parameters as a common::Schema
/// under `contact.<part>.`; a part that is not listed in `contact.parts` costs nothing: the
/// pair kernel is a template specialised on the set of enabled parts (contact_law.hpp).
/// Adding a new part (Hertz normal law, cohesion) means registering it here and adding its
/// term to the kernel.
#pragma once
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "common/schema.hpp"

namespace ssdem {

/// How a sliding contact is capped.
enum class SlipRule {
  coulomb,  ///< rescale F_T to mu_s |F_N| and set S so that k_t S + C_t u_t = F_T (strict Coulomb)
  pkdgrav   ///< pkdgrav DoDEM: zero S and apply min(mu_s |F_N|, C_t |u_t|) along u_t
};
/// Scene spellings of SlipRule (key contact.tangential.slip).
inline constexpr std::array kSlipRules{common::Choice{"coulomb", SlipRule::coulomb},
                                       common::Choice{"pkdgrav", SlipRule::pkdgrav}};

/// Enabled parts as bit flags.
enum ContactPart : unsigned {
  kPartDamping = 1u,
  kPartTangential = 2u,
  kPartRolling = 4u,
  kPartTwisting = 8u,
};

/// Resolved parameters of the contact law (SI).
struct ContactParams {
  unsigned parts = 0;       ///< OR of ContactPart flags (normal always on)
  double kn = 0.0;          ///< normal spring constant [N/m]
  double en = 1.0;          ///< normal restitution coefficient (damping part)
  double kt_over_kn = 2.0 / 7.0;
  double et = 1.0;          ///< tangential "restitution" setting C_t (tangential part)
  double mu_s = 0.0;        ///< static friction coefficient
  double mu_r = 0.0;        ///< rolling friction coefficient
  double mu_t = 0.0;        ///< twisting friction coefficient
  double beta = 0.5;        ///< shape parameter of the rolling/twisting contact size a = beta Rbar
  SlipRule slip = SlipRule::coulomb;

  double kt() const { return kt_over_kn * kn; }
  /// C_n / sqrt(mu): damping prefactor (0 when the damping part is off).
  double cn_pre() const { return (parts & kPartDamping) ? damping_prefactor(kn, en) : 0.0; }
  /// C_t / sqrt(mu).
  double ct_pre() const {
    return (parts & kPartTangential) && (parts & kPartDamping) ? damping_prefactor(kt(), et) : 0.0;
  }
  /// 2 |ln e| sqrt(k / (pi^2 + ln^2 e)) (S12 eq. 15).
  static double damping_prefactor(double k, double e) {
    if (e >= 1.0) return 0.0;
    const double le = std::log(e);
    return 2.0 * std::fabs(le) * std::sqrt(k / (M_PI * M_PI + le * le));
  }
  /// Damping ratio xi = -ln e / sqrt(pi^2 + ln^2 e).
  static double damping_ratio(double e) {
    if (e >= 1.0) return 0.0;
    const double le = std::log(e);
    return -le / std::sqrt(M_PI * M_PI + le * le);
  }
  /// Contact duration of a pair of reduced mass mu: pi sqrt(mu / (k_n (1 - xi^2))).
  double contact_time(double mu) const {
    const double xi = (parts & kPartDamping) ? damping_ratio(en) : 0.0;
    return M_PI * std::sqrt(mu / (kn * (1.0 - xi * xi)));
  }
};

/// One registered contact part.
struct ContactPartInfo {
  std::string name;
  unsigned flag = 0;  ///< 0 for the mandatory normal part
  std::string help;
  common::Schema schema;  ///< keys relative to `contact.<name>.`
  /// Read this part's values from the scene into `p`.
  std::function<void(const common::Scene&, const std::string& prefix, ContactParams& p)> read;
};

/// Explicit registry of contact parts (no static self-registration).
class ContactPartRegistry {
 public:
  /// Register a part. Throws std::invalid_argument if a part of that name is already registered.
  void add(ContactPartInfo info);
  const ContactPartInfo* find(const std::string& name) const;
  std::vector<std::string> names() const;
  /// Declare every part's keys under `contact.<part>.` plus `contact.parts` and `contact.beta`.
  void declare(common::Schema& schema) const;
  /// Parse `contact.parts` (comma-separated names) and read the enabled parts' values.
  ContactParams resolve(const common::Scene& scene) const;

 private:
  std::map<std::string, ContactPartInfo> parts_;
};

/// Register normal, damping, tangential, rolling, twisting.
void register_builtin_contact_parts(ContactPartRegistry& reg);

/// Gravel-like parameter set (ssdem.md §1.8, Spheral DEM test defaults citing Zhang et al.):
/// e_n = e_t = 0.55, mu_s = 1.0, mu_r = 1.05, mu_t = 1.3, beta = 0.5, k_t = (2/7) k_n, all
/// parts on. k_n is left to the caller (dt rule). Reliability: [V] for the Spheral defaults,
/// [R] for the published table (validation-data.md §6 gives Zhang 2017 as 1.0/1.0/1.0/1.0).
ContactParams gravel_preset(double kn);

}  // namespace ssdem
