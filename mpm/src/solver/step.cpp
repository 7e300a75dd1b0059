/// @file step.cpp
/// The solver's life cycle and the explicit step schedule (see solver.hpp for the equations and
/// references: Uintah explicit step, shared/reference/mpm.md §1.2–1.6; Sulsky, Chen & Schreyer
/// 1994; Sulsky, Zhou & Schreyer 1995 for MUSL; Bardenhagen & Kober 2004 for GIMP):
/// construction and input checks, initialize (initial stress and wave speeds), the CFL step
/// dt = C min(h) / max_p (s_p + |v_p|) (s: the signal speed, material_update.cpp) capped by dt_max,
/// step() and save_backup().
///
///   USL:  P2G (m, mv, f) -> v -> BC(v) -> v* -> BC(v*) -> G2P (v_p, x_p, L from v*)
///   MUSL: P2G (m, mv, f) -> v -> BC(v) -> v* -> BC(v*) -> FLIP v_p + re-projection (mv)
///         -> v** -> BC(v**) -> G2P (x_p from v*, L from v**)
///   USF:  P2G (m, mv) -> v -> BC(v) -> G2P (L from v, stress update) -> P2G (f) -> v*
///         -> BC(v*) -> G2P (v_p, x_p)
///   BC = the face conditions, then the velocity of driven bodies on their nodes (v at t_n,
///   v* and v** at t_n + dt; body_drive.hpp, drive.cpp), which also records their reaction.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include "kernels.hpp"

namespace mpmfrag {

using namespace detail;

Solver::Solver(SolverConfig cfg, common::GridInfo grid, ParticleSet particles,
               std::vector<MaterialSlot> materials, Subdomain sub)
    : cfg_(std::move(cfg)), grid_(grid), ps_(std::move(particles)), mats_(std::move(materials)) {
  const std::size_t n = ps_.size();
  if (n == 0 && !sub.exchange) throw common::InputError("no particles in the scene");
  if (n >= std::numeric_limits<std::uint32_t>::max()) throw common::InputError("too many particles (> 2^32)");
  if (cfg_.artificial_viscosity && ps_.q.size() != n) ps_.q.assign(n, 0.0);
  if (!cfg_.artificial_viscosity) ps_.q.clear();
  for (std::size_t m = 0; m < mats_.size(); ++m) {
    MaterialSlot& s = mats_[m];
    if (!s.model || !s.style) throw common::InputError("material '" + s.name + "' has no model");
    for (std::size_t p = s.begin; p < s.end; ++p)
      if (ps_.material[p] != static_cast<std::int32_t>(m))
        throw common::InputError("particles of material '" + s.name + "' are not contiguous");
    if (s.state.size() != s.style->state_fields.size()) s.allocate_state();
  }
  build_chunks();
  h_min_ = grid_.cell_size.minCoeff();
  for (int d = 0; d < 3; ++d)
    for (std::size_t p = 0; p < n; ++p)
      if (cfg_.shape == ShapeKind::ugimp && !(ps_.half_width[3 * p + d] > 0.0 && ps_.half_width[3 * p + d] <= 0.5 * grid_.cell_size[d] * (1 + 1e-12)))
        throw common::InputError("particle half-width must be in (0, h/2] (at least 1 particle per cell per axis)");
  sub_.exchange = sub.exchange;  // so that the smallest mass below is the global one
  const double mmin = n ? *std::min_element(ps_.mass.begin(), ps_.mass.end()) : std::numeric_limits<double>::infinity();
  m_min_ = cfg_.min_mass_fraction * -global_max(-mmin);
  set_subdomain(sub);
}

void Solver::set_subdomain(const Subdomain& sub) {
  sub_ = sub;
  if (!sub_.exchange) {
    sub_.lo.setZero();
    sub_.shape = grid_.shape;
  }
  for (int d = 0; d < 3; ++d)
    if (sub_.lo[d] < 0 || sub_.shape[d] < 1 || sub_.lo[d] + sub_.shape[d] > grid_.shape[d])
      throw common::InputError("subdomain box outside the grid");
  const std::size_t sx = sub_.shape[0], sy = sub_.shape[1];
  shift_ = static_cast<std::size_t>(sub_.lo[0]) + sx * (static_cast<std::size_t>(sub_.lo[1]) + sy * sub_.lo[2]);
  nodes_.assign(static_cast<std::size_t>(sub_.shape[0]) * sub_.shape[1] * sub_.shape[2], Node{});
  mom2_.clear();
  if (!drives_.empty()) {  // the drives' node flags follow the box (drive_prepare fills them)
    node_drive_.assign(nodes_.size(), -1);
    for (std::vector<std::size_t>& list : drive_nodes_) list.clear();
  }
  for (int d = 0; d < 3; ++d) nblocks_[d] = (sub_.shape[d] + kBlock - 1) / kBlock;
}

void Solver::replace_particles(ParticleSet particles, std::vector<MaterialSlot> materials) {
  ps_ = std::move(particles);
  mats_ = std::move(materials);
  backup_.valid = false;  // the backup holds other particles now
  for (std::size_t m = 0; m < mats_.size(); ++m) {
    const MaterialSlot& s = mats_[m];
    for (std::size_t p = s.begin; p < s.end; ++p)
      if (ps_.material[p] != static_cast<std::int32_t>(m))
        throw common::InputError("replace_particles: particles of material '" + s.name + "' are not contiguous");
  }
  build_chunks();
  body_accel_.clear();
  key_.clear();
  order_.clear();
}

double Solver::global_max(double v) const {
  if (sub_.exchange) sub_.exchange->max(&v, 1);
  return v;
}

void Solver::initialize() {
  const std::size_t nch = chunks_.size();
  std::fill(chunk_fail_.begin(), chunk_fail_.end(), 0);
  std::vector<double> L(9 * kChunk, 0.0), wpre(2 * kChunk), ws(kChunk), bs(kChunk);
  for (std::size_t p = 0; p < ps_.size(); ++p) ps_.volume[p] = ps_.volume0[p] * det3(ps_.F.data() + 9 * p);
  for (MaterialSlot& m : mats_) {  // body size of each material (flaw populations, issue 16)
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    double dx = 0.0;
    for (std::size_t p = m.begin; p < m.end; ++p) {
      lo = lo.cwiseMin(Eigen::Vector3d(ps_.x[3 * p], ps_.x[3 * p + 1], ps_.x[3 * p + 2]));
      hi = hi.cwiseMax(Eigen::Vector3d(ps_.x[3 * p], ps_.x[3 * p + 1], ps_.x[3 * p + 2]));
      dx = std::max(dx, std::cbrt(ps_.volume0[p]));
    }
    if (sub_.exchange) {  // the material's extent over all processes
      double r[7] = {-lo[0], -lo[1], -lo[2], hi[0], hi[1], hi[2], dx};
      sub_.exchange->max(r, 7);
      lo = -Eigen::Vector3d(r[0], r[1], r[2]);
      hi = Eigen::Vector3d(r[3], r[4], r[5]);
      dx = r[6];
      m.extent = hi[0] >= lo[0] ? (hi - lo).maxCoeff() + dx : 0.0;
    } else {
      m.extent = m.end > m.begin ? (hi - lo).maxCoeff() + dx : 0.0;
    }
  }
  for (std::size_t c = 0; c < nch; ++c) run_material_chunk(c, 0.0, L.data(), wpre.data(), ws.data(), bs.data());
  std::size_t bad = nch;
  for (std::size_t c = 0; c < nch && bad == nch; ++c)
    if (chunk_fail_[c]) bad = c;
  if (any_process(bad < nch))
    throw SolverFailure("initial state invalid: " + (bad < nch ? chunk_msg_[bad] : std::string("on another MPI rank")), true);
  max_speed_ = global_max(nch ? *std::max_element(chunk_speed_.begin(), chunk_speed_.end()) : 0.0);
}

double Solver::stable_dt() const {
  const double dt = cfg_.courant * h_min_ / std::max(max_speed_, 1e-300);
  dt_capped_ = dt > cfg_.dt_max;
  return std::min(dt, cfg_.dt_max);
}

void Solver::step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw SolverFailure("invalid time step " + std::to_string(dt), true);
  const bool lin = cfg_.shape == ShapeKind::linear;
  if (cfg_.reorder_every > 0 && step_ % cfg_.reorder_every == 0) {
    lin ? bin<2>() : bin<3>();
    reorder();
  }
  lin ? bin<2>() : bin<3>();
  drive_prepare();  // driven bodies: particles at v_T(t_n), their nodes C_k (drive.cpp)
  if (body_force_) {
    body_accel_.resize(3 * ps_.size());
    const std::size_t n = ps_.size();
#pragma omp parallel for schedule(static)
    for (std::size_t b = 0; b < n; b += kReduceChunk)
      body_force_(b, std::min(n, b + kReduceChunk), time_, ps_, body_accel_.data() + 3 * b);
  }
  {
    Node* nd = nodes_.data();
    const std::size_t nn = nodes_.size();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < nn; ++i) nd[i] = Node{};
  }
  using std::integral_constant;
  auto scat = [&](auto mode) {
    constexpr int M = decltype(mode)::value;
    lin ? scatter<2, M>() : scatter<3, M>();
  };
  auto gather = [&](auto fl, auto from) {
    constexpr int FL = decltype(fl)::value;
    constexpr GridSlot FROM = decltype(from)::value;
    lin ? g2p<2, FL, FROM>(dt) : g2p<3, FL, FROM>(dt);
  };
  // face conditions, then the drives' velocity condition (body_drive.hpp) on slot s at time t;
  // `record` 1: v_i at t_n, 2: v*_i at t_n + dt (the reaction), 0: MUSL v**_i
  auto bc = [&](GridSlot s, double t, int record) {
    apply_bc(s);
    if (!drives_.empty()) apply_drive(s, t, record, dt);
  };
  const double t1 = time_ + dt;
  using Velocity = integral_constant<GridSlot, GridSlot::velocity>;
  using Updated = integral_constant<GridSlot, GridSlot::updated_velocity>;
  // a subdomain: complete the sums of the nodes shared with other processes (GridExchange)
  auto complete = [&](int fields) {
    if (sub_.exchange) sub_.exchange->sum_shared(nodes_.data(), fields);
  };
  switch (cfg_.scheme) {
    case Scheme::usl:
      scat(integral_constant<int, kMass | kMom | kForce>{});
      complete(kMass | kMom | kForce);
      grid_velocity();
      bc(GridSlot::velocity, time_, 1);
      grid_integrate(dt);
      bc(GridSlot::updated_velocity, t1, 2);
      gather(integral_constant<int, kVel | kPos | kGrad>{}, Updated{});
      break;
    case Scheme::musl: {
      scat(integral_constant<int, kMass | kMom | kForce>{});
      complete(kMass | kMom | kForce);
      grid_velocity();
      bc(GridSlot::velocity, time_, 1);
      grid_integrate(dt);
      bc(GridSlot::updated_velocity, t1, 2);
      // fused: FLIP/PIC velocity update and re-projection of the new particle momenta
      lin ? musl_remap<2>() : musl_remap<3>();
      complete(kMom);
      grid_velocity();
      bc(GridSlot::velocity, t1, 0);
      gather(integral_constant<int, kPos | kGrad>{}, Velocity{});
      break;
    }
    case Scheme::midpoint:
      scat(integral_constant<int, kMass | kMom | kForce>{});
      complete(kMass | kMom | kForce);
      grid_velocity();
      bc(GridSlot::velocity, time_, 1);
      grid_integrate(dt);
      bc(GridSlot::updated_velocity, t1, 2);
      gather(integral_constant<int, kVel | kPos | kGrad>{}, integral_constant<GridSlot, GridSlot::midpoint>{});
      break;
    case Scheme::usf:
      scat(integral_constant<int, kMass | kMom>{});
      complete(kMass | kMom);
      grid_velocity();
      bc(GridSlot::velocity, time_, 1);
      gather(integral_constant<int, kGrad>{}, Velocity{});
      scat(integral_constant<int, kForce>{});
      complete(kForce);
      grid_integrate(dt);
      bc(GridSlot::updated_velocity, t1, 2);
      gather(integral_constant<int, kVel | kPos>{}, Updated{});
      break;
  }
  time_ += dt;
  ++step_;
}

void Solver::save_backup() {
  backup_.particles = ps_;
  backup_.materials = mats_;
  backup_.time = time_;
  backup_.step = step_;
  backup_.valid = true;
}

}  // namespace mpmfrag
