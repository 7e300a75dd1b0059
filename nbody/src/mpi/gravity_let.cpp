/// @file gravity_let.cpp
/// DistributedTree (mpi/gravity_let.hpp): the evaluation, the root cube, the top tree by
/// level-wise global counts, the gravity owners and the round trip of the spheres to them.
/// Building, moments and the locally essential trees: gravity_let_tree.cpp.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "common/status.hpp"
#include "ssdem/mpi/gravity_let.hpp"

namespace ssdem::mpi {

void DistributedTree::compute(const Spheres& sp, const std::vector<std::uint32_t>& own, std::vector<Vec3>& acc,
                              std::vector<double>* pot, const std::vector<std::uint64_t>& gidx) {
  st_.evaluations += 1;
  for (std::uint32_t i : own) {
    acc[i] = Vec3::Zero();
    if (pot) (*pot)[i] = 0.0;
  }
  double t = omp_get_wtime();
  auto lap = [&t](double& acc_s) {
    const double now = omp_get_wtime();
    acc_s += now - t;
    t = now;
  };
  Vec3 lo, hi;
  double smax;
  std::uint64_t n;
  root_box(sp, own, lo, hi, smax, n);
  d_.nodes.clear();
  d_.groups.clear();
  d_.leaves.clear();
  d_.stats = {};
  if (n == 0) return;
  std::vector<std::uint32_t> group_of;
  top_tree(sp, own, lo, hi, n, group_of);
  assign_owners(group_of);
  lap(st_.t_top);
  std::vector<std::vector<std::uint32_t>> sent;
  const std::vector<GravityParticle> mine = to_owners(sp, own, gidx, group_of, sent);
  lap(st_.t_owners);
  {
    Vec3 c;
    double half;
    tree::tree_root(lo, hi, c, half);
    d_.root_half = std::max(half, smax);  // as TreeGravity::build
  }
  build_local(mine);
  share_maximal();
  lap(st_.t_build);
  exchange_let();
  lap(st_.t_let);
  // walk the own groups, then return each result to the sphere's contact owner
  const std::size_t ng = mine.size();
  std::vector<Vec3> a(ng, Vec3::Zero());
  std::vector<double> ph;
  if (pot) ph.assign(ng, 0.0);
  tree::WalkTally tally;
  tree::walk(d_, p_, d_.groups, a, pot ? &ph : nullptr, tally);
  lap(st_.t_walk);
  if (ng > 0) {
    d_.stats.cell_interactions = tally.cells / static_cast<double>(ng);
    d_.stats.particle_interactions = tally.parts / static_cast<double>(ng);
    d_.stats.near_interactions = tally.near / static_cast<double>(ng);
  }
  const std::size_t rec = (pot ? 4 : 3) * sizeof(double);
  std::vector<std::size_t> from(comm_.size, 0);
  for (std::size_t k = 0; k < ng; ++k) ++from[back_src_[k]];
  std::vector<std::vector<char>> reply(comm_.size);
  for (int r = 0; r < comm_.size; ++r) reply[r].resize(from[r] * rec);
  for (std::size_t k = 0; k < ng; ++k) {
    const double v[4] = {a[k].x(), a[k].y(), a[k].z(), pot ? ph[k] : 0.0};
    std::memcpy(reply[back_src_[k]].data() + back_pos_[k] * rec, v, rec);
  }
  const double b0 = comm_.bytes_sent;
  const std::vector<std::vector<char>> got = comm_.sparse(reply);
  st_.bytes_owners += comm_.bytes_sent - b0;
  for (int r = 0; r < comm_.size; ++r) {
    if (got[r].size() != sent[r].size() * rec)
      throw std::logic_error("gravity: rank " + std::to_string(r) + " returned " + std::to_string(got[r].size()) +
                               " bytes of accelerations, expected " + std::to_string(sent[r].size() * rec));
    for (std::size_t k = 0; k < sent[r].size(); ++k) {
      double v[4];
      std::memcpy(v, got[r].data() + k * rec, rec);
      acc[sent[r][k]] = Vec3(v[0], v[1], v[2]);
      if (pot) (*pot)[sent[r][k]] = v[3];
    }
  }
  lap(st_.t_owners);
}

void DistributedTree::root_box(const Spheres& sp, const std::vector<std::uint32_t>& own, Vec3& lo, Vec3& hi,
                               double& smax, std::uint64_t& n) {
  const double inf = std::numeric_limits<double>::infinity();
  // max of (-lo, hi, s_max, non-finite flag): min(a, b) = -max(-a, -b) exactly
  double v[8] = {-inf, -inf, -inf, -inf, -inf, -inf, 0.0, 0.0};
  std::uint64_t bad_id = 0;
  for (std::uint32_t i : own) {
    const Vec3& x = sp.x[i];
    if (!x.allFinite()) {
      if (v[7] == 0.0) bad_id = sp.id[i];
      v[7] = 1.0;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      v[k] = std::max(v[k], -x[k]);
      v[3 + k] = std::max(v[3 + k], x[k]);
    }
    v[6] = std::max(v[6], sp.s[i]);
  }
  const bool bad_here = v[7] != 0.0;
  comm_.max(v, 8);
  long long cnt = static_cast<long long>(own.size());
  comm_.sum(&cnt, 1);
  st_.bytes_top += static_cast<double>(sizeof v + sizeof cnt);
  if (v[7] != 0.0)
    throw common::NumericalError(bad_here ? "gravity tree: non-finite position of sphere id " + std::to_string(bad_id)
                                          : std::string("gravity tree: non-finite position of a sphere on another rank"));
  lo = Vec3(-v[0], -v[1], -v[2]);
  hi = Vec3(v[3], v[4], v[5]);
  smax = v[6];
  n = static_cast<std::uint64_t>(cnt);
}

void DistributedTree::top_tree(const Spheres& sp, const std::vector<std::uint32_t>& own, const Vec3& lo,
                               const Vec3& hi, std::uint64_t n, std::vector<std::uint32_t>& group_of) {
  top_.clear();
  TopCell root;
  tree::tree_root(lo, hi, root.c, root.half);
  root.count = n;
  root.group = tree::tree_is_group(p_, n, 0, false);
  top_.push_back(root);
  const std::size_t no = own.size();
  group_of.assign(no, 0);
  std::vector<std::int32_t> cell(no, root.group ? -1 : 0);
  std::vector<std::uint8_t> oct(no, 0);
  std::vector<std::uint32_t> open;
  if (!root.group) open.push_back(0);
  std::vector<std::int32_t> slot;  // position in `open` of a top cell (-1 outside `open`)
  while (!open.empty()) {
    slot.resize(top_.size(), -1);
    for (std::size_t j = 0; j < open.size(); ++j) slot[open[j]] = static_cast<std::int32_t>(j);
    std::vector<long long> cnt(8 * open.size(), 0);
    for (std::size_t k = 0; k < no; ++k) {
      if (cell[k] < 0) continue;
      oct[k] = static_cast<std::uint8_t>(tree::tree_octant(sp.x[own[k]], top_[cell[k]].c));
      ++cnt[8 * static_cast<std::size_t>(slot[cell[k]]) + oct[k]];
    }
    comm_.sum(cnt.data(), static_cast<int>(cnt.size()));
    st_.bytes_top += static_cast<double>(cnt.size() * sizeof(long long));
    std::vector<std::int32_t> child_of(8 * open.size(), -1);
    std::vector<std::uint32_t> next;
    for (std::size_t j = 0; j < open.size(); ++j) {
      const TopCell parent = top_[open[j]];
      const std::int32_t first = static_cast<std::int32_t>(top_.size());
      int nch = 0;
      for (int o = 0; o < 8; ++o) {
        const long long m = cnt[8 * j + o];
        if (m == 0) continue;
        TopCell ch;
        ch.c = tree::tree_child_centre(parent.c, parent.half, o);
        ch.half = 0.5 * parent.half;
        ch.depth = parent.depth + 1;
        ch.count = static_cast<std::uint64_t>(m);
        ch.group = tree::tree_is_group(p_, ch.count, ch.depth, false);
        child_of[8 * j + o] = static_cast<std::int32_t>(top_.size());
        if (!ch.group) next.push_back(static_cast<std::uint32_t>(top_.size()));
        top_.push_back(ch);
        ++nch;
      }
      top_[open[j]].child = first;
      top_[open[j]].nchild = static_cast<std::uint8_t>(nch);
    }
    for (std::size_t k = 0; k < no; ++k) {
      if (cell[k] < 0) continue;
      const std::int32_t ch = child_of[8 * static_cast<std::size_t>(slot[cell[k]]) + oct[k]];
      if (top_[ch].group) {
        group_of[k] = static_cast<std::uint32_t>(ch);
        cell[k] = -1;
      } else {
        cell[k] = ch;
      }
    }
    for (std::uint32_t k : open) slot[k] = -1;
    open.swap(next);
  }
}

void DistributedTree::assign_owners(const std::vector<std::uint32_t>& group_of) {
  dfs_groups_.clear();
  std::vector<std::uint32_t> stack{0};
  while (!stack.empty()) {
    const std::uint32_t k = stack.back();
    stack.pop_back();
    if (top_[k].group) {
      dfs_groups_.push_back(k);
      continue;
    }
    for (int j = top_[k].nchild - 1; j >= 0; --j) stack.push_back(static_cast<std::uint32_t>(top_[k].child + j));
  }
  // each group to the rank holding most of its spheres (the lowest such rank on a tie): the
  // contact domains are compact boxes balanced by count, so only the spheres of groups cut by a
  // domain boundary travel, and the gravity work is balanced as the spheres are
  std::vector<std::int32_t> pos(top_.size(), -1);
  for (std::size_t j = 0; j < dfs_groups_.size(); ++j) pos[dfs_groups_[j]] = static_cast<std::int32_t>(j);
  struct CountRank {
    int count, rank;
  };
  std::vector<CountRank> cr(dfs_groups_.size(), CountRank{0, comm_.rank});
  for (std::uint32_t g : group_of) ++cr[pos[g]].count;
  MPI_Allreduce(MPI_IN_PLACE, cr.data(), static_cast<int>(cr.size()), MPI_2INT, MPI_MAXLOC, comm_.c);
  st_.bytes_top += static_cast<double>(cr.size() * sizeof(CountRank));
  for (std::size_t j = 0; j < dfs_groups_.size(); ++j) top_[dfs_groups_[j]].owner = cr[j].rank;
  for (std::size_t k = top_.size(); k-- > 0;) {  // children after their parent
    TopCell& t = top_[k];
    if (t.group) continue;
    t.owner = top_[t.child].owner;
    for (int j = 1; j < t.nchild; ++j)
      if (top_[t.child + j].owner != t.owner) t.owner = -1;
  }
  maximal_.assign(comm_.size, {});
  stack.assign(1, 0);
  while (!stack.empty()) {
    const std::uint32_t k = stack.back();
    stack.pop_back();
    if (top_[k].owner >= 0) {
      maximal_[top_[k].owner].push_back(k);
      continue;
    }
    for (int j = top_[k].nchild - 1; j >= 0; --j) stack.push_back(static_cast<std::uint32_t>(top_[k].child + j));
  }
}

std::vector<DistributedTree::GravityParticle> DistributedTree::to_owners(
    const Spheres& sp, const std::vector<std::uint32_t>& own, const std::vector<std::uint64_t>& gidx,
    const std::vector<std::uint32_t>& group_of, std::vector<std::vector<std::uint32_t>>& sent) {
  std::vector<std::vector<char>> out(comm_.size);
  sent.assign(comm_.size, {});
  for (std::size_t k = 0; k < own.size(); ++k) {
    const std::uint32_t i = own[k];
    const int r = top_[group_of[k]].owner;
    put(out[r], gidx[i]);  // field by field: 52 B, no padding on the wire
    for (double v : {sp.x[i].x(), sp.x[i].y(), sp.x[i].z(), sp.m[i], sp.s[i]}) put(out[r], v);
    put(out[r], group_of[k]);
    sent[r].push_back(i);
  }
  const double b0 = comm_.bytes_sent;
  const std::vector<std::vector<char>> in = comm_.sparse(out);
  st_.bytes_owners += comm_.bytes_sent - b0;
  std::vector<GravityParticle> got;
  std::vector<std::uint32_t> src, pos;
  for (int r = 0; r < comm_.size; ++r) {
    constexpr std::size_t kWire = 8 + 5 * 8 + 4;
    const std::size_t m = in[r].size() / kWire;
    std::size_t off = 0;
    for (std::size_t k = 0; k < m; ++k) {
      GravityParticle p{};
      p.g = get<std::uint64_t>(in[r], off);
      for (double* v : {&p.x[0], &p.x[1], &p.x[2], &p.m, &p.s}) *v = get<double>(in[r], off);
      p.group = get<std::uint32_t>(in[r], off);
      got.push_back(p);
      src.push_back(static_cast<std::uint32_t>(r));
      pos.push_back(static_cast<std::uint32_t>(k));
    }
    if (r != comm_.rank) st_.moved_spheres += static_cast<double>(m);
  }
  // tree order of the groups, then the global index: a group's spheres in one rank's order.
  // A counting sort by group (stable: each sender's spheres arrive in ascending index), then the
  // few groups whose spheres came from more than one rank sorted by index.
  std::vector<std::uint32_t> start(top_.size() + 1, 0);
  for (const GravityParticle& p : got) ++start[p.group + 1];
  {
    std::uint32_t run = 0;  // groups in tree order
    std::vector<std::uint32_t> first(top_.size(), 0);
    for (std::uint32_t g : dfs_groups_) {
      first[g] = run;
      run += start[g + 1];
    }
    for (std::uint32_t g : dfs_groups_) start[g] = first[g];
  }
  std::vector<std::size_t> order(got.size());
  for (std::size_t k = 0; k < got.size(); ++k) order[start[got[k].group]++] = k;
  for (std::size_t b = 0; b < order.size();) {
    std::size_t e = b + 1;
    while (e < order.size() && got[order[e]].group == got[order[b]].group) ++e;
    auto by_index = [&](std::size_t x, std::size_t y) { return got[x].g < got[y].g; };
    if (!std::is_sorted(order.begin() + b, order.begin() + e, by_index)) std::sort(order.begin() + b, order.begin() + e, by_index);
    b = e;
  }
  std::vector<GravityParticle> mine(got.size());
  back_src_.resize(got.size());
  back_pos_.resize(got.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    mine[k] = got[order[k]];
    back_src_[k] = src[order[k]];
    back_pos_[k] = pos[order[k]];
  }
  st_.gravity_spheres += static_cast<double>(mine.size());
  return mine;
}

}  // namespace ssdem::mpi
