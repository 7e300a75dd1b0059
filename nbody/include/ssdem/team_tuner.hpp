/// @file team_tuner.hpp
/// Which rule gives the OpenMP loops of a run a team, chosen by measuring the run itself.
///
/// Whether a loop runs faster on a team than on one thread depends on more than its own size.
/// It depends on where its data was last written: a thread that reads spheres another core last
/// drifted or kicked takes them from that core's cache. omp_team.hpp's thresholds count items
/// only. On one 2-core machine the fastest rule differed by scene (nbody/README.md, "Thread teams
/// chosen by measurement", 2 threads):
///   * the demo's 1 022 spheres: no gated team at all (the second thread's teams cost more than
///     they save);
///   * the 1 km remnant, 8 217 spheres at rest: the passes over every sphere (drift, level scan)
///     on the team too (each thread then keeps its own spheres in its own cache), or the size
///     rule: the two lie within the rounds' spread; no team was 1.27x slower;
///   * the sparse debris of a disrupted target, 2 493 spheres: the size rule or no team (within
///     the rounds' spread); every pass on the team was 2.2x slower there.
/// So the rule is measured, as FFTW measures its plans. The base steps are cut into windows of W
/// steps, each run under one rule. A window's cost is its wall time per base step, less the
/// gravity evaluations: the tree's regions are not gated by these rules. Each rule keeps its last
/// three costs and the cheapest of them is its estimate, so a window that met a list rebuild or
/// another process does not decide. A cycle tries every rule that is not backed off for one
/// window each, then runs the rule with the lowest estimate for 32 windows. A rule that lost by
/// more than 30 % skips its next 1, 3, 7 or 15 cycles, so a slow rule costs little after its
/// first trials; the winner of a cycle is tried in every cycle after it. W starts at 32 and doubles while a window takes less than 20 ms, up to 2^16.
/// Every rule gives the same bits (omp_team.hpp: each item written by one thread, sums exact or
/// of zeros), so the choice changes speed only; tests compare runs with each rule forced.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace ssdem {

/// run.teams: the rule measured while the run goes (automatic), or one rule for the whole run.
enum class TeamMode { automatic, size, every_pass, one_thread };

class TeamTuner {
 public:
  enum Rule : int { size_rule, every_pass, one_thread };
  static constexpr int kRules = 3;
  static const char* name(Rule r);

  /// automatic: measured (with more than one thread); size: the thresholds stay as they are and
  /// tick() only counts; every_pass, one_thread: that rule throughout (force()).
  explicit TeamTuner(TeamMode mode);
  /// The thresholds found before the first of the tuners that set them (auto with more than one
  /// thread, or forced) are every such tuner's size rule; the last of them to end restores them.
  ~TeamTuner();
  TeamTuner(const TeamTuner&) = delete;
  TeamTuner& operator=(const TeamTuner&) = delete;

  /// At the start of every base step. excluded_s: wall seconds the run has spent so far in
  /// phases the rules do not govern (gravity); their growth within a window is not its cost.
  void tick(double excluded_s);
  bool on() const { return on_; }
  Rule current() const { return cur_; }
  /// Base steps run under each rule so far.
  const std::array<std::int64_t, kRules>& steps() const { return steps_; }
  /// One line for run_info.txt: the window length and each rule's share of the base steps.
  std::string report() const;

  /// Forces one rule for every base step (tests); tick() then only counts.
  void force(Rule r);
  /// Forces the rules in turn, each for `every` base steps (tests: switches in mid-run).
  void force_rotation(std::int64_t every);
  /// The clock (seconds) the windows are timed with; omp_get_wtime unless a test sets another.
  void set_clock(double (*now)()) { now_ = now; }
  /// The current window length in base steps.
  std::int64_t window() const { return window_; }

 private:
  void begin(double excluded_s);
  void close(double excluded_s);
  Rule best() const;
  double estimate(Rule r) const;
  void apply(Rule r) const;

  void register_user();

  bool on_ = false;
  bool one_ = false;         ///< auto asked for, one thread
  bool started_ = false;
  bool registered_ = false;  ///< sets the thresholds (auto or forced): restores them at the end
  bool forced_ = false;
  std::int64_t rotate_ = 0;  ///< force_rotation's period (0: none)
  double (*now_)() = nullptr;
  std::size_t items0_ = 0, stream0_ = 0;  ///< the thresholds found (the size rule)
  Rule cur_ = size_rule;
  std::int64_t window_ = 32, in_window_ = 0;
  double t0_ = 0.0, x0_ = 0.0;
  std::array<std::array<double, 3>, kRules> cost_{};  ///< last three costs per rule (s per base step)
  std::array<int, kRules> ncost_{};                  ///< how many of them are set
  std::array<int, kRules> backoff_{}, skip_{};
  std::array<Rule, kRules> order_{};  ///< the rules this cycle tries
  int ntry_ = 0, tried_ = 0;          ///< their count, and how many were tried
  int exploit_left_ = 0;
  std::array<std::int64_t, kRules> steps_{};
};

}  // namespace ssdem
