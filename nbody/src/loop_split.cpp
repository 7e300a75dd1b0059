/// @file loop_split.cpp
/// LoopSplit: cuts of a team's loop moved towards equal measured times (equations in
/// loop_split.hpp).
#include "ssdem/loop_split.hpp"

#include <algorithm>
#include <cmath>

namespace ssdem {

std::size_t LoopSplit::size_class(std::size_t n) {
  const double q = std::floor(4.0 * std::log2(static_cast<double>(n) + 1.0));
  return std::min<std::size_t>(static_cast<std::size_t>(std::max(0.0, q)), 95);
}

std::vector<double> LoopSplit::cuts(std::size_t n, int T) const {
  const Cuts& k = classes_[size_class(n)];
  if (k.T == T && static_cast<int>(k.c.size()) == T + 1) return {k.c.begin() + 1, k.c.end() - 1};
  std::vector<double> u;
  for (int j = 1; j < T; ++j) u.push_back(static_cast<double>(j) / T);
  return u;
}

void LoopSplit::block(std::size_t n, int t, int T, std::size_t& lo, std::size_t& hi) const {
  if (T <= 1) {
    lo = 0;
    hi = n;
    return;
  }
  const Cuts& k = classes_[size_class(n)];
  const bool have = k.T == T && static_cast<int>(k.c.size()) == T + 1;
  const std::vector<double>& pin = pinned();
  const bool pinned_here = static_cast<int>(pin.size()) == T - 1;
  auto at = [&](int j) -> std::size_t {
    if (j <= 0) return 0;
    if (j >= T) return n;
    const double f = pinned_here ? pin[static_cast<std::size_t>(j) - 1]
                     : have      ? k.c[static_cast<std::size_t>(j)]
                                 : static_cast<double>(j) / T;
    return std::min(n, static_cast<std::size_t>(f * static_cast<double>(n)));
  };
  lo = at(t);
  hi = std::max(lo, at(t + 1));
}

void LoopSplit::begin(std::size_t n, int T) {
  n_ = n;
  T_ = T;
  times_.assign(T > 1 ? static_cast<std::size_t>(T) : 0, -1.0);
}

void LoopSplit::end() {
  if (T_ <= 1 || n_ == 0 || !pinned().empty()) return;
  // the team that ran: threads 0 .. T - 1 reported (a region may get fewer threads than asked)
  int T = 0;
  while (T < T_ && times_[static_cast<std::size_t>(T)] >= 0.0) {
    if (!std::isfinite(times_[static_cast<std::size_t>(T)])) return;
    ++T;
  }
  for (int j = T; j < T_; ++j)
    if (times_[static_cast<std::size_t>(j)] >= 0.0) return;  // (not a team's numbering)
  if (T < 2) return;
  Cuts& k = classes_[size_class(n_)];
  if (k.T != T || static_cast<int>(k.c.size()) != T + 1) {
    k.T = T;
    k.c.resize(static_cast<std::size_t>(T) + 1);
    for (int j = 0; j <= T; ++j) k.c[static_cast<std::size_t>(j)] = static_cast<double>(j) / T;
  }
  std::vector<double> C(static_cast<std::size_t>(T) + 1, 0.0);
  for (int j = 0; j < T; ++j) C[static_cast<std::size_t>(j) + 1] = C[static_cast<std::size_t>(j)] + times_[static_cast<std::size_t>(j)];
  const double total = C.back();
  if (!(total > 0.0)) return;
  std::vector<double> next = k.c;
  for (int cut = 1; cut < T; ++cut) {
    const double target = total * cut / T;
    int j = 0;
    while (j < T - 1 && C[static_cast<std::size_t>(j) + 1] < target) ++j;
    const double tj = times_[static_cast<std::size_t>(j)];
    const double c0 = k.c[static_cast<std::size_t>(j)], c1 = k.c[static_cast<std::size_t>(j) + 1];
    const double x = tj > 0.0 ? c0 + (target - C[static_cast<std::size_t>(j)]) / tj * (c1 - c0) : 0.5 * (c0 + c1);
    next[static_cast<std::size_t>(cut)] = k.c[static_cast<std::size_t>(cut)] + 0.5 * (x - k.c[static_cast<std::size_t>(cut)]);
  }
  // keep every block at least 1/(8T) of the loop (a mismeasured call cannot starve a thread)
  const double floor_len = 1.0 / (8.0 * T);
  for (int cut = 1; cut < T; ++cut) {
    double& c = next[static_cast<std::size_t>(cut)];
    c = std::min(std::max(c, next[static_cast<std::size_t>(cut) - 1] + floor_len), 1.0 - (T - cut) * floor_len);
  }
  k.c = next;
}

}  // namespace ssdem
