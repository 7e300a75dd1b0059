/// @file domain_exchange.cpp
/// Where the spheres of DomainSim live (domain_sim.hpp): the first distribution, exchanges
/// (rebalance, migration, history routing by the owner rule), ghosts and the per-step halo update.
/// This rank's part of the state and its gathering: domain_local.cpp.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "ssdem/mpi/domain_sim.hpp"
#include "sphere_pack.hpp"

namespace ssdem::mpi {
namespace {
bool is_wall(const HistoryRecord& r) { return r.id_b >= kWallIdBase; }
}  // namespace

void DomainSim::pack_owned(std::size_t i, std::vector<char>& b) const {
  put(b, gidx_[i]);
  put_sphere(sp_, i, b);
  for (const auto* v : {&a_, &alpha_, &ag_, &a_prev_, &alpha_prev_}) put(b, (*v)[i]);
  if (cfg_.multirate) {
    put(b, lr_.level[i]);
    put(b, topen_[i]);
    put(b, hopen_[i]);
    put(b, tau_prev_[i]);
  }
}

// One record of pack_owned, appended to `own`.
void DomainSim::unpack_owned(const std::vector<char>& b, std::size_t& off, Owned& own) const {
  own.g.push_back(get<std::uint64_t>(b, off));
  append_sphere(b, off, own.sp);
  for (auto* v : {&own.a, &own.alpha, &own.ag, &own.a_prev, &own.alpha_prev}) v->push_back(get<Vec3>(b, off));
  unpack_multirate(b, off, own);
}

// The multi-rate fields of pack_owned, appended to `own`.
void DomainSim::unpack_multirate(const std::vector<char>& b, std::size_t& off, Owned& own) const {
  if (!cfg_.multirate) return;
  own.level.push_back(get<std::uint8_t>(b, off));
  own.topen.push_back(get<std::int64_t>(b, off));
  own.hopen.push_back(get<double>(b, off));
  own.tau_prev.push_back(get<double>(b, off));
}

void DomainSim::distribute(const SimState& all) {
  const std::size_t n = all.sp.size();
  orb_ = OrbTree(all.sp.x, comm_.size);
  ++stats_.rebalances;
  Owned own;
  for (std::size_t i = 0; i < n; ++i) {
    if (orb_.owner(all.sp.x[i]) != comm_.rank) continue;
    own.g.push_back(i);
    own.a.push_back(all.a[i]);
    own.alpha.push_back(all.alpha[i]);
    own.ag.push_back(all.ag.size() == n ? all.ag[i] : Vec3::Zero());
    own.a_prev.push_back(all.a_prev.size() == n ? all.a_prev[i] : Vec3::Zero());
    own.alpha_prev.push_back(all.alpha_prev.size() == n ? all.alpha_prev[i] : Vec3::Zero());
    if (cfg_.multirate) {  // a state is taken at a block boundary: every sphere opens at its first step
      own.level.push_back(all.level.size() == n ? all.level[i] : 0);
      own.topen.push_back(all.step);
      own.hopen.push_back(0.0);
      own.tau_prev.push_back(all.tau_prev.size() == n ? all.tau_prev[i] : 0.0);
    }
  }
  own.sp.resize(own.g.size());
  std::vector<char> b;
  for (std::size_t k = 0; k < own.g.size(); ++k) {
    b.clear();
    put_sphere(all.sp, own.g[k], b);
    std::size_t off = 0;
    get_sphere(b, off, own.sp, k);
  }
  pick_bonds(all);  // domain_bonds.cpp
  rebuild_local(std::move(own), all.history);
}

std::vector<HistoryRecord> DomainSim::owned_history() const {
  std::vector<HistoryRecord> out;
  if (!contacts_) return out;
  for (const HistoryRecord& r : contacts_->export_history(sp_))
    if (mine_[slot_of_id_.at(r.id_a)]) out.push_back(r);  // owner rule: the lower-index member's rank
  return out;
}

void DomainSim::exchange() {
  const double t0 = omp_get_wtime(), b0 = comm_.bytes_sent;
  halo_update();  // ghosts' current positions: routing of the history by partner position
  const std::vector<HistoryRecord> recs = owned_history();
  // rebalance when the largest domain exceeds the mean by the imbalance threshold
  // (two reductions, not a gather of every rank's count; counts are exact in a double)
  long long total = static_cast<long long>(own_.size());
  comm_.sum(&total, 1);
  const double most = comm_.max(static_cast<double>(own_.size()));
  const double mean = static_cast<double>(total) / comm_.size;
  if (most > (1.0 + imbalance_) * mean && most - mean >= 1.0) {
    std::vector<Vec3> mine;  // no rank gathers all positions: the cuts by collective selection
    mine.reserve(own_.size());
    for (std::uint32_t i : own_) mine.push_back(sp_.x[i]);
    orb_ = OrbTree::collective(comm_, mine);
    ++stats_.rebalances;
  }
  std::vector<int> dest(sp_.size());
  for (std::size_t i = 0; i < sp_.size(); ++i) dest[i] = orb_.owner(sp_.x[i]);
  // migration: every owned sphere goes to the rank owning its position (itself included)
  std::vector<std::vector<char>> out(comm_.size);
  for (std::uint32_t i : own_) pack_owned(i, out[dest[i]]);
  const std::vector<std::vector<char>> in = comm_.sparse(out);
  Owned own;
  for (const auto& b : in)
    for (std::size_t off = 0; off < b.size();) unpack_owned(b, off, own);
  // history: the owner's record goes to the new owners of both members
  for (auto& b : out) b.clear();
  for (const HistoryRecord& r : recs) {
    const int ra = dest[slot_of_id_.at(r.id_a)];
    const int rb = is_wall(r) ? ra : dest[slot_of_id_.at(r.id_b)];
    put(out[ra], r);
    if (rb != ra) put(out[rb], r);
  }
  std::vector<HistoryRecord> got;
  for (const auto& b : comm_.sparse(out))
    for (std::size_t off = 0; off < b.size();) got.push_back(get<HistoryRecord>(b, off));
  if (nb_global_ > 0)  // bonds: the owner's record to the new owners of both ends (domain_bonds.cpp)
    for (const auto& b : comm_.sparse(route_bonds(dest))) bonds_in_.insert(bonds_in_.end(), b.begin(), b.end());
  stats_.bytes_exchange += comm_.bytes_sent - b0;
  ++stats_.exchanges;
  rebuild_local(std::move(own), got);
  stats_.wall_comm += omp_get_wtime() - t0;
}

void DomainSim::rebuild_local(Owned own, const std::vector<HistoryRecord>& recs) {
  ghosts_fresh_ = true;
  const std::size_t no = own.g.size();
  std::vector<std::size_t> ord(no);
  std::iota(ord.begin(), ord.end(), std::size_t{0});
  std::sort(ord.begin(), ord.end(), [&](std::size_t p, std::size_t q) { return own.g[p] < own.g[q]; });
  // bounding boxes of every rank's own spheres
  std::vector<double> box(7, 0.0);
  if (no > 0) {
    Vec3 lo = own.sp.x[0], hi = own.sp.x[0];
    for (std::size_t k = 0; k < no; ++k) {
      lo = lo.cwiseMin(own.sp.x[k]);
      hi = hi.cwiseMax(own.sp.x[k]);
    }
    box = {1.0, lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z()};
  }
  const std::vector<double> boxes = comm_.gather(box);
  boxes_ = boxes;
  // ghosts: own spheres within the reach of another rank's box (at least the longest intact bond)
  const double reach = nb_global_ > 0 ? std::max(reach_, bond_reach_ * (1.0 + 1e-9)) : reach_;
  std::vector<std::vector<char>> out(comm_.size);
  std::vector<std::vector<std::uint64_t>> sendg(comm_.size);
  if (reach_ >= 0.0)
    for (std::size_t k : ord)
      for (int r = 0; r < comm_.size; ++r) {
        const double* bx = &boxes[7 * r];
        if (r == comm_.rank || bx[0] == 0.0) continue;
        if (box_distance(own.sp.x[k], bx + 1) >= reach) continue;
        put(out[r], own.g[k]);
        put_sphere(own.sp, k, out[r]);
        if (cfg_.multirate) {
          put(out[r], own.level[k]);
          put(out[r], own.topen[k]);
        }
        sendg[r].push_back(own.g[k]);
      }
  const double b0 = comm_.bytes_sent;
  const std::vector<std::vector<char>> in = comm_.sparse(out);
  stats_.bytes_exchange += comm_.bytes_sent - b0;
  Spheres gh;
  std::vector<std::uint64_t> ghg;
  std::vector<int> ghr;
  std::vector<std::uint8_t> ghl;
  std::vector<std::int64_t> gho;
  for (int r = 0; r < comm_.size; ++r)
    for (std::size_t off = 0; off < in[r].size();) {
      ghg.push_back(get<std::uint64_t>(in[r], off));
      ghr.push_back(r);
      append_sphere(in[r], off, gh);
      if (cfg_.multirate) {
        ghl.push_back(get<std::uint8_t>(in[r], off));
        gho.push_back(get<std::int64_t>(in[r], off));
      }
    }
  // the local set: own + ghosts in global-index order
  struct E {
    std::uint64_t g;
    std::size_t k;
    bool own;
  };
  std::vector<E> e;
  for (std::size_t k = 0; k < no; ++k) e.push_back(E{own.g[k], k, true});
  for (std::size_t k = 0; k < ghg.size(); ++k) e.push_back(E{ghg[k], k, false});
  std::sort(e.begin(), e.end(), [](const E& p, const E& q) { return p.g < q.g; });
  const std::size_t nl = e.size();
  sp_ = Spheres{};
  sp_.resize(nl);
  gidx_.resize(nl);
  mine_.assign(nl, 0);
  own_.clear();
  for (auto* v : {&a_, &alpha_, &ag_, &a_prev_, &alpha_prev_, &vpred_, &wpred_, &F_, &T_})
    v->assign(nl, Vec3::Zero());
  ag_old_ = ag_;
  const bool mr = cfg_.multirate;
  if (mr) {
    lr_.reset(nl);  // (the caches follow the new local set)
    topen_.assign(nl, 0);
    hopen_.assign(nl, 0.0);
    tau_prev_.assign(nl, 0.0);
  }
  std::vector<char> b;
  std::vector<std::uint32_t> ghost_slot(ghg.size());
  for (std::size_t s = 0; s < nl; ++s) {
    b.clear();
    put_sphere(e[s].own ? own.sp : gh, e[s].k, b);
    std::size_t off = 0;
    get_sphere(b, off, sp_, s);
    gidx_[s] = e[s].g;
    if (e[s].own) {
      const std::size_t k = e[s].k;
      mine_[s] = 1;
      own_.push_back(static_cast<std::uint32_t>(s));
      a_[s] = own.a[k];
      alpha_[s] = own.alpha[k];
      ag_[s] = own.ag[k];
      a_prev_[s] = own.a_prev[k];
      alpha_prev_[s] = own.alpha_prev[k];
      if (mr) {
        lr_.level[s] = own.level[k];
        topen_[s] = own.topen[k];
        hopen_[s] = own.hopen[k];
        tau_prev_[s] = own.tau_prev[k];
      }
    } else {
      ghost_slot[e[s].k] = static_cast<std::uint32_t>(s);
      if (mr) {
        lr_.level[s] = ghl[e[s].k];
        topen_[s] = gho[e[s].k];
      }
    }
  }
  xex_ = sp_.x;
  slot_of_id_.clear();
  for (std::size_t s = 0; s < nl; ++s) slot_of_id_[sp_.id[s]] = static_cast<std::uint32_t>(s);
  auto slot_of_g = [&](std::uint64_t g) {
    return static_cast<std::uint32_t>(std::lower_bound(gidx_.begin(), gidx_.end(), g) - gidx_.begin());
  };
  send_.assign(comm_.size, {});
  recv_.assign(comm_.size, {});
  for (int r = 0; r < comm_.size; ++r)
    for (std::uint64_t g : sendg[r]) send_[r].push_back(slot_of_g(g));
  for (std::size_t k = 0; k < ghg.size(); ++k) recv_[ghr[k]].push_back(ghost_slot[k]);
  pot_step_ = -1;  // potentials are kept per local slot: the slots changed
  if (contacts_) {
    std::vector<HistoryRecord> mine;
    for (const HistoryRecord& r : recs)
      if (slot_of_id_.count(r.id_a) && (is_wall(r) || slot_of_id_.count(r.id_b))) mine.push_back(r);
    contacts_->import_history(sp_, mine);
  }
  if (nb_global_ > 0) place_bonds();
}

std::vector<std::vector<char>> DomainSim::halo(const std::vector<std::vector<char>>& out, std::size_t record) {
  std::vector<std::size_t> expect(comm_.size);
  for (int r = 0; r < comm_.size; ++r) expect[r] = recv_[r].size() * record;
  return comm_.neighbours(out, expect);
}

void DomainSim::halo_update() {
  if (reach_ < 0.0) return;
  const double t0 = omp_get_wtime(), b0 = comm_.bytes_sent;
  std::vector<std::vector<char>> out(comm_.size);
  for (int r = 0; r < comm_.size; ++r)
    for (std::uint32_t i : send_[r])
      for (const Vec3* v : {&sp_.x[i], &sp_.v[i], &sp_.w[i], &vpred_[i], &wpred_[i]}) put(out[r], *v);
  const std::vector<std::vector<char>> in = halo(out, 5 * sizeof(Vec3));
  for (int r = 0; r < comm_.size; ++r) {
    std::size_t off = 0;
    for (std::uint32_t i : recv_[r])
      for (Vec3* v : {&sp_.x[i], &sp_.v[i], &sp_.w[i], &vpred_[i], &wpred_[i]}) *v = get<Vec3>(in[r], off);
  }
  stats_.bytes_halo += comm_.bytes_sent - b0;
  stats_.wall_comm += omp_get_wtime() - t0;
}

std::size_t DomainSim::cross_rank_contacts() const {
  unsigned long long n = 0;
  for (const HistoryRecord& r : owned_history()) n += !is_wall(r) && !mine_[slot_of_id_.at(r.id_b)];
  MPI_Allreduce(MPI_IN_PLACE, &n, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm_.c);
  return n;
}

int DomainSim::owner_of_id(std::uint64_t id) const {
  const auto it = slot_of_id_.find(id);
  int r = it != slot_of_id_.end() && mine_[it->second] ? comm_.rank : -1;
  MPI_Allreduce(MPI_IN_PLACE, &r, 1, MPI_INT, MPI_MAX, comm_.c);
  return r;
}

}  // namespace ssdem::mpi
