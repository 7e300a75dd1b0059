/// @file domain_bonds.cpp
/// Bonds over the domain decomposition (domain_sim.hpp, "Bonds"; mechanics in bonds.hpp): which
/// rank holds which bond, their routing at exchanges, their part of the packed state and of a
/// series row. A bond record: its row in the one-rank bond order, the rows of its two spheres,
/// then every array of BondSet (BondSet::zip_arrays) at that bond.
#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>

#include "common/exact_sum_mpi.hpp"
#include "common/status.hpp"
#include "ssdem/dt_rule.hpp"
#include "ssdem/mpi/domain_sim.hpp"
#include "sphere_pack.hpp"

namespace ssdem::mpi {
namespace {
using common::mpi::get;
using common::mpi::put;

struct BondRow {
  std::uint64_t g, ga, gb;  // bond row; rows of its spheres id_a, id_b
};

void put_bond(std::vector<char>& b, const BondRow& r, const BondSet& s, std::size_t k) {
  put(b, r);
  BondSet::zip_arrays([&](const auto& arr) { put(b, arr[k]); }, s);
}

// Append the records of `b` to `s` (in their order); their rows into `rows`.
void get_bonds(const std::vector<char>& b, BondSet& s, std::vector<BondRow>& rows) {
  for (std::size_t off = 0; off < b.size();) {
    rows.push_back(get<BondRow>(b, off));
    BondSet::zip_arrays([&](auto& arr) {
      using T = typename std::decay_t<decltype(arr)>::value_type;
      arr.push_back(get<T>(b, off));
    }, s);
  }
}
}  // namespace

void DomainSim::setup_bonds(const BondSet& all, const Spheres& sp) {
  nb_global_ = all.size();
  bond_base_ = all.released_base;
  if (all.empty()) return;
  if (!cfg_.contacts) throw common::InputError("bonds need the soft-sphere contacts (contact.enabled = true)");
  check_bond_dt(all, sp, cfg_.dt, cfg_.min_steps_per_contact);
  BondSystem check(all, sp);  // every rank alike: unknown ids, bad radii or lengths (InputError)
}

void DomainSim::pick_bonds(const SimState& all) {
  bonds_in_.clear();
  bond_reach_ = 0.0;
  const BondSet& b = all.bonds;
  if (b.empty()) return;
  std::unordered_map<std::uint64_t, std::uint64_t> row;
  row.reserve(2 * all.sp.size());
  for (std::size_t i = 0; i < all.sp.size(); ++i) row.emplace(all.sp.id[i], i);
  for (std::size_t k = 0; k < b.size(); ++k) {
    const std::uint64_t ia = row.at(b.id_a[k]), ib = row.at(b.id_b[k]);
    const bool intact = !b.broken[k];
    if (intact) bond_reach_ = std::max(bond_reach_, (all.sp.x[ib] - all.sp.x[ia]).norm());
    // an intact bond on the owners of both ends, a broken one on that of id_a only
    if (orb_.owner(all.sp.x[ia]) == comm_.rank || (intact && orb_.owner(all.sp.x[ib]) == comm_.rank))
      put_bond(bonds_in_, BondRow{k, ia, ib}, b, k);
  }
}

std::vector<std::vector<char>> DomainSim::route_bonds(const std::vector<int>& dest) {
  std::vector<std::vector<char>> out(comm_.size);
  double longest = 0.0;
  if (bonds_) {
    const BondSet& b = bonds_->bonds();
    const auto& ia = bonds_->index_a();
    const auto& ib = bonds_->index_b();
    for (std::size_t k = 0; k < b.size(); ++k) {
      if (!b.broken[k]) longest = std::max(longest, (sp_.x[ib[k]] - sp_.x[ia[k]]).norm());
      if (!bown_[k]) continue;  // the owner sends it
      const int ra = dest[ia[k]], rb = dest[ib[k]];
      const BondRow r{bg_[k], gidx_[ia[k]], gidx_[ib[k]]};
      put_bond(out[ra], r, b, k);
      if (!b.broken[k] && rb != ra) put_bond(out[rb], r, b, k);
    }
  }
  for (std::size_t k = 0; k < retired_.size(); ++k)
    put_bond(out[dest[slot_of_id_.at(retired_.id_a[k])]],
             BondRow{retired_g_[k], retired_sph_[2 * k], retired_sph_[2 * k + 1]}, retired_, k);
  bond_reach_ = comm_.max(longest);
  return out;
}

void DomainSim::place_bonds() {
  BondSet in;
  std::vector<BondRow> rows;
  get_bonds(bonds_in_, in, rows);
  bonds_in_ = std::vector<char>{};
  std::vector<std::size_t> order(rows.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t p, std::size_t q) { return rows[p].g < rows[q].g; });
  BondSet live;
  live.released_base = bond_base_;
  bg_.clear();
  bown_.clear();
  retired_ = BondSet{};
  retired_g_.clear();
  retired_sph_.clear();
  auto slot = [&](std::uint64_t id, std::uint64_t g) {
    const auto it = slot_of_id_.find(id);
    if (it == slot_of_id_.end())  // the ghost reach covers the longest intact bond: a bug if reached
      throw std::logic_error("bond row " + std::to_string(g) + ": sphere id " + std::to_string(id) +
                             " is not in the local set of rank " + std::to_string(comm_.rank));
    return it->second;
  };
  for (std::size_t k : order) {
    const BondRow& r = rows[k];
    if (in.broken[k]) {  // kept by the owner of id_a for the files
      if (!mine_[slot(in.id_a[k], r.g)])
        throw std::logic_error("broken bond row " + std::to_string(r.g) + " sent to a rank that does not own id_a");
      retired_.append(in, k);
      retired_g_.push_back(r.g);
      retired_sph_.insert(retired_sph_.end(), {r.ga, r.gb});
      continue;
    }
    const std::uint32_t a = slot(in.id_a[k], r.g);
    slot(in.id_b[k], r.g);
    live.append(in, k);
    bg_.push_back(r.g);
    bown_.push_back(mine_[a]);
  }
  blevels_.reset();
  bonds_ = live.empty() ? nullptr : std::make_unique<BondSystem>(std::move(live), sp_);
  // multi-rate: the bond levels over the local set (l_b from the bond and its two spheres only:
  // the same on every rank that holds the bond)
  if (bonds_ && cfg_.multirate) blevels_ = std::make_unique<BondLevels>(*bonds_, sp_, lr_);
}

void DomainSim::pack_bonds(std::vector<char>& b) const {
  if (bonds_) {
    const auto& ia = bonds_->index_a();
    const auto& ib = bonds_->index_b();
    for (std::size_t k = 0; k < bg_.size(); ++k)
      if (bown_[k]) put_bond(b, BondRow{bg_[k], gidx_[ia[k]], gidx_[ib[k]]}, bonds_->bonds(), k);
  }
  for (std::size_t k = 0; k < retired_.size(); ++k)
    put_bond(b, BondRow{retired_g_[k], retired_sph_[2 * k], retired_sph_[2 * k + 1]}, retired_, k);
}

void DomainSim::unpack_bonds(const std::vector<char>& b, Local& L) const {
  std::vector<BondRow> rows;
  get_bonds(b, L.st.bonds, rows);
  L.st.bonds.released_base = bond_base_;
  for (const BondRow& r : rows) {
    L.brow.push_back(r.g);
    L.bsph.insert(L.bsph.end(), {r.ga, r.gb});
  }
}

void DomainSim::bond_diagnostics(Diagnostics& d, common::ExactSum& elastic) const {
  common::ExactSum el, rel;
  unsigned long long broken = 0;
  if (bonds_) {
    el = bonds_->elastic_sum(sp_, &bown_);
    const BondSet& b = bonds_->bonds();
    for (std::size_t k = 0; k < b.size(); ++k)
      if (bown_[k] && b.broken[k]) {  // broken since the last exchange
        rel.add(b.released[k]);
        ++broken;
      }
  }
  for (double e : retired_.released) rel.add(e);
  broken += retired_.size();
  if (comm_.rank == 0) rel.add(bond_base_);
  common::ExactSum* sums[] = {&el, &rel};
  common::mpi::allreduce(comm_, sums, 2);
  MPI_Allreduce(MPI_IN_PLACE, &broken, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm_.c);
  d.bond_elastic = el.value();
  d.bond_released = rel.value();
  d.bonds = nb_global_;
  d.bonds_broken = broken;
  elastic += d.bond_elastic;  // as the one-rank Simulation::diagnostics
}

std::size_t DomainSim::cross_rank_bonds() const {
  unsigned long long n = 0;
  if (bonds_)
    for (std::size_t k = 0; k < bg_.size(); ++k)
      n += bown_[k] && !bonds_->bonds().broken[k] && !mine_[bonds_->index_b()[k]];
  MPI_Allreduce(MPI_IN_PLACE, &n, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm_.c);
  return n;
}

}  // namespace ssdem::mpi
