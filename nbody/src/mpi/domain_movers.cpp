/// @file domain_movers.cpp
/// When DomainSim needs an exchange (domain_sim.hpp): not at the first sphere that moved far, but
/// when a near pair could miss a ghost.
///
/// Let d_i = |x_i - x_i(ex)| (displacement since the last exchange), g the near gap (skin/2;
/// near: |x_i - x_j| < s_i + s_j + g; a contact is near) and t = exchange_distance() (skin/4 with
/// multi-rate steps, skin/2 without). At the exchange every sphere j within R = 2 s_max + k of the
/// box of rank A's own spheres became a ghost on A. For i own on A and j own on B with j not a
/// ghost on A, |x_i(ex) - x_j(ex)| >= R, so |x_i - x_j| >= R - d_i - d_j:
///   * both d < t: |x_i - x_j| > 2 s_max + k - 2t >= s_i + s_j + (k - 2t): not near with multi-rate
///     (k - 2t = g) and not in contact without (k - 2t = 0). No check needed.
///   * a mover (d >= t; debris: the few fast fragments): its position is sent to every rank
///     (allgather of the movers, one collective per step as the former max-displacement
///     allreduce), and each rank tests its own spheres against the foreign movers through the pair
///     list's cell grid (ContactSystem::near_point, cell edge 2 s_max + k: a j within s_m + s_j +
///     g' of the mover whose reference position is within k - g' of x_j lies in the 27 cells
///     around the mover; g' = g with multi-rate, 0 (a contact) without), and the rare own spheres
///     farther than k - g' from their reference position directly. A near pair (m, j) is covered
///     iff m is a ghost here and j was sent to m's rank at the exchange (x_j(ex) within R of that
///     rank's box then). Any uncovered pair on any rank, or more movers than max(64, N / 16),
///     triggers the exchange. Before that test every rank rules out, from the movers and the
///     ranks' boxes at the exchange that all of them hold, the movers that are far from every
///     other rank's box (a non-mover lies within t of it) and from every other rank's movers
///     (movers_far_apart): when all are, no rank tests its spheres and no reduction is made
///     (stats: mover_reductions of mover_checks; DomainSim::audit_movers runs the test anyway and
///     fails if it finds a near pair the rule missed: the MPI tests set it).
/// The old rule (an exchange whenever max d >= t) exchanged every other base step on the paper
/// debris, where fragments at hundreds of m/s move t in a few steps. Exchanges never change
/// results (the forces are those of one rank whenever the ghosts cover every near pair), only cost.
#include <omp.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

#include "ssdem/mpi/domain_sim.hpp"

namespace ssdem::mpi {
namespace {
struct Mover {
  std::uint64_t g;
  double x[3];
  double s;
  std::int32_t rank;
};
// a rank's failure-check records (DomainSim::Pending) ride first in its movers: kVerdict with
// x = (first non-finite index, its id, largest overlap), kVerdict - 1 with x = (the pair's ids, -)
// (indices and ids bit-copied into the doubles)
constexpr std::uint64_t kVerdict = ~std::uint64_t{0};

// Whether every rank may conclude from what all of them hold alike (the gathered movers, every
// rank's box of own spheres at the exchange) that no mover is near a sphere of another rank: a
// sphere that is not a mover lies within t of its rank's box (its displacement since the exchange
// is < t), so a mover m farther than s_m + s_max + g + t from every other rank's box and farther
// than s_m + s_m' + g from every other rank's mover m' is near none of their spheres. O(M (P + M))
// for M movers on P ranks; above 2^16 box tests the ranks test their spheres instead (false).
bool movers_far_apart(const std::vector<Mover>& all, const std::vector<double>& boxes, int P, double smax, double g,
                      double t) {
  if (all.size() * (static_cast<std::size_t>(P) + all.size()) > (std::size_t{1} << 16)) return false;
  constexpr double kMargin = 1.0 + 1e-12;  // round-off of the distances
  for (std::size_t a = 0; a < all.size(); ++a) {
    const Mover& m = all[a];
    const Vec3 x(m.x[0], m.x[1], m.x[2]);
    for (int r = 0; r < P; ++r) {
      const double* bx = &boxes[7 * static_cast<std::size_t>(r)];
      if (r != m.rank && bx[0] != 0.0 && box_distance(x, bx + 1) < (m.s + smax + g + t) * kMargin) return false;
    }
    for (std::size_t b = a + 1; b < all.size(); ++b) {
      const Mover& o = all[b];
      const double d = m.s + o.s + g;
      if (o.rank != m.rank && (x - Vec3(o.x[0], o.x[1], o.x[2])).squaredNorm() < d * d * kMargin) return false;
    }
  }
  return true;
}
}  // namespace

bool DomainSim::need_exchange() {
  const double t = exchange_distance(), g = cfg_.multirate ? 0.5 * skin_ : 0.0;
  // first the previous step's failure check (check_state), whose verdict this allgather carries
  // (a rank's part only if it fails: parts_to_send)
  std::vector<Mover> mine;
  for (const Pending& p : parts_to_send()) {
    mine.push_back(Mover{kVerdict, {std::bit_cast<double>(p.bad_g), std::bit_cast<double>(p.bad_id), p.overlap}, 0.0,
                         comm_.rank});
    mine.push_back(Mover{kVerdict - 1, {std::bit_cast<double>(p.id_a), std::bit_cast<double>(p.id_b), 0.0}, 0.0,
                         comm_.rank});
  }
  for (std::uint32_t i : own_)
    if ((sp_.x[i] - xex_[i]).squaredNorm() >= t * t)
      mine.push_back(Mover{gidx_[i], {sp_.x[i].x(), sp_.x[i].y(), sp_.x[i].z()}, sp_.s[i], comm_.rank});
  std::vector<Mover> all = comm_.gather(mine);
  std::vector<Pending> parts;  // in rank order, as the allgather placed them
  for (const Mover& m : all)
    if (m.g == kVerdict) {
      Pending p;
      p.bad_g = std::bit_cast<std::uint64_t>(m.x[0]);
      p.bad_id = std::bit_cast<std::uint64_t>(m.x[1]);
      p.overlap = m.x[2];
      parts.push_back(p);
    } else if (m.g == kVerdict - 1) {
      parts.back().id_a = std::bit_cast<std::uint64_t>(m.x[0]);
      parts.back().id_b = std::bit_cast<std::uint64_t>(m.x[1]);
    }
  verdict(parts);  // every rank alike (the same records)
  all.erase(std::remove_if(all.begin(), all.end(), [](const Mover& m) { return m.g >= kVerdict - 1; }), all.end());
  if (all.empty()) return false;
  if (all.size() > std::max<std::size_t>(64, n_global_ / 16)) return true;
  ++stats_.mover_checks;
  const bool far = movers_far_apart(all, boxes_, comm_.size, smax_, g, t);  // every rank alike
  if (far && !audit_movers) return false;
  if (!far) ++stats_.mover_reductions;
  // a near pair of foreign mover m and own sphere j: covered iff m is a ghost here and j was sent
  // to m's rank (x_j(ex) within the reach of that rank's box at the exchange)
  auto covered = [&](const Mover& m, std::uint32_t j) {
    const auto it = std::lower_bound(gidx_.begin(), gidx_.end(), m.g);
    const bool ghost = it != gidx_.end() && *it == m.g && !mine_[it - gidx_.begin()];
    const double* bx = &boxes_[7 * m.rank];
    return ghost && bx[0] != 0.0 && box_distance(xex_[j], bx + 1) < reach_;
  };
  auto near = [&](const Mover& m, std::uint32_t j) {
    const double r = m.s + sp_.s[j] + g;
    return (sp_.x[j] - Vec3(m.x[0], m.x[1], m.x[2])).squaredNorm() < r * r;
  };
  // own spheres the grid may not find (farther than skin - g' from their reference position)
  const std::vector<Vec3>& xref = contacts_->reference_positions();
  const double lim = skin_ - g;
  std::vector<std::uint32_t> direct, cand;
  for (std::uint32_t j : own_)
    if ((sp_.x[j] - xref[j]).squaredNorm() > lim * lim) direct.push_back(j);
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);  // own box now
  for (std::uint32_t j : own_) {
    lo = lo.cwiseMin(sp_.x[j]);
    hi = hi.cwiseMax(sp_.x[j]);
  }
  bool bad = false;
  for (const Mover& m : all) {
    if (m.rank == comm_.rank || own_.empty()) continue;
    if (box_distance(Vec3(m.x[0], m.x[1], m.x[2]), lo, hi) >= m.s + smax_ + g) continue;  // near none
    if (m.s + smax_ + skin_ <= contacts_->cell_edge()) {
      cand = direct;
      contacts_->near_point(Vec3(m.x[0], m.x[1], m.x[2]), cand);
    } else {
      cand = own_;  // a mover larger than the local spheres: the grid's cells are too small for it
    }
    for (std::uint32_t j : cand)
      if (mine_[j] && near(m, j) && !covered(m, j)) bad = true;
    if (bad) break;
  }
  const bool any = comm_.max(bad ? 1.0 : 0.0) > 0.0;
  if (far && any)  // (audit_movers; every rank alike)
    throw std::logic_error("movers_far_apart ruled out a near pair that the ranks' test finds, at base step " +
                           std::to_string(step_));
  return any;
}

}  // namespace ssdem::mpi
