/// @file exact_sum.cpp
/// Order-independent exact sums of doubles (exact_sum.hpp).
#include "common/exact_sum.hpp"

#include <cmath>
#include <cstring>

namespace common {
namespace {
constexpr std::uint32_t kNormaliseEvery = 1u << 20;  // digits < 2^32 each: no limb passes 2^53
constexpr std::int64_t kDigit = std::int64_t{1} << 32;
}  // namespace

void ExactSum::add(double x) {
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  const unsigned E = static_cast<unsigned>(bits >> 52) & 0x7ffu;
  if (E == 0x7ffu) {  // inf or NaN: summed apart
    special_ += x;
    has_special_ = true;
    return;
  }
  std::uint64_t m = bits & ((std::uint64_t{1} << 52) - 1);
  if (m == 0 && E == 0) return;  // ±0
  if (E != 0) m |= std::uint64_t{1} << 52;
  const unsigned p = E == 0 ? 0u : E - 1u;  // x = ±m 2^(p - 1074)
  const unsigned k = p >> 5, s = p & 31u;
  const unsigned __int128 v = static_cast<unsigned __int128>(m) << s;  // < 2^85: three digits
  const auto d0 = static_cast<std::int64_t>(static_cast<std::uint64_t>(v) & 0xffffffffu);
  const auto d1 = static_cast<std::int64_t>(static_cast<std::uint64_t>(v >> 32) & 0xffffffffu);
  const auto d2 = static_cast<std::int64_t>(static_cast<std::uint64_t>(v >> 64));
  if (bits >> 63) {
    d_[k] -= d0;
    d_[k + 1] -= d1;
    d_[k + 2] -= d2;
  } else {
    d_[k] += d0;
    d_[k + 1] += d1;
    d_[k + 2] += d2;
  }
  if (++pending_ >= kNormaliseEvery) normalise();
}

void ExactSum::normalise() {
  std::int64_t carry = 0;
  for (int k = 0; k < kLimbs - 1; ++k) {
    const std::int64_t t = d_[k] + carry;
    carry = t >> 32;  // floor division by 2^32 (arithmetic shift)
    d_[k] = t - carry * kDigit;
  }
  d_[kLimbs - 1] += carry;
  pending_ = 0;
}

void ExactSum::merge(const ExactSum& o) {
  normalise();
  const std::array<std::int64_t, kLimbs> l = o.limbs();
  for (int k = 0; k < kLimbs; ++k) d_[k] += l[k];
  pending_ = 1;
  if (o.has_special_) {
    special_ += o.special_;
    has_special_ = true;
  }
}

std::array<std::int64_t, ExactSum::kLimbs> ExactSum::limbs() const {
  ExactSum c = *this;
  c.normalise();
  return c.d_;
}

ExactSum ExactSum::from_limbs(const std::int64_t* limbs, double special, bool has_special) {
  ExactSum s;
  std::memcpy(s.d_.data(), limbs, sizeof(std::int64_t) * kLimbs);
  s.pending_ = 1;
  s.normalise();
  s.special_ = special;
  s.has_special_ = has_special;
  return s;
}

double ExactSum::value() const {
  if (has_special_) return special_;
  ExactSum c = *this;
  c.normalise();
  const bool negative = c.d_[kLimbs - 1] < 0;
  if (negative) {
    for (std::int64_t& l : c.d_) l = -l;
    c.normalise();
  }
  int k = kLimbs - 1;
  while (k >= 0 && c.d_[k] == 0) --k;
  if (k < 0) return 0.0;
  // the top three digits (the leading one nonzero: at least 65 significant bits) and a sticky
  // bit for everything below: one correctly rounded conversion, then an exact scaling
  auto digit = [&](int i) { return i >= 0 ? static_cast<unsigned __int128>(c.d_[i]) : 0; };
  unsigned __int128 top = (digit(k) << 64) | (digit(k - 1) << 32) | digit(k - 2);
  bool sticky = false;
  for (int i = k - 3; i >= 0 && !sticky; --i) sticky = c.d_[i] != 0;
  if (sticky) top |= 1;
  const double r = std::ldexp(static_cast<double>(top), 32 * (k - 2) - 1074);
  return negative ? -r : r;
}

}  // namespace common
