/// @file gravity_let_tree.cpp
/// DistributedTree (mpi/gravity_let.hpp), steps 4 and 5: the rank's part of the one-rank tree
/// (its groups' subtrees, the top cells it owns), the maximal cells shared with every rank, and
/// the locally essential trees sent to and received from the other ranks.
#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "common/status.hpp"
#include "ssdem/mpi/gravity_let.hpp"

namespace ssdem::mpi {
namespace {

constexpr std::uint8_t kClosed = 0, kLeaf = 1, kOpen = 2;

// A node whose data this rank does not hold: NaN moments, and as a leaf the NaN sentinel
// particle, so that any use shows as a non-finite acceleration.
tree::Node unknown_node(std::uint32_t sentinel) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  tree::Node nd;
  nd.com = Vec3::Constant(nan);
  nd.mass = nd.bmax = nd.hmax = nan;
  for (double& q : nd.q) q = nan;
  nd.lo = nd.hi = Vec3::Constant(nan);
  nd.start = sentinel;
  nd.count = 1;
  return nd;
}

// A node's moments as sent: what the walk reads of a cell it accepts or opens (96 B). The box
// (lo, hi) is read only of leaves whose particles are used, and of the maximal cells (the ranks'
// boxes): it travels with those (Boxed).
struct NodeRecord {
  double mass, com[3], q[6], bmax, hmax;
};
struct Boxed {
  NodeRecord m;
  double lo[3], hi[3];
};
NodeRecord record_of(const tree::Node& nd) {
  NodeRecord r{};
  r.mass = nd.mass;
  r.bmax = nd.bmax;
  r.hmax = nd.hmax;
  for (int k = 0; k < 3; ++k) r.com[k] = nd.com[k];
  for (int k = 0; k < 6; ++k) r.q[k] = nd.q[k];
  return r;
}
Boxed boxed_of(const tree::Node& nd) {
  Boxed b{record_of(nd), {nd.lo[0], nd.lo[1], nd.lo[2]}, {nd.hi[0], nd.hi[1], nd.hi[2]}};
  return b;
}
void apply(const NodeRecord& r, tree::Node& nd) {
  nd.mass = r.mass;
  nd.bmax = r.bmax;
  nd.hmax = r.hmax;
  nd.com = Vec3(r.com[0], r.com[1], r.com[2]);
  for (int k = 0; k < 6; ++k) nd.q[k] = r.q[k];
}
void apply(const Boxed& b, tree::Node& nd) {
  apply(b.m, nd);
  nd.lo = Vec3(b.lo[0], b.lo[1], b.lo[2]);
  nd.hi = Vec3(b.hi[0], b.hi[1], b.hi[2]);
}

}  // namespace

void DistributedTree::build_local(const std::vector<GravityParticle>& mine) {
  const std::size_t ng = mine.size();
  gx_.resize(ng + 1);
  gm_.resize(ng + 1);
  gs_.resize(ng + 1);
  for (std::size_t k = 0; k < ng; ++k) {
    gx_[k] = Vec3(mine[k].x[0], mine[k].x[1], mine[k].x[2]);
    gm_[k] = mine[k].m;
    gs_[k] = mine[k].s;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  gx_[ng] = Vec3::Constant(nan);  // the sentinel particle
  gm_[ng] = gs_[ng] = nan;
  tree::Data& d = d_;
  const std::uint32_t sentinel = static_cast<std::uint32_t>(ng);
  d.nodes.assign(top_.size(), unknown_node(sentinel));
  for (std::size_t k = 0; k < top_.size(); ++k)
    if (!top_[k].group) {
      d.nodes[k].child = top_[k].child;
      d.nodes[k].nchild = top_[k].nchild;
    }
  d.perm.resize(ng + 1);
  for (std::size_t k = 0; k <= ng; ++k) d.perm[k] = static_cast<std::uint32_t>(k);
  d.scratch.resize(ng + 1);
  for (std::vector<double>* v : {&d.px, &d.py, &d.pz, &d.pm, &d.ph}) v->assign(ng + 1, nan);
  const tree::Source src{gx_.data(), gm_.data(), gs_.data()};
  std::size_t k = 0;
  while (k < ng) {
    const std::uint32_t g = mine[k].group;
    std::size_t e = k;
    while (e < ng && mine[e].group == g) ++e;
    const TopCell& t = top_[g];
    if (t.owner != comm_.rank || t.count != e - k)
      throw std::logic_error("gravity: group " + std::to_string(g) + " of " + std::to_string(t.count) +
                               " spheres arrived with " + std::to_string(e - k) + " on rank " +
                               std::to_string(comm_.rank) + " (owner " + std::to_string(t.owner) + ")");
    tree::build_subtree(d, p_, src, g, static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(e - k), t.c,
                        t.half, t.depth, false);
    k = e;
  }
  for (std::size_t j = top_.size(); j-- > 0;)  // the top cells this rank alone owns, bottom up
    if (!top_[j].group && top_[j].owner == comm_.rank) tree::moments(d, static_cast<std::uint32_t>(j));
}

void DistributedTree::share_maximal() {
  std::vector<Boxed> mine;
  for (std::uint32_t k : maximal_[comm_.rank]) mine.push_back(boxed_of(d_.nodes[k]));
  const double b0 = comm_.bytes_sent;
  std::vector<int> counts;
  const std::vector<Boxed> all = comm_.gather(mine, -1, &counts);
  st_.bytes_top += comm_.bytes_sent - b0;
  const double inf = std::numeric_limits<double>::infinity();
  box_lo_.assign(comm_.size, Vec3::Constant(inf));
  box_hi_.assign(comm_.size, Vec3::Constant(-inf));
  box_h_.assign(comm_.size, 0.0);
  std::size_t o = 0;
  for (int r = 0; r < comm_.size; ++r) {
    if (counts[r] != static_cast<int>(maximal_[r].size()))
      throw std::logic_error("gravity: rank " + std::to_string(r) + " sent " + std::to_string(counts[r]) +
                               " maximal cells, expected " + std::to_string(maximal_[r].size()));
    for (std::uint32_t k : maximal_[r]) {
      if (r != comm_.rank) apply(all[o], d_.nodes[k]);
      const tree::Node& nd = d_.nodes[k];
      box_lo_[r] = box_lo_[r].cwiseMin(nd.lo);
      box_hi_[r] = box_hi_[r].cwiseMax(nd.hi);
      box_h_[r] = std::max(box_h_[r], nd.hmax);
      ++o;
    }
  }
  std::size_t nmax = 0;
  for (const auto& m : maximal_) nmax += m.size();
  st_.maximal_cells = static_cast<double>(nmax);
  st_.top_cells = static_cast<double>(top_.size());
  for (std::size_t j = top_.size(); j-- > 0;)  // the shared cells, bottom up
    if (top_[j].owner < 0) tree::moments(d_, static_cast<std::uint32_t>(j));
}

void DistributedTree::exchange_let() {
  const double itheta = 1.0 / p_.theta;
  std::vector<std::vector<char>> out(comm_.size);
  for (int r = 0; r < comm_.size; ++r) {
    if (r == comm_.rank || maximal_[r].empty()) continue;
    // accepted for every maximal cell of r (each holds some of r's groups), hence for every
    // group of r; the box of all of them first (accepted there: accepted for each)
    auto accepted = [&](const tree::Node& nd) {
      if (tree::tree_accepts(nd, box_lo_[r], box_hi_[r], box_h_[r], itheta)) return true;
      for (std::uint32_t k : maximal_[r]) {
        const tree::Node& m = d_.nodes[k];
        if (!tree::tree_accepts(nd, m.lo, m.hi, m.hmax, itheta)) return false;
      }
      return true;
    };
    std::vector<char>& b = out[r];
    // the body of an opened node: a leaf's particles, or every child's moments and then either
    // kClosed or the child's own body
    auto body = [&](auto&& self, std::uint32_t n) -> void {
      const tree::Node& nd = d_.nodes[n];
      if (nd.child < 0) {
        put(b, kLeaf);
        put(b, nd.lo);
        put(b, nd.hi);
        put(b, nd.count);
        for (std::uint32_t t = nd.start; t < nd.start + nd.count; ++t)
          for (double v : {d_.px[t], d_.py[t], d_.pz[t], d_.pm[t], d_.ph[t]}) put(b, v);
        return;
      }
      put(b, kOpen);
      put(b, nd.nchild);
      for (int j = 0; j < nd.nchild; ++j) {
        const std::uint32_t c = static_cast<std::uint32_t>(nd.child + j);
        put(b, record_of(d_.nodes[c]));
        if (accepted(d_.nodes[c]))
          put(b, kClosed);
        else
          self(self, c);
      }
    };
    for (std::uint32_t m : maximal_[comm_.rank]) {
      if (accepted(d_.nodes[m])) continue;
      put(b, m);
      body(body, m);
    }
  }
  const double b0 = comm_.bytes_sent;
  const std::vector<std::vector<char>> in = comm_.sparse(out);
  st_.bytes_let += comm_.bytes_sent - b0;
  const std::uint32_t sentinel = static_cast<std::uint32_t>(gx_.size() - 1);
  for (int r = 0; r < comm_.size; ++r) {
    if (r == comm_.rank) continue;
    const std::vector<char>& b = in[r];
    std::size_t off = 0;
    auto read = [&](auto&& self, std::uint32_t n, std::uint8_t kind) -> void {
      if (kind == kLeaf) {
        d_.nodes[n].lo = get<Vec3>(b, off);
        d_.nodes[n].hi = get<Vec3>(b, off);
        const std::uint32_t cnt = get<std::uint32_t>(b, off);
        d_.nodes[n].start = static_cast<std::uint32_t>(d_.px.size());
        d_.nodes[n].count = cnt;
        d_.nodes[n].child = -1;
        for (std::uint32_t t = 0; t < cnt; ++t)
          for (std::vector<double>* v : {&d_.px, &d_.py, &d_.pz, &d_.pm, &d_.ph}) v->push_back(get<double>(b, off));
        st_.imported_particles += cnt;
        return;
      }
      if (kind != kOpen) throw std::logic_error("gravity: bad tree record from rank " + std::to_string(r));
      const std::uint8_t nch = get<std::uint8_t>(b, off);
      std::uint32_t first;
      if (n < top_.size() && !top_[n].group) {
        if (top_[n].nchild != nch) throw std::logic_error("gravity: top cell mismatch with rank " + std::to_string(r));
        first = static_cast<std::uint32_t>(top_[n].child);
      } else {
        first = static_cast<std::uint32_t>(d_.nodes.size());
        d_.nodes.resize(d_.nodes.size() + nch, unknown_node(sentinel));
        d_.nodes[n].child = static_cast<std::int32_t>(first);
        d_.nodes[n].nchild = nch;
      }
      for (std::uint32_t j = 0; j < nch; ++j) {
        apply(get<NodeRecord>(b, off), d_.nodes[first + j]);
        st_.imported_nodes += 1;
        const std::uint8_t k = get<std::uint8_t>(b, off);
        if (k != kClosed) self(self, first + j, k);
      }
    };
    while (off < b.size()) {
      const std::uint32_t m = get<std::uint32_t>(b, off);
      if (m >= top_.size() || top_[m].owner != r)
        throw std::logic_error("gravity: rank " + std::to_string(r) + " sent a cell it does not own");
      read(read, m, get<std::uint8_t>(b, off));
    }
  }
}

double DistributedTree::bytes() const {
  double b = static_cast<double>(d_.nodes.capacity() * sizeof(tree::Node) + top_.capacity() * sizeof(TopCell));
  b += static_cast<double>((d_.perm.capacity() + d_.scratch.capacity()) * sizeof(std::uint32_t));
  for (const std::vector<double>* v : {&d_.px, &d_.py, &d_.pz, &d_.pm, &d_.ph, &gm_, &gs_})
    b += static_cast<double>(v->capacity() * sizeof(double));
  b += static_cast<double>(gx_.capacity() * sizeof(Vec3));
  b += static_cast<double>((back_src_.capacity() + back_pos_.capacity() + d_.leaves.capacity() +
                            d_.groups.capacity() + dfs_groups_.capacity()) *
                           sizeof(std::uint32_t));
  for (const auto& m : maximal_) b += static_cast<double>(m.capacity() * sizeof(std::uint32_t));
  b += static_cast<double>((box_lo_.capacity() + box_hi_.capacity()) * sizeof(Vec3) + box_h_.capacity() * 8);
  return b;
}

}  // namespace ssdem::mpi
