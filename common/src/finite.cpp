/// @file finite.cpp
/// Input bounds and output finiteness checks (finite.hpp).
#include "common/finite.hpp"

#include <cmath>
#include <sstream>

#include "common/particle_file.hpp"
#include "common/sphere_file.hpp"
#include "common/status.hpp"

namespace common {
namespace {
std::string num(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

// Every component finite and |value| <= hi (per component, or the norm of each row of `width`).
void check_range(const std::vector<double>& v, std::size_t width, bool norm, double lo, double hi,
                 const std::string& file, const std::string& dataset, const std::string& unit, std::size_t row0 = 0) {
  const std::size_t rows = width ? v.size() / width : 0;
  for (std::size_t i = 0; i < rows; ++i) {
    double m = 0;  // the magnitude, without overflow (std::hypot)
    for (std::size_t k = 0; k < width; ++k) {
      const double x = v[i * width + k];
      if (!std::isfinite(x))
        throw InputError(file, dataset, "value " + num(x) + " at index " + std::to_string(row0 + i) + " is not finite");
      if (!norm && !(x >= lo && x <= hi))
        throw InputError(file, dataset,
                         "value " + num(x) + " " + unit + " at index " + std::to_string(row0 + i) + " is outside the allowed range [" +
                             num(lo) + ", " + num(hi) + "] " + unit);
      m = std::hypot(m, x);
    }
    if (norm && m > hi)
      throw InputError(file, dataset,
                       "magnitude " + num(m) + " " + unit + " at index " + std::to_string(row0 + i) +
                           " exceeds the allowed maximum " + num(hi) + " " + unit);
  }
}
}  // namespace

void check_input_particles(const ParticleSnapshot& s, const std::string& file) {
  using namespace bounds;
  check_range(s.position, 3, false, -kMaxLength, kMaxLength, file, "/particles/position", "m");
  check_range(s.velocity, 3, true, 0, kMaxSpeed, file, "/particles/velocity", "m/s");
  check_range(s.mass, 1, false, 0, kMaxMass, file, "/particles/mass", "kg");
  check_range(s.volume, 1, false, 0, kMaxLength * kMaxLength * kMaxLength, file, "/particles/volume", "m^3");
  check_range(s.size, 3, false, 0, kMaxLength, file, "/particles/size", "m");
}

void check_input_spheres(const SphereSet& s, const std::string& file, const std::string& group, std::size_t row0) {
  using namespace bounds;
  check_range(s.position, 3, false, -kMaxLength, kMaxLength, file, group + "position", "m", row0);
  check_range(s.velocity, 3, true, 0, kMaxSpeed, file, group + "velocity", "m/s", row0);
  check_range(s.spin, 3, true, 0, kMaxAngularVelocity, file, group + "spin", "rad/s", row0);
  check_range(s.mass, 1, false, 0, kMaxMass, file, group + "mass", "kg", row0);
  check_range(s.radius, 1, false, 0, kMaxLength, file, group + "radius", "m", row0);
}

void require_finite(const double* data, std::size_t n, const std::string& what, const std::string& name) {
  const std::size_t i = first_non_finite(data, n);
  if (i < n)
    throw NumericalError(what + ": " + name + "[" + std::to_string(i) + "] = " + num(data[i]) +
                         " is not finite; not written");
}

namespace {
void require_finite_vec(const std::vector<double>& v, const std::string& path, const std::string& name) {
  common::require_finite(v.data(), v.size(), path, name);
}
double kinetic(const std::vector<double>& m, const std::vector<double>& v) {
  double e = 0;
  for (std::size_t i = 0; i < m.size() && 3 * i + 2 < v.size(); ++i)
    e += 0.5 * m[i] * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
  return e;
}
}  // namespace

void check_output_particles(const ParticleSnapshot& s, const std::string& path) {
  require_finite_vec(s.position, path, "position");
  require_finite_vec(s.velocity, path, "velocity");
  require_finite_vec(s.mass, path, "mass");
  require_finite_vec(s.volume, path, "volume");
  const double k = kinetic(s.mass, s.velocity);
  if (!std::isfinite(k)) throw NumericalError(path + ": kinetic energy " + num(k) + " J is not finite; not written");
}

void check_output_spheres(const SphereSet& s, const std::string& path) {
  require_finite_vec(s.position, path, "position");
  require_finite_vec(s.velocity, path, "velocity");
  require_finite_vec(s.spin, path, "spin");
  require_finite_vec(s.mass, path, "mass");
  require_finite_vec(s.radius, path, "radius");
  double k = kinetic(s.mass, s.velocity);
  for (std::size_t i = 0; i < s.mass.size() && i < s.radius.size() && 3 * i + 2 < s.spin.size(); ++i) {
    const double* w = &s.spin[3 * i];
    k += 0.2 * s.mass[i] * s.radius[i] * s.radius[i] * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  }
  if (!std::isfinite(k))
    throw NumericalError(path + ": kinetic + rotational energy " + num(k) + " J is not finite; not written");
}

}  // namespace common
