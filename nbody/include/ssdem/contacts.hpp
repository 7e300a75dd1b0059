/// @file contacts.hpp
/// Contact detection (cell-list Verlet pair list with a skin) and force assembly for the
/// soft-sphere law of contact_law.hpp, with contact history keyed by sphere-id pairs.
///
/// Neighbour search: spheres are binned in cubic cells of edge >= 2 s_max + skin (hashed cell
/// keys, sorted, so an escaping sphere far away does not blow up a dense grid). All pairs with
/// |x_i - x_j| < s_i + s_j + skin form the pair list, which is rebuilt when any sphere has
/// moved more than skin/2 since the last build (then no contact can be missed).
/// Determinism: the pair list is sorted by (i, j) with i < j; per-pair results are written to
/// per-pair arrays in parallel and gathered per sphere in ascending partner order, so the
/// summation order (and hence the result, bit for bit) is independent of the thread count and
/// of when the list was rebuilt (pairs not in contact contribute nothing).
/// History: per pair (S, n_old, theta_r, theta_q) for the enabled parts only, carried across
/// rebuilds by an id-pair lookup and exported/imported for checkpoints.
#pragma once
#include <cstdint>
#include <vector>

#include "ssdem/contact_law.hpp"
#include "ssdem/spheres.hpp"

namespace ssdem {

/// An infinite plane wall: points p with (p - point).normal >= 0 are inside the domain.
struct Plane {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  ///< unit normal pointing into the domain
};

/// One history record as written to checkpoints. For a wall contact id_b = kWallIdBase + wall.
struct HistoryRecord {
  std::uint64_t id_a = 0, id_b = 0;
  Vec3 S = Vec3::Zero(), n_old = Vec3::Zero(), theta_r = Vec3::Zero();
  double theta_q = 0.0;
};
inline constexpr std::uint64_t kWallIdBase = 0xFFFFFFFF00000000ull;

/// Per-step contact statistics.
struct ContactStats {
  std::size_t contacts = 0;       ///< sphere-sphere contacts
  std::size_t wall_contacts = 0;
  double max_overlap_frac = 0.0;  ///< max overlap / smaller radius
  std::size_t worst_a = 0, worst_b = 0;  ///< indices of the worst pair (b = a for a wall)
  bool rebuilt = false;  ///< the pair list was rebuilt since the previous compute()
};

class ContactSystem {
 public:
  ContactSystem(const ContactParams& p, std::vector<Plane> walls, double skin);

  const ContactParams& params() const { return params_; }
  const std::vector<Plane>& walls() const { return walls_; }
  double skin() const { return skin_; }

  /// Rebuild the pair list if needed (or if `force`). Returns whether it rebuilt. The caller
  /// (Simulation::compute_forces) calls it once before every compute(); nothing else does.
  bool update_neighbors(const Spheres& sp, bool force = false);
  /// Contact forces and torques for all spheres (overwrites F and T), using predicted
  /// velocities/spins vpred/wpred and half-step spins for the transport rotation. Uses the pair
  /// list as left by update_neighbors() / import_history() (std::logic_error if there is none for
  /// these spheres); ContactStats::rebuilt says whether it was rebuilt since the last compute().
  ContactStats compute(const Spheres& sp, const std::vector<Vec3>& vpred,
                       const std::vector<Vec3>& wpred, double h, std::vector<Vec3>& F,
                       std::vector<Vec3>& T);
  /// Elastic energy stored in all current contacts [J] (serial, deterministic).
  double elastic_energy(const Spheres& sp) const;
  /// Active contacts as records keyed by ids (sorted by pair order).
  std::vector<HistoryRecord> export_history(const Spheres& sp) const;
  /// Load history (e.g. from a checkpoint); rebuilds the pair list immediately.
  void import_history(const Spheres& sp, const std::vector<HistoryRecord>& recs);

  std::size_t pair_count() const { return pi_.size(); }
  std::size_t rebuild_count() const { return rebuilds_; }
  /// Bytes held per sphere by the contact system (pair list, history, CSR), current sizes.
  double bytes_per_sphere(std::size_t n) const;

 private:
  void build_pairs(const Spheres& sp);
  template <unsigned PARTS>
  ContactStats compute_impl(const Spheres& sp, const std::vector<Vec3>& vpred,
                            const std::vector<Vec3>& wpred, double h, std::vector<Vec3>& F,
                            std::vector<Vec3>& T);

  ContactParams params_;
  ContactCoeffs coeffs_;
  std::vector<Plane> walls_;
  double skin_;
  bool tang_, roll_, twist_, hist_;

  // pair list (i < j), sorted
  std::vector<std::uint32_t> pi_, pj_;
  std::vector<std::uint8_t> active_;
  std::vector<Vec3> S_, nold_, thr_;
  std::vector<double> thq_;
  // per-pair results
  std::vector<Vec3> pF_, pTp_, pTn_;
  // CSR of pairs where the sphere is the j member (ascending i)
  std::vector<std::uint32_t> jrow_, jpair_;
  // CSR of pairs where the sphere is the i member: contiguous range
  std::vector<std::uint32_t> irow_;
  // wall history, N x nwalls
  std::vector<std::uint8_t> wactive_;
  std::vector<Vec3> wS_, wnold_, wthr_;
  std::vector<double> wthq_;
  std::vector<Vec3> xref_;
  std::size_t rebuilds_ = 0;
  bool rebuilt_since_compute_ = false;
  std::vector<HistoryRecord> pending_;  // imported history waiting for the first build
  bool import_ = false;
};

}  // namespace ssdem
