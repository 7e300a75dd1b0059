/// @file loop_split.hpp
/// Contiguous blocks of a loop over an OpenMP team whose bounds follow the threads' measured times.
///
/// A loop split into equal counts is balanced only when every item costs the same. The contact
/// pair loop is not: a listed pair whose gap is only tested costs a few position loads, cache
/// misses included, and one in contact the pair kernel. On the 2.42 km impact's 500 m debris at
/// t = 7 900 s, thread 0's half of the level-2 pair loop took 1.37x the time of thread 1's half
/// (the other thread waited), and neither the contact count (weights 1 and 7) nor chunks handed
/// out on demand (schedule(dynamic): 1.2x slower contacts, each call moving pairs between the
/// threads' caches) fixed it. So each thread's time over its block is measured, and after the
/// call the cuts move halfway towards those that would have equalised the times, assuming each
/// block's cost spread evenly over its items:
///   C_k = sum_{j<k} t_j,  target of cut k: C_T k / T,  c_k' = c_k + (x_k - c_k) / 2,
/// x_k interpolated linearly inside the block where C reaches the target. Cuts are kept per loop
/// size (quarter octaves of n), since the subsets of different levels differ in where their cost
/// lies. Each thread still writes what it wrote before (its items' records, a sphere's sums), so
/// the results do not depend on the cuts, only the speed does. Used by the contact loops
/// (contacts.cpp) and the opening kicks and drift (multirate.cpp: there the items cost the same,
/// but the pile's spheres arrive from the other core's cache).
#pragma once
#include <array>
#include <cstddef>
#include <vector>

namespace ssdem {

class LoopSplit {
 public:
  /// Inside a team's region: thread t of T's block [lo, hi) of n items (call from every thread,
  /// with the same n). Outside a team (T = 1): [0, n).
  void block(std::size_t n, int t, int T, std::size_t& lo, std::size_t& hi) const;
  /// Inside the region: thread t's time over its block [s].
  void record(int t, double seconds) {
    if (t >= 0 && static_cast<std::size_t>(t) < times_.size()) times_[static_cast<std::size_t>(t)] = seconds;
  }
  /// Before the region: size the timers for a team of up to T threads (T = 1: nothing is
  /// recorded or moved).
  void begin(std::size_t n, int T);
  /// After the region: move the cuts of n's size class for the team that reported (threads 0 to
  /// m - 1, m >= 2, each with a finite time; else nothing moves) towards equal times.
  void end();
  /// The cuts (fractions of n, T - 1 of them) of n's size class for a team of T; uniform if none
  /// were measured yet (exposed for tests).
  std::vector<double> cuts(std::size_t n, int T) const;
  /// Tests: every LoopSplit of the process uses these cuts for teams of cuts.size() + 1 threads
  /// and moves none (empty: measured cuts again), so that results can be compared under extreme
  /// splits.
  static std::vector<double>& pinned() {
    static std::vector<double> p;
    return p;
  }

 private:
  static std::size_t size_class(std::size_t n);
  struct Cuts {
    int T = 0;
    std::vector<double> c;  ///< c[0] = 0 < c[1] < ... < c[T] = 1
  };
  std::array<Cuts, 96> classes_{};
  std::vector<double> times_;
  std::size_t n_ = 0;
  int T_ = 1;
};

}  // namespace ssdem
