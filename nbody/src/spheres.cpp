// SoA sphere storage (spheres.hpp).
#include "ssdem/spheres.hpp"

namespace ssdem {

void Spheres::resize(std::size_t n) {
  id.resize(n, 0);
  x.resize(n, Vec3::Zero());
  v.resize(n, Vec3::Zero());
  w.resize(n, Vec3::Zero());
  m.resize(n, 0.0);
  s.resize(n, 0.0);
}

void Spheres::push(std::uint64_t id_, const Vec3& x_, const Vec3& v_, const Vec3& w_, double m_,
                   double s_) {
  id.push_back(id_);
  x.push_back(x_);
  v.push_back(v_);
  w.push_back(w_);
  m.push_back(m_);
  s.push_back(s_);
}

}  // namespace ssdem
