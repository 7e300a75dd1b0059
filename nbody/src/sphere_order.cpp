/// @file sphere_order.cpp
/// Renumbering of the spheres by cells and the storage-to-file map (sphere_order.hpp).
#include "ssdem/sphere_order.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "common/status.hpp"

namespace ssdem {
namespace {
template <class T>
void gather(std::vector<T>& a, const std::vector<std::uint32_t>& perm, std::size_t width = 1) {
  if (a.empty()) return;
  std::vector<T> out(a.size());
  for (std::size_t k = 0; k < perm.size(); ++k)
    std::copy_n(a.begin() + static_cast<std::ptrdiff_t>(width * perm[k]), width,
                out.begin() + static_cast<std::ptrdiff_t>(width * k));
  a.swap(out);
}

std::vector<std::uint32_t> inverse(const std::vector<std::uint32_t>& perm) {
  std::vector<std::uint32_t> inv(perm.size());
  for (std::size_t k = 0; k < perm.size(); ++k) inv[perm[k]] = static_cast<std::uint32_t>(k);
  return inv;
}
}  // namespace

std::vector<std::uint32_t> cell_order(const std::vector<Vec3>& x, double cell) {
  const std::size_t n = x.size();
  Vec3 lo = Vec3::Constant(INFINITY);
  for (const Vec3& p : x)
    if (p.allFinite()) lo = lo.cwiseMin(p);
  const double inv = cell > 0.0 && std::isfinite(cell) ? 1.0 / cell : 0.0;
  constexpr double kMax = 2097151.0;  // 2^21 - 1 cells per axis: 63 bits of key
  std::vector<std::uint64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t q[3] = {0, 0, 0};
    if (x[i].allFinite())
      for (int d = 0; d < 3; ++d) q[d] = static_cast<std::uint64_t>(std::clamp((x[i][d] - lo[d]) * inv, 0.0, kMax));
    key[i] = (q[2] << 42) | (q[1] << 21) | q[0];
  }
  std::vector<std::uint32_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0u);
  std::stable_sort(perm.begin(), perm.end(), [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  return perm;
}

std::vector<std::uint32_t> cell_order(const Spheres& sp) {
  double smax = 0.0;
  for (double s : sp.s) smax = std::max(smax, s);
  return cell_order(sp.x, 2.0 * smax);
}

bool is_permutation_of(const std::vector<std::uint32_t>& perm, std::size_t n) {
  if (perm.size() != n) return false;
  std::vector<char> seen(n, 0);
  for (std::uint32_t k : perm) {
    if (k >= n || seen[k]) return false;
    seen[k] = 1;
  }
  return true;
}

void permute_spheres(Spheres& sp, const std::vector<std::uint32_t>& perm) {
  sp.for_each_array([&](const common::SphereArray&, auto& a) { gather(a, perm); });
  for (common::Field& f : sp.carried) gather(f.values, perm, f.ncomp);
}

void permute_state(SimState& st, const std::vector<std::uint32_t>& perm) {
  permute_spheres(st.sp, perm);
  for (std::vector<Vec3>* a : {&st.a, &st.alpha, &st.ag, &st.a_prev, &st.alpha_prev}) gather(*a, perm);
  gather(st.level, perm);
  gather(st.tau_prev, perm);
  gather(st.sphere_order, perm);
}

SphereOrder::SphereOrder(std::size_t n) : row_(n) { std::iota(row_.begin(), row_.end(), 0u); }

void SphereOrder::renumber(const std::vector<std::uint32_t>& perm) {
  gather(row_, perm);
  identity_ = true;
  for (std::size_t k = 0; k < row_.size() && identity_; ++k) identity_ = row_[k] == k;
}

Spheres SphereOrder::to_file(const Spheres& sp) const {
  Spheres out = sp;
  if (!identity_) permute_spheres(out, inverse(row_));
  return out;
}

SimState SphereOrder::to_file(SimState st) const {
  st.sphere_order.clear();
  if (identity_) return st;
  permute_state(st, inverse(row_));
  st.sphere_order = row_;
  return st;
}

SphereOrder SphereOrder::from_file(SimState& st, const std::string& path) {
  SphereOrder o(st.sp.size());
  if (st.sphere_order.empty()) return o;
  if (!is_permutation_of(st.sphere_order, st.sp.size()))
    throw common::InputError(path + ": /ssdem_state/sphere_order must hold each sphere row 0 .. " +
                             std::to_string(st.sp.size()) + " - 1 once");
  const std::vector<std::uint32_t> rows = std::move(st.sphere_order);
  st.sphere_order.clear();
  permute_state(st, rows);  // storage index k takes file row rows[k]
  o.renumber(rows);
  return o;
}

}  // namespace ssdem
