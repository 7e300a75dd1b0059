/// @file drive.cpp
/// Velocity-driven bodies: the kinematic velocity condition on the nodes a driven body occupies
/// and the reaction impulse it records (equations in mpm/body_drive.hpp).
///
///   C_k = { i : S_ip > 0 for a particle p of drive k }   (first drive wins on a shared node;
///         a per-axis weight below kMinWeight counts as 0: a node at the very edge of a particle's
///         support, h + l_p away, gets a round-off weight ~1e-28 from x_p - x_i, and taking it in
///         would widen a platen's grip by a whole cell)
///   v_i <- v_T(t_n), v*_i (and MUSL v**_i) <- v_T(t_n + dt)  on C_k
///   J_k = sum_{C_k} m_i [c2_i + (1 - alpha) c1_i] - M_k (v_T(t_n + dt) - v_T(t_n))
///
/// The node lists are built serially in particle index order, and every sum runs over them in
/// that order, so the loads do not depend on the thread count.
///
/// On MPI ranks (a Subdomain with an exchange): M_k is the body's mass from build_setup (every
/// particle in id order, BodyDrive::mass: the same bits on any rank count and after a restart,
/// whatever the particles' split); after the local
/// flags the ranks make the flags of their shared nodes agree (GridExchange::min_shared_drive:
/// a node reached only by a neighbour's particle of the body is constrained here as well, so
/// owner and ghost keep identical values); each rank sums the reaction over the constrained nodes
/// it owns (Subdomain::own_*), and the ranks' partial impulses are summed in rank order (one
/// reduction per step), so every rank holds the same J_k and the same load history.
#include <string>

#include "kernels.hpp"

namespace mpmfrag {

using namespace detail;

namespace {
constexpr double kMinWeight = 1e-9;
}  // namespace

void Solver::set_drives(std::vector<BodyDrive> drives) {
  for (std::size_t a = 0; a < drives.size(); ++a) {
    if (drives[a].id_end <= drives[a].id_begin)
      throw common::InputError("drive of body " + std::to_string(drives[a].body) + " holds no particle");
    for (std::size_t b = 0; b < a; ++b)
      if (drives[a].id_begin < drives[b].id_end && drives[b].id_begin < drives[a].id_end)
        throw common::InputError("drives of bodies " + std::to_string(drives[b].body) + " and " +
                                 std::to_string(drives[a].body) + " hold the same particles");
  }
  drives_ = std::move(drives);
  const std::size_t nd = drives_.size();
  drive_load_.assign(nd, DriveLoad{});
  drive_mass_.assign(nd, 0.0);
  drive_nodes_.assign(nd, {});
  drive_c1_.assign(nd, Eigen::Vector3d::Zero());
  node_drive_.assign(nd ? nodes_.size() : 0, -1);
  for (std::size_t k = 0; k < nd; ++k) {
    if (drives_[k].mass < 0.0 && sub_.exchange)
      throw common::InputError("drive of body " + std::to_string(drives_[k].body) +
                               ": its mass must come from the set-up on MPI ranks (BodyDrive::mass)");
    if (drives_[k].mass >= 0.0) drive_mass_[k] = drives_[k].mass;
  }
  for (std::size_t p = 0; p < ps_.size(); ++p) {  // one process, drives built without a mass
    const int k = drive_of(ps_.id[p]);
    if (k >= 0 && drives_[k].mass < 0.0) drive_mass_[k] += ps_.mass[p];
  }
}

void Solver::drive_prepare() {
  if (drives_.empty()) return;
  for (std::vector<std::size_t>& list : drive_nodes_) {
    for (const std::size_t i : list) node_drive_[i] = -1;
    list.clear();
  }
  std::vector<Eigen::Vector3d> vt(drives_.size());
  for (std::size_t k = 0; k < drives_.size(); ++k) vt[k] = drives_[k].velocity_at(time_);
  const int sx = sub_.shape[0], sy = sub_.shape[1];
  std::vector<std::size_t>& touched = drive_nodes_[0];  // all nodes first, split below
  for (std::size_t p = 0; p < ps_.size(); ++p) {
    const int k = drive_of(ps_.id[p]);
    if (k < 0) continue;
    for (int d = 0; d < 3; ++d) ps_.v[3 * p + d] = vt[k][d];
    const Stencil s = particle_stencil(cfg_.shape, ps_.x.data() + 3 * p, ps_.half_width.data() + 3 * p, grid_.origin,
                                       grid_.cell_size, sx, sy, shift_);
    for (int c = 0; c < s.Z.n; ++c) {
      if (!(s.Z.w[c] > kMinWeight)) continue;
      for (int b = 0; b < s.Y.n; ++b) {
        if (!(s.Y.w[b] > kMinWeight)) continue;
        const std::size_t row = s.row(sx, sy, b, c);
        for (int a = 0; a < s.X.n; ++a) {
          if (!(s.X.w[a] > kMinWeight)) continue;
          std::int32_t& owner = node_drive_[row + a];
          if (owner < 0) touched.push_back(row + a);
          if (owner < 0 || k < owner) owner = k;
        }
      }
    }
  }
  if (sub_.exchange) sub_.exchange->min_shared_drive(node_drive_.data(), touched);  // collective
  if (drives_.size() > 1) {
    std::vector<std::size_t> all;
    all.swap(touched);
    for (const std::size_t i : all) drive_nodes_[node_drive_[i]].push_back(i);
  }
}

void Solver::apply_drive(GridSlot which, double t, int record, double dt) {
  const Node::Slot3 slot = Node::slot(which);
  // the nodes whose reaction this process counts: all, or on MPI ranks those it owns
  const std::size_t sx = static_cast<std::size_t>(sub_.shape[0]), sy = static_cast<std::size_t>(sub_.shape[1]);
  auto counted = [&](std::size_t i) {
    if (sub_.owns_all) return true;
    const int c[3] = {static_cast<int>(i % sx), static_cast<int>((i / sx) % sy), static_cast<int>(i / (sx * sy))};
    for (int d = 0; d < 3; ++d)
      if (c[d] + sub_.lo[d] < sub_.own_lo[d] || c[d] + sub_.lo[d] >= sub_.own_hi[d]) return false;
    return true;
  };
  std::vector<double> partial;  // record 2: this process's part of each drive's impulse
  for (std::size_t k = 0; k < drives_.size(); ++k) {
    const Eigen::Vector3d vt = drives_[k].velocity_at(t);
    double sum[3] = {0.0, 0.0, 0.0};
    for (const std::size_t i : drive_nodes_[k]) {
      Node& n = nodes_[i];
      double* v = n.*slot;
      const double m = counted(i) ? n.m : 0.0;
      for (int d = 0; d < 3; ++d) {
        sum[d] += m * (vt[d] - v[d]);
        v[d] = vt[d];
      }
    }
    const Eigen::Vector3d c(sum[0], sum[1], sum[2]);
    if (record == 1) drive_c1_[k] = c;
    if (record == 2) {
      const Eigen::Vector3d j = c + (1.0 - cfg_.flip) * drive_c1_[k];
      partial.insert(partial.end(), j.data(), j.data() + 3);
    }
  }
  if (record != 2 || drives_.empty()) return;
  if (sub_.exchange) sub_.exchange->sum(partial.data(), static_cast<int>(partial.size()));  // collective
  for (std::size_t k = 0; k < drives_.size(); ++k) {
    const Eigen::Vector3d vt = drives_[k].velocity_at(t);
    const Eigen::Vector3d J = Eigen::Vector3d(partial[3 * k], partial[3 * k + 1], partial[3 * k + 2]) -
                              drive_mass_[k] * (vt - drives_[k].velocity_at(time_));
    drive_load_[k].force = J / dt;
    drive_load_[k].impulse += J;
  }
}

}  // namespace mpmfrag
