/// @file body_drive.cpp
/// Relaxation body force of velocity-driven bodies (equations in body_drive.hpp).
#include "mpm/body_drive.hpp"

#include <algorithm>

namespace mpmfrag {

BodyForce make_drive_force(std::vector<BodyDrive> drives) {
  if (drives.empty()) return {};
  return [drives = std::move(drives)](std::size_t b, std::size_t e, double t, const ParticleSet& P, double* a) {
    for (std::size_t q = b; q < e; ++q) {
      double* aq = a + 3 * (q - b);
      aq[0] = aq[1] = aq[2] = 0.0;
      const std::uint64_t id = P.id[q];
      for (const BodyDrive& d : drives) {
        if (id < d.id_begin || id >= d.id_end) continue;
        const bool ramping = d.ramp_time > 0.0 && t < d.ramp_time;
        const double f = ramping ? t / d.ramp_time : 1.0;
        for (int k = 0; k < 3; ++k)
          aq[k] = (f * d.velocity[k] - P.v[3 * q + k]) / d.relaxation_time + (ramping ? d.velocity[k] / d.ramp_time : 0.0);
        break;
      }
    }
  };
}

}  // namespace mpmfrag
