/// @file contact_params.hpp
/// Resolved soft-sphere contact parameters (composed from the parts of contact/table.hpp) and the
/// registry of contact parts chosen by name in `contact.parts`.
///
/// The parts and their equations are in nbody/include/ssdem/contact/<part>.hpp:
///   normal (linear spring, S12 eq. 3) | hertz (Hertz-Mindlin, Johnson 1985; Tsuji et al. 1992)
///   damping (S12 eqs 13, 15-16), tangential (S12 eqs 6-7, 14, 17-19),
///   rolling and twisting (Zhang et al. 2017, spring-dashpot-slider), cohesion (sigma_c over
///   the contact area pi (beta Rbar)^2, spheres and walls)
/// (S12 = Schwartz, Richardson & Michel 2012, Granular Matter 14:363). Every part declares its
/// parameters as a common::Schema under `contact.<part>.`; a part that is not listed in
/// `contact.parts` costs nothing (one pair kernel is compiled per valid set of parts).
/// Exactly one normal law ("normal" or "hertz") must be listed.
#pragma once
#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "common/schema.hpp"
#include "ssdem/contact/table.hpp"

namespace ssdem {

/// Resolved parameters of the contact law (SI): every part's Params, the enabled set, beta.
struct ContactParams : TableInfo::Params {
  unsigned parts = 0;  ///< OR of the parts' flags (the linear normal law has none)
  double beta = 0.5;   ///< shape parameter of the rolling/twisting contact size a = beta Rbar
  bool resolve_edges = true;  ///< edge impulses at contact onset and release (contact_law.hpp)

  bool has(unsigned flag) const { return (parts & flag) != 0u; }
  double kt() const { return kt_over_kn * kn; }
  /// C_n / sqrt(mu) of the linear law: damping prefactor (0 when the damping part is off).
  double cn_pre() const { return (parts & kPartDamping) ? damping_prefactor(kn, en) : 0.0; }
  /// C_t / sqrt(mu) of the linear law.
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
  /// Contact duration of a pair of reduced mass mu and reduced radius Rbar. Linear law:
  /// pi sqrt(mu / (k_n (1 - xi^2))) (Rbar unused); Hertz: the undamped Hertz time at the impact
  /// speed vmax (normal_hertz.hpp).
  double contact_time(double mu, double Rbar = 0.0) const;
};

/// One registered contact part.
struct ContactPartInfo {
  std::string name;
  unsigned flag = 0;  ///< 0 for the default normal law
  unsigned requires_parts = 0;
  PartSlot slot = PartSlot::additive;
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

/// Register every part of the table (contact/table.hpp).
void register_builtin_contact_parts(ContactPartRegistry& reg);

/// Gravel-like parameter set (ssdem.md §1.8, Spheral DEM test defaults citing Zhang et al.):
/// e_n = e_t = 0.55, mu_s = 1.0, mu_r = 1.05, mu_t = 1.3, beta = 0.5, k_t = (2/7) k_n, all
/// parts on. k_n is left to the caller (dt rule). Reliability: [V] for the Spheral defaults,
/// [R] for the published table (validation-data.md §6 gives Zhang 2017 as 1.0/1.0/1.0/1.0).
ContactParams gravel_preset(double kn);

}  // namespace ssdem
