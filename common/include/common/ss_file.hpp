/// @file ss_file.hpp
/// pkdgrav `.ss` files, written by mpm2spheres (`export.ss`) and read by ssdem-grav
/// (`initial.source = "ss"`). Format facts from pkdgrav's ssio.h (ecosystem.md §1.4): Sun XDR,
/// i.e. big-endian, no padding.
///
///   header (16 B):           float64 time, int32 n_data, int32 magic (-1 standard; 0 accepted
///                            as standard from old writers; other values, e.g. the reduced
///                            format, are refused)
///   standard record (96 B):  float64 mass, radius, pos[3], vel[3], spin[3]; int32 color, org_idx
///
/// Units. Values are in pkdgrav system units unless SI is chosen (`SsUnitSystem::si`): G = 1,
/// length 1 AU = 1.495978707e11 m (IAU 2012), mass 1 M_sun = 1.98847e30 kg (IAU 2015 nominal
/// GM_sun / CODATA 2018 G = 6.67430e-11), time sqrt(AU^3 / (G M_sun)) = 5.0226e6 s, i.e. one year
/// / (2 pi); velocities in AU per time unit (29.78 km/s), spins in rad per time unit. The reader
/// multiplies each value by its SI unit (no other conversion). A pkdgrav run in G = 1 units thus
/// corresponds to SI with G = 6.67430e-11 m^3/(kg s^2).
///
/// Ids. The writer stores sphere ids as org_idx (they must fit an int32); the reader takes ids from
/// org_idx and refuses negative ones (aggregate members, not supported) and duplicates. `color` is
/// written for every record and ignored on reading; so is the header time by ssdem-grav.
#pragma once
#include <array>
#include <string>

#include "common/choice.hpp"
#include "common/sphere_file.hpp"

namespace common {

/// Units of a .ss file (keys `export.ss_units` of mpm2spheres, `initial.ss_units` of ssdem-grav).
enum class SsUnitSystem { pkdgrav, si };
inline constexpr std::array kSsUnitSystems{Choice{"pkdgrav", SsUnitSystem::pkdgrav}, Choice{"si", SsUnitSystem::si}};

/// SI values of the unit of length, mass and time used in a .ss file.
struct SsUnits {
  double length = 1.0;  ///< m
  double mass = 1.0;    ///< kg
  double time = 1.0;    ///< s
  std::string name = "si";
  /// pkdgrav system units: 1 AU = 1.495978707e11 m (IAU 2012), 1 M_sun = 1.98847e30 kg
  /// (IAU 2015 nominal GM_sun / CODATA 2018 G), time = sqrt(AU^3 / (G M_sun)) so that G = 1.
  static SsUnits pkdgrav();
  static SsUnits si() { return {}; }
  /// The units of a unit-system choice.
  static SsUnits of(SsUnitSystem u) { return u == SsUnitSystem::si ? si() : pkdgrav(); }
};

/// Write atomically; ids become org_idx (must fit int32), `color` for every record; a JSON
/// companion `<path>.json` records the units.
void write_ss(const std::string& path, const SphereSet& s, const SsUnits& units, int color = 3);

/// Read and validate (size, magic, finite values, positive mass and radius, non-negative and
/// unique org_idx); converts to SI. Throws InputError naming the file and the record. Physical
/// bounds (common/finite.hpp check_input_spheres) are the caller's, as for sphere files.
SphereSet read_ss(const std::string& path, const SsUnits& units);

}  // namespace common
