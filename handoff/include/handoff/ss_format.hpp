/// @file ss_format.hpp
/// pkdgrav `.ss` files (ecosystem.md §1.4, format facts from pkdgrav's ssio.h): Sun XDR, i.e.
/// big-endian, no padding. Header (16 B): float64 time, int32 n_data, int32 magic (-1 standard;
/// 0 accepted as standard from old writers). Standard record (96 B): float64 mass, radius,
/// pos[3], vel[3], spin[3]; int32 color, org_idx. Values are in pkdgrav system units
/// (G = 1; length 1 AU, mass 1 M_sun, time derived from G) unless SI is chosen.
#pragma once
#include <string>

#include "common/sphere_file.hpp"

namespace handoff {

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
};

/// Write atomically; ids become org_idx (must fit int32), `color` for every record; a JSON
/// companion `<path>.json` records the units.
void write_ss(const std::string& path, const common::SphereSet& s, const SsUnits& units, int color = 3);

/// Read and validate (size, magic, finite values, positive mass and radius); converts to SI.
/// Throws common::InputError naming the file and record.
common::SphereSet read_ss(const std::string& path, const SsUnits& units);

}  // namespace handoff
