/// @file domain_blocks.cpp
/// DomainSim started from blocks of rows (domain_sim.hpp, "Input in blocks"): each rank passes the
/// rows [first, first + n) of the input file that it read, so that no rank holds the whole input.
/// The spheres go to their ORB owners (the collective tree, orb.hpp); ids are checked for
/// uniqueness and the contact history is routed through a directory of ids: the entry of id
/// (its global index and new owner) lives on rank dir(id), a hash of the id. A history record
/// visits dir(id_a), then dir(id_b), which sends it to the owners of both members (a wall contact
/// goes from dir(id_a) to its sphere's owner). Four exchanges, O(N / P) bytes per rank. The checks
/// made here (sphere values, duplicate ids, unknown history ids) throw the one-rank message on
/// every rank alike; a duplicate id is found after the set-up's other checks (one rank: when the
/// file is read). The readers' own checks fail on the rank that holds the bad row, naming its
/// file row, and the driver stops every rank (MPI_Abort).
#include <algorithm>
#include <stdexcept>

#include "common/sorted_rows.hpp"
#include "common/status.hpp"
#include "ssdem/mpi/domain_sim.hpp"
#include "sphere_pack.hpp"

namespace ssdem::mpi {
namespace {
bool is_wall(const HistoryRecord& r) { return r.id_b >= kWallIdBase; }

// A directory entry: a sphere's id, global index and owner (no padding: sent as bytes).
struct IdEntry {
  std::uint64_t id, g, owner;
};

// The directory rank of an id (a multiplicative hash, so that consecutive ids spread).
int dir_of(std::uint64_t id, int P) {
  return static_cast<int>(((id * 0x9E3779B97F4A7C15ull) >> 32) % static_cast<std::uint64_t>(P));
}

// The record with the smallest first value over the ranks (every rank alike; ~0: none anywhere).
std::vector<std::uint64_t> lowest_over_ranks(Comm& comm, const std::vector<std::uint64_t>& mine) {
  const std::vector<std::uint64_t> all = comm.gather(mine);
  std::vector<std::uint64_t> best = mine;
  for (std::size_t r = 0; r + mine.size() <= all.size(); r += mine.size())
    if (all[r] < best[0]) best.assign(all.begin() + static_cast<std::ptrdiff_t>(r), all.begin() + static_cast<std::ptrdiff_t>(r + mine.size()));
  return best;
}

template <class T>
std::vector<T> unpack_all(const std::vector<std::vector<char>>& in) {
  std::vector<T> out;
  for (const auto& b : in)
    for (std::size_t off = 0; off < b.size();) out.push_back(get<T>(b, off));
  return out;
}
}  // namespace

DomainSim::DomainSim(Comm& comm, const SimState& block, const Block& at, SimConfig cfg, double imbalance)
    : comm_(comm), cfg_(std::move(cfg)), imbalance_(imbalance) {
  check_config();
  if (!cfg_.bonds.empty() || !block.bonds.empty())
    throw std::logic_error("DomainSim: a start from blocks takes no bonds (every rank passes all of them instead)");
  const std::size_t n = block.sp.size();
  // the one-rank checks (DomainSim::setup), decided together: the first failing sphere in index order
  const std::size_t lo = common::mpi::dense_first(at.summary.n, comm_.size, comm_.rank);
  if (at.first != lo || n != common::mpi::dense_first(at.summary.n, comm_.size, comm_.rank + 1) - lo)
    throw std::logic_error("DomainSim: a start from blocks needs each rank's dense block of rows (carried_block)");
  std::vector<std::uint64_t> bad{~std::uint64_t{0}, 0};  // global index, id
  const bool consistent = block.sp.consistent();
  for (std::size_t i = 0; i < n && consistent; ++i)
    if (!(block.sp.m[i] > 0.0) || !(block.sp.s[i] > 0.0)) {
      bad = {at.first + i, block.sp.id[i]};
      break;
    }
  if (!comm_.all(consistent)) throw common::InputError("spheres: array sizes differ");
  bad = lowest_over_ranks(comm_, bad);
  if (bad[0] != ~std::uint64_t{0})
    throw common::InputError("sphere id " + std::to_string(bad[1]) + ": mass and radius must be > 0");
  setup_config(at.summary);
  setup_bonds(BondSet{}, Spheres{});
  n_global_ = at.summary.n;
  carried_ = block.sp.carried;  // the rows read are the rank's fixed block (carried_block)
  if (at.restart) {
    const bool sizes = block.a.size() == n && block.alpha.size() == n && (!cfg_.self_gravity || block.ag.size() == n);
    if (!comm_.all(sizes)) throw common::InputError("restart state: acceleration arrays do not match the sphere count");
    resume_clock(block);
    has_prev_ = comm_.all(cfg_.extrapolated_predictor && block.a_prev.size() == n);
  } else {
    block_ = cfg_.adaptive_gravity ? 1 : cfg_.gravity_every;
  }
  distribute_block(block, at.first, at.file);
  if (!at.restart) {  // as the fresh start from all the spheres
    if (contacts_) contacts_->set_edges(false);  // the initial overlaps are not onsets
    compute_forces(true);
    if (contacts_) contacts_->set_edges(true);
    check_state();
  }
}

void DomainSim::distribute_block(const SimState& b, std::size_t first, const std::string& file) {
  const std::size_t n = b.sp.size();
  orb_ = OrbTree::collective(comm_, b.sp.x);  // the tree OrbTree(all positions) gives
  ++stats_.rebalances;
  auto row = [&](const std::vector<Vec3>& v, std::size_t i) { return v.size() == n ? v[i] : Vec3::Zero(); };
  // the rows to their owners, as pack_owned packs them (a state is taken at a block boundary:
  // every sphere opens at its first step, as distribute())
  std::vector<int> owner(n);
  std::vector<std::vector<char>> out(comm_.size);
  for (std::size_t i = 0; i < n; ++i) {
    owner[i] = orb_.owner(b.sp.x[i]);
    std::vector<char>& o = out[owner[i]];
    put(o, static_cast<std::uint64_t>(first + i));
    put_sphere(b.sp, i, o);
    for (const auto* v : {&b.a, &b.alpha, &b.ag, &b.a_prev, &b.alpha_prev}) put(o, row(*v, i));
    if (cfg_.multirate) {
      put(o, static_cast<std::uint8_t>(b.level.size() == n ? b.level[i] : 0));
      put(o, static_cast<std::int64_t>(b.step));
      put(o, 0.0);
      put(o, b.tau_prev.size() == n ? b.tau_prev[i] : 0.0);
    }
  }
  Owned own;
  for (const auto& buf : comm_.alltoallv(out))
    for (std::size_t off = 0; off < buf.size();) unpack_owned(buf, off, own);
  rebuild_local(std::move(own), route_block_history(b, first, owner, file));
}

std::vector<HistoryRecord> DomainSim::route_block_history(const SimState& b, std::size_t first,
                                                          const std::vector<int>& owner, const std::string& file) {
  const int P = comm_.size;
  std::vector<std::vector<char>> out(P);
  // 1. the directory: (id, index, owner) of every row on rank dir(id)
  for (std::size_t i = 0; i < b.sp.size(); ++i)
    put(out[dir_of(b.sp.id[i], P)], IdEntry{b.sp.id[i], first + i, static_cast<std::uint64_t>(owner[i])});
  std::vector<IdEntry> dir = unpack_all<IdEntry>(comm_.alltoallv(out));
  std::sort(dir.begin(), dir.end(), [](const IdEntry& x, const IdEntry& y) { return x.id != y.id ? x.id < y.id : x.g < y.g; });
  // unique ids (common's check_unique_ids over all rows): the repeat with the lowest row, over all ranks
  std::vector<std::uint64_t> dup{~std::uint64_t{0}, 0, 0};  // repeat's row, first row, id
  for (std::size_t k = 1; k < dir.size(); ++k)
    if (dir[k].id == dir[k - 1].id && (k < 2 || dir[k - 2].id != dir[k].id) && dir[k].g < dup[0])
      dup = {dir[k].g, dir[k - 1].g, dir[k].id};
  dup = lowest_over_ranks(comm_, dup);
  if (dup[0] != ~std::uint64_t{0})
    throw common::InputError(file, "/spheres/id", "duplicate id " + std::to_string(dup[2]) + " at rows " +
                                                      std::to_string(dup[1]) + " and " + std::to_string(dup[0]) +
                                                      " (ids must be unique)");
  auto owner_of = [&](std::uint64_t id) {
    const auto it = std::lower_bound(dir.begin(), dir.end(), id, [](const IdEntry& e, std::uint64_t v) { return e.id < v; });
    return it != dir.end() && it->id == id ? static_cast<int>(it->owner) : -1;
  };
  // as the one-rank import (ContactSystem): no contacts, no history; wall records only with walls
  if (!contacts_) return {};
  const std::size_t nw = cfg_.walls.size();
  // 2. each record to dir(id_a): its owner there
  for (auto& o : out) o.clear();
  for (const HistoryRecord& r : b.history) put(out[dir_of(r.id_a, P)], r);
  struct Routed {  // (the owner widened: no padding bytes are sent)
    HistoryRecord r;
    std::uint64_t owner_a;
  };
  const std::vector<HistoryRecord> at_a = unpack_all<HistoryRecord>(comm_.alltoallv(out));
  std::vector<std::vector<char>> deliver(P);
  for (auto& o : out) o.clear();
  bool unknown_pair = false, unknown_wall = false;
  for (const HistoryRecord& r : at_a) {
    if (is_wall(r) && nw == 0) continue;
    const int oa = owner_of(r.id_a);
    if (oa < 0 || (is_wall(r) && r.id_b - kWallIdBase >= nw)) {
      (is_wall(r) ? unknown_wall : unknown_pair) = true;
      continue;
    }
    if (is_wall(r))
      put(deliver[oa], r);  // a wall contact lives with its sphere
    else
      put(out[dir_of(r.id_b, P)], Routed{r, static_cast<std::uint64_t>(oa)});
  }
  // 3. pair records to dir(id_b), which sends them to both owners
  for (const Routed& q : unpack_all<Routed>(comm_.alltoallv(out))) {
    const int ob = owner_of(q.r.id_b);
    if (ob < 0) {
      unknown_pair = true;
      continue;
    }
    const int oa = static_cast<int>(q.owner_a);
    put(deliver[oa], q.r);
    if (ob != oa) put(deliver[ob], q.r);
  }
  if (!comm_.all(!unknown_pair)) throw common::InputError("checkpoint contact history names an unknown sphere id");
  if (!comm_.all(!unknown_wall)) throw common::InputError("checkpoint wall history names an unknown sphere or wall");
  // 4. delivery
  return unpack_all<HistoryRecord>(comm_.alltoallv(deliver));
}

}  // namespace ssdem::mpi
