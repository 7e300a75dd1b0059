/// @file spheres.cpp
/// SoA sphere storage (spheres.hpp): every operation goes through Spheres::zip_arrays.
#include "ssdem/spheres.hpp"

namespace ssdem {

bool Spheres::consistent() const {
  bool ok = true;
  for_each_array([&](const common::SphereArray&, const auto& a) { ok = ok && a.size() == size(); });
  return ok;
}

void Spheres::resize(std::size_t n) {
  for_each_array([&](const common::SphereArray&, auto& a) {
    a.resize(n, zero<typename std::decay_t<decltype(a)>::value_type>());
  });
}

void Spheres::push(std::uint64_t id_, const Vec3& x_, const Vec3& v_, const Vec3& w_, double m_,
                   double s_) {
  const std::size_t i = size();
  resize(i + 1);
  id[i] = id_;
  x[i] = x_;
  v[i] = v_;
  w[i] = w_;
  m[i] = m_;
  s[i] = s_;
}

void Spheres::append(const Spheres& o) {
  zip_arrays([](const common::SphereArray&, auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); },
             *this, o);
}

}  // namespace ssdem
