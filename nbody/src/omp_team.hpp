/// @file omp_team.hpp
/// OpenMP regions entered only where a team pays for itself (internal to the nbody library).
///
/// libgomp ends every parallel region with a barrier whose last thread makes a futex wake-up
/// system call whether or not a thread waits, also for a team of one (an `if` clause that is
/// false still starts a region). On a virtual machine where that call costs ~1.5 µs, the 2.42 km
/// impact's 1 500 m debris (2 493 spheres, 13 evaluated per base step on average) made 7.6 futex
/// calls and ~7 µs of system time per base step on one thread, a quarter of the step, and its
/// late, sparse debris ran slower on two threads than on one. So the decision is taken before
/// the region: work below the threshold calls the body on this thread and starts no region.
/// Orphaned worksharing constructs in a body (`omp for`, `critical`) are then executed by this
/// thread alone (outside any parallel region; called from inside one, the body gets a region of
/// one thread of its own, so that they do not bind to the enclosing team); an orphaned barrier
/// without a team returns at once. Every loop gives the same
/// bits on a team or on one thread (each item written by one thread; the sums over items are of
/// integers, exact (common::ExactSum) or of zeros that only a NaN spoils), so the thresholds
/// change speed, never results.
#pragma once
#include <omp.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ssdem {

/// The smallest work that gets a team. `items`: loops whose items cost tens of nanoseconds or
/// more (a listed pair, an evaluated sphere's prediction, kick or force sum). `stream`: passes
/// over every sphere at a nanosecond or less per sphere (the drift and the scan of the levels),
/// where below this many the second thread's wake-up and the closing barrier cost more than the
/// half of the pass they save (nbody/README.md, "OpenMP regions entered only where they pay").
/// Tests lower both to 1 so that every region here runs on a team and compare with the serial
/// bits (test_omp_team.cpp). TeamTuner (team_tuner.hpp) sets them between base steps, never
/// inside one: a loop's team decision is taken afresh at each call, so a change between calls
/// is like a change of the loop's size.
struct TeamThresholds {
  std::size_t items = 2048;
  std::size_t stream = 16384;
  /// Listed items shared by count (for_joined_share) only where the threads' blocks held
  /// them this unevenly at the last comparable call: the opening kicks (~4 ns each, two barriers)
  /// and the level assignment (tens of ns each, one barrier); estimates from the barrier cost
  /// (~2 us on the VMs here), not tuned. Tests set 0 (always shared).
  std::size_t kick_skew = 4096;
  std::size_t level_skew = 512;
};
inline TeamThresholds& team_thresholds() {
  static TeamThresholds t;
  return t;
}
enum class Work { items, stream };

/// Whether n units of work get a team (more than one thread available and at least the
/// threshold of that kind of work).
inline bool use_team(std::size_t n, Work w = Work::items) {
  const TeamThresholds& t = team_thresholds();
  return n >= (w == Work::items ? t.items : t.stream) && omp_get_max_threads() > 1;
}

/// f() on this thread alone: directly outside any parallel region, else in a region of one
/// thread of its own (so that orphaned constructs in f bind to it, not to the enclosing team).
template <class F>
inline void alone(F&& f) {
  if (omp_get_level() == 0) {
    f();
  } else {
#pragma omp parallel num_threads(1)
    f();
  }
}

/// f() once on each thread of a team when `team`, else once on this thread (alone()).
template <class F>
inline void in_team(bool team, F&& f) {
  if (team) {
#pragma omp parallel
    f();
  } else {
    alone(f);
  }
}

/// Thread `t` of `T`'s block [b, e) of n items (static: consecutive, ascending with t).
inline void static_block(std::size_t n, int t, int T, std::size_t& b, std::size_t& e) {
  b = n * static_cast<std::size_t>(t) / static_cast<std::size_t>(T);
  e = n * static_cast<std::size_t>(t + 1) / static_cast<std::size_t>(T);
}

/// Thread `t` of `T`'s share of the items that the team's threads listed from their static blocks:
/// f(item) for the items [m t / T, m (t + 1) / T) of lists[0], ..., lists[T - 1] joined (m items in
/// all). Called by every thread of the team after a barrier (the lists complete); the caller
/// places a barrier after it if other work needs its results. Where the listed items cluster in
/// memory (the opening spheres of a pile, consecutive in the spheres' cell order), one thread's
/// block holds most of them: shared by count, each thread gets its half whatever the layout.
/// Each item is processed once, by one thread, so the results do not depend on who does it.
template <class F>
inline void for_joined_share(const std::vector<std::uint32_t>* lists, int t, int T, F&& f) {
  std::size_t m = 0;
  for (int k = 0; k < T; ++k) m += lists[k].size();
  std::size_t b, e;
  static_block(m, t, T, b, e);
  std::size_t off = 0;  // index in the joined list of lists[k][0]
  for (int k = 0; k < T && off < e; ++k) {
    const std::size_t sz = lists[k].size();
    const std::size_t lo = b > off ? b - off : 0, hi = e - off < sz ? e - off : sz;
    for (std::size_t r = lo; r < hi; ++r) f(lists[k][r]);
    off += sz;
  }
}

/// Largest minus smallest size of lists[0..T): how unevenly T static blocks held their listed items.
inline std::size_t list_skew(const std::vector<std::uint32_t>* lists, int T) {
  std::size_t lo = static_cast<std::size_t>(-1), hi = 0;
  for (int k = 0; k < T; ++k) {
    lo = lists[k].size() < lo ? lists[k].size() : lo;
    hi = lists[k].size() > hi ? lists[k].size() : hi;
  }
  return T > 0 ? hi - lo : 0;
}

/// f(lo, hi) on consecutive blocks covering [0, n): one block per thread of a team when
/// use_team(n, w), else f(0, n) on this thread. The loop over a block is the caller's, compiled
/// in its own function (a call per item through the runtime's outlined loop is neither inlined
/// nor vectorised by GCC).
template <class F>
inline void for_blocks(std::size_t n, Work w, F&& f) {
  if (use_team(n, w)) {
#pragma omp parallel
    {
      std::size_t lo, hi;
      static_block(n, omp_get_thread_num(), omp_get_num_threads(), lo, hi);
      f(lo, hi);
    }
  } else {
    alone([&] { f(std::size_t{0}, n); });
  }
}

}  // namespace ssdem
