/// @file ss_file.cpp
/// Implementation of common/ss_file.hpp (the header states the contract, and for physics the equations and sources).
#include "common/ss_file.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/status.hpp"
#include "item_file.hpp"

namespace common {

namespace {

void put_u64(std::string& b, std::uint64_t v) {
  for (int i = 7; i >= 0; --i) b.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void put_f64(std::string& b, double x) { put_u64(b, std::bit_cast<std::uint64_t>(x)); }
void put_i32(std::string& b, std::int32_t x) {
  const auto v = static_cast<std::uint32_t>(x);
  for (int i = 3; i >= 0; --i) b.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
std::uint64_t get_u64(const unsigned char* p) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return v;
}
double get_f64(const unsigned char* p) { return std::bit_cast<double>(get_u64(p)); }
std::int32_t get_i32(const unsigned char* p) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v = (v << 8) | p[i];
  return static_cast<std::int32_t>(v);
}

constexpr std::size_t kHeader = 16, kRecord = 96;

}  // namespace

SsUnits SsUnits::pkdgrav() {
  SsUnits u;
  u.name = "pkdgrav";
  u.length = 1.495978707e11;
  u.mass = 1.98847e30;
  const double G = 6.67430e-11;
  u.time = std::sqrt(u.length * u.length * u.length / (G * u.mass));
  return u;
}

void write_ss(const std::string& path, const SphereSet& s, const SsUnits& u, int color) {
  const std::size_t n = s.count();
  if (n > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw InputError(path, "n_data", ".ss files hold at most 2^31-1 spheres");
  const double vel = u.length / u.time, spin = 1.0 / u.time;
  std::string b;
  b.reserve(kHeader + kRecord * n);
  put_f64(b, s.time / u.time);
  put_i32(b, static_cast<std::int32_t>(n));
  put_i32(b, -1);
  for (std::size_t i = 0; i < n; ++i) {
    if (s.id[i] > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()))
      throw InputError(path, "org_idx", "sphere id " + std::to_string(s.id[i]) + " does not fit an int32");
    put_f64(b, s.mass[i] / u.mass);
    put_f64(b, s.radius[i] / u.length);
    for (int d = 0; d < 3; ++d) put_f64(b, s.position[3 * i + d] / u.length);
    for (int d = 0; d < 3; ++d) put_f64(b, s.velocity[3 * i + d] / vel);
    for (int d = 0; d < 3; ++d) put_f64(b, s.spin[3 * i + d] / spin);
    put_i32(b, color);
    put_i32(b, static_cast<std::int32_t>(s.id[i]));
  }
  write_text_atomic(path, b);
  std::ostringstream j;
  j.precision(17);
  j << "{\n  \"format\": \"pkdgrav ss (XDR, standard records)\",\n  \"units\": \"" << u.name
    << "\",\n  \"length_unit_m\": " << u.length << ",\n  \"mass_unit_kg\": " << u.mass
    << ",\n  \"time_unit_s\": " << u.time << ",\n  \"count\": " << n << ",\n  \"color\": " << color << "\n}\n";
  write_text_atomic(path + ".json", j.str());
}

SphereSet read_ss(const std::string& path, const SsUnits& u) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open .ss file");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (data.size() < kHeader) throw InputError(path, "header", "file shorter than the 16-byte header");
  const auto* p = reinterpret_cast<const unsigned char*>(data.data());
  const double time = get_f64(p);
  const std::int32_t n = get_i32(p + 8), magic = get_i32(p + 12);
  if (magic != -1 && magic != 0)
    throw InputError(path, "header", "magic number " + std::to_string(magic) +
                                         " is not a standard .ss file (-1); reduced files are not supported");
  if (n < 0) throw InputError(path, "header", "negative particle count");
  if (data.size() != kHeader + kRecord * static_cast<std::size_t>(n))
    throw InputError(path, "", "size " + std::to_string(data.size()) + " B does not match " +
                                   std::to_string(n) + " standard records (expected " +
                                   std::to_string(kHeader + kRecord * static_cast<std::size_t>(n)) + " B)");
  if (!std::isfinite(time)) throw InputError(path, "header", "non-finite time");
  const double vel = u.length / u.time, spin = 1.0 / u.time;
  SphereSet s;
  s.time = time * u.time;
  s.resize(static_cast<std::size_t>(n));
  for (std::int32_t i = 0; i < n; ++i) {
    const unsigned char* r = p + kHeader + kRecord * static_cast<std::size_t>(i);
    double v[11];
    for (int k = 0; k < 11; ++k) {
      v[k] = get_f64(r + 8 * k);
      if (!std::isfinite(v[k])) throw InputError(path, "record " + std::to_string(i), "non-finite value");
    }
    if (!(v[0] > 0) || !(v[1] > 0)) throw InputError(path, "record " + std::to_string(i), "mass and radius must be > 0");
    const std::int32_t org = get_i32(r + 92);
    if (org < 0) throw InputError(path, "record " + std::to_string(i), "negative org_idx (aggregate member) is not supported");
    s.id[i] = static_cast<std::uint64_t>(org);
    s.mass[i] = v[0] * u.mass;
    s.radius[i] = v[1] * u.length;
    for (int d = 0; d < 3; ++d) {
      s.position[3 * i + d] = v[2 + d] * u.length;
      s.velocity[3 * i + d] = v[5 + d] * vel;
      s.spin[3 * i + d] = v[8 + d] * spin;
    }
  }
  detail::check_unique_ids(path, "org_idx", s.id);
  return s;
}

}  // namespace common
