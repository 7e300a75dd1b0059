/// @file team_tuner.cpp
/// The measured choice of the team rule (team_tuner.hpp has the scheme and the reasons).
#include "ssdem/team_tuner.hpp"

#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <limits>

#include "omp_team.hpp"

namespace ssdem {
namespace {
constexpr int kExploit = 32;          // windows under the best rule per cycle
constexpr double kLoses = 1.3;        // a rule this much slower than the best backs off
constexpr int kMaxBackoff = 15;       // cycles skipped at most
constexpr double kMinWindowS = 0.02;  // W doubles while a window is shorter
constexpr std::int64_t kMaxWindow = std::int64_t{1} << 16;

// The thresholds found when the first of the tuners that set them was made (the size rule of
// all of them), and how many such tuners are alive: a second simulation made while another's
// tuner has set "never" must not take that for its size rule, and the thresholds are restored
// when the last one ends.
struct Base {
  TeamThresholds t;
  int users = 0;
};
Base& base() {
  static Base b;
  return b;
}
}  // namespace

const char* TeamTuner::name(Rule r) {
  switch (r) {
    case size_rule: return "size";
    case every_pass: return "every-pass";
    case one_thread: return "one-thread";
  }
  return "?";
}

TeamTuner::TeamTuner(TeamMode mode) {
  on_ = mode == TeamMode::automatic && omp_get_max_threads() > 1;
  one_ = mode == TeamMode::automatic && !on_;
  now_ = &omp_get_wtime;
  items0_ = team_thresholds().items;
  stream0_ = team_thresholds().stream;
  if (mode == TeamMode::every_pass) force(every_pass);
  if (mode == TeamMode::one_thread) force(one_thread);
  if (on_) register_user();
}

void TeamTuner::register_user() {
  if (registered_) return;
  registered_ = true;
  Base& b = base();
  if (b.users++ == 0) b.t = team_thresholds();
  items0_ = b.t.items;
  stream0_ = b.t.stream;
}

TeamTuner::~TeamTuner() {
  if (!registered_) return;
  Base& b = base();
  if (--b.users == 0) team_thresholds() = b.t;
}

void TeamTuner::apply(Rule r) const {
  constexpr std::size_t never = std::numeric_limits<std::size_t>::max();
  TeamThresholds& t = team_thresholds();  // (the rules set the team sizes; the skew thresholds stay)
  if (r == size_rule) t.items = items0_, t.stream = stream0_;
  if (r == every_pass) t.items = items0_, t.stream = 1;
  if (r == one_thread) t.items = never, t.stream = never;
}

void TeamTuner::force(Rule r) {
  register_user();
  forced_ = true;
  rotate_ = 0;
  in_window_ = 0;
  cur_ = r;
  apply(r);
}

void TeamTuner::force_rotation(std::int64_t every) {
  force(size_rule);
  rotate_ = every;
}

double TeamTuner::estimate(Rule r) const {
  const int k = ncost_[r];
  if (k == 0) return std::numeric_limits<double>::infinity();
  return *std::min_element(cost_[r].begin(), cost_[r].begin() + k);
}

TeamTuner::Rule TeamTuner::best() const {
  Rule b = size_rule;
  for (int r = 1; r < kRules; ++r)
    if (estimate(static_cast<Rule>(r)) < estimate(b)) b = static_cast<Rule>(r);
  return b;
}

void TeamTuner::begin(double excluded_s) {
  t0_ = now_();
  x0_ = excluded_s;
  in_window_ = 0;
  apply(cur_);
}

// a cycle: the rules not backed off, one window each, then the best for kExploit windows
void TeamTuner::close(double excluded_s) {
  const double wall = now_() - t0_;
  const double c = std::max(0.0, wall - (excluded_s - x0_)) / static_cast<double>(window_);
  auto& ring = cost_[cur_];
  std::rotate(ring.rbegin(), ring.rbegin() + 1, ring.rend());  // newest first, oldest dropped
  ring[0] = c;
  ncost_[cur_] = std::min(ncost_[cur_] + 1, 3);
  if (wall < kMinWindowS && window_ < kMaxWindow) window_ *= 2;
  if (tried_ < ntry_) ++tried_;  // exploring: order_[tried_ - 1] has its window
  if (tried_ < ntry_) {
    cur_ = order_[tried_];
  } else if (exploit_left_ == 0 && ntry_ > 0) {  // this cycle's trials are complete
    const Rule b = best();
    for (int k = 0; k < ntry_; ++k) {
      const Rule r = order_[k];
      backoff_[r] = r != b && estimate(r) > kLoses * estimate(b) ? std::min(2 * backoff_[r] + 1, kMaxBackoff) : 0;
      skip_[r] = backoff_[r];
    }
    backoff_[b] = skip_[b] = 0;  // the winner is tried in every cycle from now on
    ntry_ = 0;
    cur_ = b;
    exploit_left_ = kExploit;
  } else if (--exploit_left_ > 0) {
    cur_ = best();
  } else {  // a new cycle
    ntry_ = tried_ = 0;
    for (int r = 0; r < kRules; ++r) {
      if (skip_[r] > 0) {
        --skip_[r];
        continue;
      }
      order_[ntry_++] = static_cast<Rule>(r);
    }
    cur_ = ntry_ > 0 ? order_[0] : best();
    if (ntry_ == 0) exploit_left_ = kExploit;
  }
  begin(excluded_s);
}

void TeamTuner::tick(double excluded_s) {
  if (forced_ || !on_) {
    if (rotate_ > 0 && in_window_++ == rotate_) {
      cur_ = static_cast<Rule>((cur_ + 1) % kRules);
      apply(cur_);
      in_window_ = 1;
    }
    ++steps_[cur_];
    return;
  }
  if (!started_) {  // the first base step: the first cycle tries every rule
    started_ = true;
    for (int r = 0; r < kRules; ++r) order_[r] = static_cast<Rule>(r);
    ntry_ = kRules;
    tried_ = 0;
    cur_ = order_[0];
    begin(excluded_s);
  } else if (in_window_ == window_) {
    close(excluded_s);
  }
  ++in_window_;
  ++steps_[cur_];
}

std::string TeamTuner::report() const {
  std::int64_t total = 0;
  for (std::int64_t s : steps_) total += s;
  std::string out;
  if (one_) {
    out = "auto (one thread: no team to choose)";
  } else if (forced_) {
    out = rotate_ > 0 ? "the rules in turn, " + std::to_string(rotate_) + " base steps each"
                      : std::string(name(cur_)) + " (run.teams)";
  } else if (!on_) {
    out = "size (team from " + std::to_string(items0_) + " items, " + std::to_string(stream0_) +
          " for passes over every sphere)";
  } else {
    out = "auto (measured in windows of " + std::to_string(window_) + " base steps; share of base steps:";
    for (int r = 0; r < kRules; ++r) {
      char buf[64];
      std::snprintf(buf, sizeof buf, " %s %.3f", name(static_cast<Rule>(r)),
                    total ? static_cast<double>(steps_[r]) / static_cast<double>(total) : 0.0);
      out += buf;
    }
    out += ")";
  }
  return out;
}

}  // namespace ssdem
