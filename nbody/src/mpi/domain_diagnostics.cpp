/// @file domain_diagnostics.cpp
/// A series row's quantities over the ranks (DomainSim::diagnostics): each rank adds the terms of
/// its own spheres and of the contacts it owns (the lower-index member's rank, as the history
/// records) into exact sums, which are added over the ranks (diagnostics.hpp,
/// common/exact_sum_mpi.hpp): no rank holds the whole state, and every rank count gives the bits
/// of one rank's Simulation::diagnostics.
#include <mpi.h>

#include <algorithm>

#include "common/exact_sum_mpi.hpp"
#include "ssdem/mpi/domain_sim.hpp"

namespace ssdem::mpi {

Diagnostics DomainSim::diagnostics() {
  if (cfg_.self_gravity && pot_step_ != step_) {
    // the potential at the current positions, the held field untouched (as Simulation::diagnostics)
    const std::vector<Vec3> keep = ag_;
    const std::int64_t gs = grav_step_;
    const bool want = want_pot_;
    const double gb = stats_.bytes_gravity;
    want_pot_ = true;
    const std::optional<LetStats> tree_stats = tree_ ? std::optional<LetStats>(tree_->stats()) : std::nullopt;
    compute_gravity();
    if (tree_) tree_->set_stats(*tree_stats);  // the row's evaluation is not the integration's
    want_pot_ = want;
    ag_ = keep;
    grav_step_ = gs;
    --times_.gravity_evals;
    // the row's own gathering: counted as "other" traffic, not as the integration's gravity
    stats_.bytes_other += stats_.bytes_gravity - gb;
    stats_.bytes_gravity = gb;
    --stats_.gravity_gathers;
  }
  DiagnosticSums sums;
  for (std::uint32_t i : own_)
    sums.add_sphere(sp_, i, contacts_ != nullptr, cfg_.self_gravity ? &pot_[i] : nullptr, cfg_.uniform_g);
  unsigned long long counts[2] = {0, 0};  // sphere-sphere and wall contacts
  double max_overlap = 0.0;
  if (contacts_) {
    contacts_->add_elastic_energy(sp_, sums.elastic, &mine_);
    for (const HistoryRecord& r : owned_history()) {
      const std::uint32_t a = slot_of_id_.at(r.id_a);
      double frac;
      if (r.id_b >= kWallIdBase) {
        const Plane& p = cfg_.walls.at(r.id_b - kWallIdBase);
        frac = (sp_.s[a] - (sp_.x[a] - p.point).dot(p.normal)) / sp_.s[a];
        ++counts[1];
      } else {
        const std::uint32_t b = slot_of_id_.at(r.id_b);
        frac = (sp_.s[a] + sp_.s[b] - (sp_.x[a] - sp_.x[b]).norm()) / std::min(sp_.s[a], sp_.s[b]);
        ++counts[0];
      }
      max_overlap = std::max(max_overlap, frac);
    }
  }
  const double b0 = comm_.bytes_sent;
  auto all = sums.all();
  common::mpi::allreduce(comm_, all.data(), all.size());
  MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm_.c);
  MPI_Allreduce(MPI_IN_PLACE, &max_overlap, 1, MPI_DOUBLE, MPI_MAX, comm_.c);
  comm_.bytes_sent += 2 * sizeof(unsigned long long) + sizeof(double);
  stats_.bytes_other += comm_.bytes_sent - b0;
  Diagnostics d;
  if (nb_global_ > 0) bond_diagnostics(d, sums.elastic);  // domain_bonds.cpp
  sums.store(d);
  d.contacts = counts[0];
  d.wall_contacts = counts[1];
  d.max_overlap_frac = max_overlap;
  return d;
}

}  // namespace ssdem::mpi
