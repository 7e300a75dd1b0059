/// @file domain_local.cpp
/// This rank's part of DomainSim's state (domain_sim.hpp): packed (pack_owned records of its own
/// spheres and the history records it owns), unpacked for the collective writers (local_state,
/// io_mpi.hpp), kept as the last good state, and gathered on rank 0 in the one-rank layout
/// (gather_state: tests and one-rank comparisons).
#include <algorithm>
#include <numeric>
#include <tuple>

#include "common/sorted_rows.hpp"
#include "ssdem/mpi/domain_sim.hpp"
#include "sphere_pack.hpp"

namespace ssdem::mpi {

DomainSim::Packed DomainSim::pack_local() const {
  Packed p;
  for (std::uint32_t i : own_) pack_owned(i, p.spheres);
  for (const HistoryRecord& r : owned_history()) {
    const auto [first, second] = history_key(r);
    put(p.history, first);
    put(p.history, second);
    put(p.history, r);
  }
  pack_bonds(p.bonds);
  p.step = step_;
  p.time = time_;
  p.grav_step = grav_step_;
  p.block = block_;
  p.has_prev = has_prev_;
  return p;
}

DomainSim::Local DomainSim::unpack(const std::vector<char>& spheres, const std::vector<char>& history,
                                   const std::vector<char>& bonds, const Packed& scalars) const {
  Local L;
  SimState& st = L.st;
  Owned mr;  // multi-rate fields
  for (std::size_t off = 0; off < spheres.size();) {
    L.row.push_back(get<std::uint64_t>(spheres, off));
    append_sphere(spheres, off, st.sp);
    for (auto* v : {&st.a, &st.alpha, &st.ag, &st.a_prev, &st.alpha_prev}) v->push_back(get<Vec3>(spheres, off));
    unpack_multirate(spheres, off, mr);
  }
  if (!cfg_.self_gravity) st.ag.clear();
  if (!scalars.has_prev) {
    st.a_prev.clear();
    st.alpha_prev.clear();
  }
  if (cfg_.multirate) {
    st.level = std::move(mr.level);
    st.tau_prev = std::move(mr.tau_prev);
  }
  for (std::size_t off = 0; off < history.size();) {
    const std::uint64_t first = get<std::uint64_t>(history, off), second = get<std::uint64_t>(history, off);
    L.hkey.emplace_back(first, second);
    st.history.push_back(get<HistoryRecord>(history, off));
  }
  unpack_bonds(bonds, L);
  L.has_prev = scalars.has_prev;
  st.step = scalars.step;
  st.time = scalars.time;
  st.gravity_step = scalars.grav_step;
  st.gravity_block = scalars.block;
  return L;
}

std::pair<std::uint64_t, std::uint64_t> DomainSim::history_key(const HistoryRecord& r) const {
  const bool wall = r.id_b >= kWallIdBase;  // pairs by (index a, index b), then walls by (index, wall)
  const std::uint64_t ga = gidx_[slot_of_id_.at(r.id_a)];
  return {(wall ? std::uint64_t{1} << 63 : 0) | ga, wall ? r.id_b : gidx_[slot_of_id_.at(r.id_b)]};
}

DomainSim::Local DomainSim::local_state() const {
  const Packed p = pack_local();
  return unpack(p.spheres, p.history, p.bonds, p);
}

std::optional<DomainSim::Local> DomainSim::last_good_local() const {
  if (!last_good_) return std::nullopt;
  return unpack(last_good_->spheres, last_good_->history, last_good_->bonds, *last_good_);
}

SimState DomainSim::gather_state() const { return assemble(pack_local()); }

void DomainSim::set_keep_last_good(std::int64_t every) {
  keep_every_ = every;
  if (every > 0 && !last_good_) last_good_ = pack_local();
}

std::optional<SimState> DomainSim::gather_last_good() const {
  if (!last_good_) return std::nullopt;
  return assemble(*last_good_);
}

SimState DomainSim::assemble(const Packed& mine) const {
  const double b0 = comm_.bytes_sent;
  const std::vector<char> all = comm_.gather(mine.spheres, 0), hall = comm_.gather(mine.history, 0),
                          ball = comm_.gather(mine.bonds, 0);
  std::vector<common::Field> carried = carried_;  // the ranks' blocks, in index order on rank 0
  for (common::Field& f : carried) f.values = comm_.gather(f.values, 0);
  stats_.bytes_other += comm_.bytes_sent - b0;
  if (comm_.rank != 0) return SimState{};
  Local L = unpack(all, hall, ball, mine);
  const std::size_t n = n_global_;
  SimState st;
  st.sp.resize(n);
  std::vector<char> b;
  for (std::size_t k = 0; k < L.row.size(); ++k) {  // arrival order -> index order
    b.clear();
    put_sphere(L.st.sp, k, b);
    std::size_t off = 0;
    get_sphere(b, off, st.sp, L.row[k]);
  }
  auto place = [&](const auto& from, auto& to) {
    if (from.empty()) return;
    to.resize(n);
    for (std::size_t k = 0; k < L.row.size(); ++k) to[L.row[k]] = from[k];
  };
  place(L.st.a, st.a);
  place(L.st.alpha, st.alpha);
  place(L.st.ag, st.ag);
  place(L.st.a_prev, st.a_prev);
  place(L.st.alpha_prev, st.alpha_prev);
  place(L.st.level, st.level);
  place(L.st.tau_prev, st.tau_prev);
  st.sp.carried = std::move(carried);
  st.step = L.st.step;
  st.time = L.st.time;
  st.gravity_step = L.st.gravity_step;
  st.gravity_block = L.st.gravity_block;
  // history in the one-rank order
  const auto& key = L.hkey;
  std::vector<std::size_t> order(key.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t p, std::size_t q) { return key[p] < key[q]; });
  for (std::size_t k : order) st.history.push_back(L.st.history[k]);
  // bonds in the one-rank order
  std::vector<std::size_t> border(L.brow.size());
  std::iota(border.begin(), border.end(), std::size_t{0});
  std::sort(border.begin(), border.end(), [&](std::size_t p, std::size_t q) { return L.brow[p] < L.brow[q]; });
  for (std::size_t k : border) st.bonds.append(L.st.bonds, k);
  st.bonds.released_base = bond_base_;
  return st;
}

}  // namespace ssdem::mpi
