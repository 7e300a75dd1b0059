/// @file drift_schedule.cpp
/// The per-sphere schedule of re-insertion tests in multi-rate steps (drift_schedule.hpp).
#include "ssdem/drift_schedule.hpp"

#include <cmath>

namespace ssdem {

bool DriftSchedule::open(std::size_t n, const std::uint32_t* kicked, std::size_t nkicked, const std::uint8_t* level,
                         std::vector<std::uint32_t>& out) {
  ++now_;
  if (ring_.size() != static_cast<std::size_t>(ring_len_)) ring_.resize(static_cast<std::size_t>(ring_len_));
  auto& bucket = ring_[static_cast<std::size_t>(now_ % ring_len_)];
  if (kicked) {
    kicked_sum_ += static_cast<std::int64_t>(nkicked);
    ++calls_;
  } else {  // a block opens: planned if the last one kicked fewer than 1/32 of the spheres per call
    planning_ = calls_ > 0 && 32 * kicked_sum_ < calls_ * static_cast<std::int64_t>(n);
    kicked_sum_ = calls_ = 0;
  }
  if (!planning_) {
    valid_ = false;
    return true;
  }
  if (!valid_ || !kicked || due_.size() != n) {
    valid_ = false;
    due_.assign(n, -1);
    until_.resize(n);
    for (std::size_t i = 0; i < n; ++i) until_[i] = now_ + (std::int64_t{1} << level[i]);
    for (auto& b : ring_) b.clear();
    return true;
  }
  for (std::size_t r = 0; r < nkicked; ++r) {
    const std::uint32_t i = kicked[r];
    until_[i] = now_ + (std::int64_t{1} << level[i]);
    due_[i] = -1;  // taken (an entry for now is skipped below)
    out.push_back(i);
  }
  for (std::uint32_t i : bucket)
    if (due_[i] == now_) {
      due_[i] = -1;
      out.push_back(i);
    }
  bucket.clear();
  return false;
}

std::int64_t DriftSchedule::wait(const Vec3& x, const Vec3& xr, const Vec3& u, double D, std::int64_t horizon) const {
  const std::int64_t H = horizon < ring_len_ ? horizon : ring_len_;
  if (H <= 0) return 1;
  const double um = u.cwiseAbs().maxCoeff();
  const double scale = x.cwiseAbs().maxCoeff() + xr.cwiseAbs().maxCoeff() + (static_cast<double>(H) + 2.0) * um;
  const double Dp = D - (4.0 * static_cast<double>(H) * 0x1p-52 * scale + 1e-12 * D);
  if (!(Dp > 0.0)) return 1;
  const Vec3 d = x - xr;
  const double c = d.squaredNorm() - Dp * Dp;
  if (!(c < 0.0)) return 1;  // already at D' (or not finite): test at every call
  // inside D' at both ends of the H calls, so inside throughout (convex): no root needed
  if ((d + static_cast<double>(H) * u).squaredNorm() < Dp * Dp) return horizon + 1;
  const double a = u.squaredNorm(), b = 2.0 * d.dot(u);
  const double sq = std::sqrt(b * b - 4.0 * a * c);  // > |b|, as c < 0
  // the larger root, without cancellation: (-b + sq) / (2 a) = 2 c / (-b - sq)
  const double root = b >= 0.0 ? (2.0 * c) / (-b - sq) : (-b + sq) / (2.0 * a);
  if (!(root >= 1.0)) return 1;
  if (root > static_cast<double>(H)) return horizon + 1;
  return static_cast<std::int64_t>(root);  // floor: at most one call before the first that may fire
}

void DriftSchedule::enter(std::uint32_t i, std::int64_t m) {
  const std::int64_t h = horizon(i);
  if (h < 0) {
    m = 1;  // its kick was due and not named: tested at every call until it is
  } else if (m > h) {
    if (h < ring_len_) {  // kicked before it can fire: tested then
      due_[i] = -1;
      return;
    }
    m = ring_len_ - 1;  // renewed then
  }
  if (m > ring_len_ - 1) m = ring_len_ - 1;
  due_[i] = now_ + m;
  ring_[static_cast<std::size_t>(due_[i] % ring_len_)].push_back(i);
}

double DriftSchedule::bytes_per_sphere(std::size_t n) const {
  if (n == 0) return 0.0;
  std::size_t entries = 0;
  for (const auto& b : ring_) entries += b.capacity();
  const double per = 8.0 * static_cast<double>(due_.capacity() + until_.capacity()) + 4.0 * static_cast<double>(entries);
  return per / static_cast<double>(n);
}

}  // namespace ssdem
