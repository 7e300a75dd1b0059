/// @file domain.cpp
/// One rank's part of a distributed mpm-frag run (mpm/mpi/domain.hpp for the design and the
/// equations): set-up from the full scene, the step (migration, rebalancing, the serial step on
/// the rank's box), global diagnostics summed in rank order, and the gather of all particles.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/status.hpp"
#include "mpm/memory_bounds.hpp"
#include "mpm/mpi/domain.hpp"
#include "mpm/shape_functions.hpp"

namespace mpmfrag::mpi {

namespace {
/// Cell c = floor((x - o) / h) of position x per axis (the expression of axis_weights), clamped
/// to the grid.
Eigen::Vector3i cell_of(const common::GridInfo& g, const double* x) {
  Eigen::Vector3i c;
  for (int a = 0; a < 3; ++a) {
    const double f = std::floor((x[a] - g.origin[a]) / g.cell_size[a]);
    // a NaN position counts in cell 0 (migrate() stops the run on it before it is used)
    c[a] = static_cast<int>(std::min(f > 0.0 ? f : 0.0, static_cast<double>(g.shape[a] - 1)));
  }
  return c;
}
/// The tree's grid, halo (H = 2) and narrowest side W (domain.hpp), no cuts.
Orb orb_layout(const common::GridInfo& grid, int ghost_layers) {
  Orb o;
  o.shape = grid.shape;
  o.halo = 2;
  o.min_width = std::max({2 * o.halo, 2 * ghost_layers + 1 - o.halo, 1});
  return o;
}
}  // namespace

Orb orb_of_particles(const Orb& layout, const common::GridInfo& g, int ranks, const WeightedParticles& each, Comm* comm) {
  return orb_cuts(layout.shape, ranks, layout.halo, layout.min_width,
                  [&](const std::vector<OrbRequest>& req, const std::function<int(const Eigen::Vector3i&)>& locate) {
                    std::vector<std::vector<long long>> h(req.size());
                    for (std::size_t q = 0; q < req.size(); ++q)
                      h[q].assign(static_cast<std::size_t>(req[q].box.hi[req[q].axis] - req[q].box.lo[req[q].axis]), 0);
                    each([&](const double* x, long long w) {
                      const Eigen::Vector3i c = cell_of(g, x);
                      const int q = locate(c);
                      if (q >= 0) h[static_cast<std::size_t>(q)][static_cast<std::size_t>(c[req[q].axis] - req[q].box.lo[req[q].axis])] += w;
                    });
                    if (comm) {  // one exact integer reduction per level of the tree
                      std::vector<long long> flat;
                      for (const auto& v : h) flat.insert(flat.end(), v.begin(), v.end());
                      comm->sum(flat.data(), static_cast<int>(flat.size()));
                      std::size_t k = 0;
                      for (auto& v : h)
                        for (long long& x : v) x = flat[k++];
                    }
                    return h;
                  });
}

Subdomain subdomain_of(const Orb& orb, int r) {
  const Box held = orb.held(r), own = orb.own()[static_cast<std::size_t>(r)];
  Subdomain s;
  s.lo = held.lo;
  s.shape = held.hi - held.lo;
  s.owns_all = false;
  s.own_lo = own.lo;
  s.own_hi = own.hi;
  return s;
}

DomainSolver::DomainSolver(MPI_Comm comm, const Setup& setup, DomainOptions opt)
    : comm_(comm), opt_(opt), grid_(setup.grid) {
  init_orb(setup);
  const ParticleSet& ps = setup.particles;
  orb_ = orb_of_particles(orb_, grid_, comm_.size, [&](const auto& add) {
    for (std::size_t p = 0; p < ps.size(); ++p) add(&ps.x[3 * p], 1);
  }, nullptr);
  std::vector<char> keep(ps.size());
  for (std::size_t p = 0; p < ps.size(); ++p) keep[p] = orb_.owner(cell(&ps.x[3 * p])) == comm_.rank;
  ParticleSet mine;
  std::vector<MaterialSlot> mats;
  select_particles(ps, setup.materials, keep, mine, mats);
  build_solver(setup, std::move(mine), std::move(mats));
}

DomainSolver::DomainSolver(MPI_Comm comm, const Setup& mine, const Orb& orb, DomainOptions opt)
    : comm_(comm), opt_(opt), grid_(mine.grid) {
  init_orb(mine);
  if (orb.ranks() != comm_.size || orb.shape != grid_.shape || !orb_.set(orb.split))
    throw std::logic_error("DomainSolver: a tree of " + std::to_string(orb.ranks()) + " boxes for " +
                           std::to_string(comm_.size) + " ranks, of another grid or not a partition");
  bool ok = true;
  for (std::size_t p = 0; ok && p < mine.particles.size(); ++p) ok = orb_.owner(cell(&mine.particles.x[3 * p])) == comm_.rank;
  if (!comm_.all(ok))  // every rank throws
    throw std::logic_error("DomainSolver: a particle outside its rank's box");
  build_solver(mine, mine.particles, mine.materials);
}

std::pair<Setup, Orb> distributed_setup(MPI_Comm comm, const common::Scene& scene, bool particles) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  SetupPart none;  // the grid first (nothing stored)
  Setup shape = build_setup(scene, builtin_materials(), &none);
  if (!particles) return {std::move(shape), Orb{}};  // a restart: the checkpoint's particles and tree
  const common::GridInfo& g = shape.grid;
  // the particles per plane of each box being cut: every rank walks the lattice itself (the same
  // integers everywhere: no reduction)
  Orb orb = orb_of_particles(orb_layout(g, shape.solver.ghost_layers), g, size, [&](const auto& add) {
    SetupPart counting;
    counting.each = [&](const Eigen::Vector3d& x) { add(x.data(), 1); };
    (void)build_setup(scene, builtin_materials(), &counting);
  }, nullptr);
  SetupPart mine;
  mine.keep = [&](const Eigen::Vector3d& x) { return orb.owner(cell_of(g, x.data())) == rank; };
  return {build_setup(scene, builtin_materials(), &mine), std::move(orb)};
}

void DomainSolver::init_orb(const Setup& setup) { orb_ = orb_layout(grid_, setup.solver.ghost_layers); }

void DomainSolver::build_solver(const Setup& setup, ParticleSet mine, std::vector<MaterialSlot> mats) {
  check_memory(mats);
  halo_ = std::make_unique<HaloExchange>(comm_, orb_);
  Subdomain box = subdomain_of(orb_, comm_.rank);
  box.exchange = halo_.get();
  solver_ = std::make_unique<Solver>(setup.solver, grid_, std::move(mine), std::move(mats), box);
  solver_->set_drives(setup.drives);  // the drives' masses from the set-up (BodyDrive::mass)
}

Eigen::Vector3i DomainSolver::cell(const double* x) const { return cell_of(grid_, x); }

Orb DomainSolver::balanced_orb(const ParticleSet& ps, const std::vector<MaterialSlot>& mats) {
  const std::vector<long long> w = work_weights(ps, mats);
  return orb_of_particles(orb_, grid_, comm_.size, [&](const auto& add) {
    for (std::size_t p = 0; p < ps.size(); ++p) add(&ps.x[3 * p], w[p]);
  }, &comm_);
}

void DomainSolver::migrate() {
  const Solver& s = *solver_;
  const ParticleSet& ps = s.particles();
  const std::vector<MaterialSlot>& mats = s.materials();
  const std::size_t n = ps.size();
  const int npa = s.config().shape == ShapeKind::linear ? 2 : 3;
  std::vector<char> keep(n, 1);
  std::vector<std::vector<char>> send(comm_.size);
  std::size_t bad = n;
  long long sent = 0;
  for (std::size_t p = 0; p < n; ++p) {
    bool ok = true;
    for (int d = 0; d < 3; ++d) {
      const double x = ps.x[3 * p + d];
      const AxisWeights w = axis_weights(s.config().shape, x, grid_.origin[d], grid_.cell_size[d], ps.half_width[3 * p + d]);
      if (!std::isfinite(x)) ok = false;
      // outside the grid: a failure, or with outflow removal the owner of its (clamped) cell
      // removes it in the step (outflow.cpp)
      if ((w.first < 0 || w.first + npa > grid_.shape[d]) && !s.config().outflow_remove) ok = false;
    }
    if (!ok) {
      bad = std::min(bad, p);
      continue;
    }
    const int r = orb_.owner(cell(&ps.x[3 * p]));
    if (r == comm_.rank) continue;
    keep[p] = 0;
    pack_particle(ps, mats, p, send[r]);
    ++sent;
  }
  double flag = bad < n ? 1.0 : 0.0;
  comm_.max(&flag, 1);
  if (flag > 0.0) {
    std::ostringstream os;
    if (bad < n)
      os << "particle id " << ps.id[bad] << " at (" << ps.x[3 * bad] << ", " << ps.x[3 * bad + 1] << ", " << ps.x[3 * bad + 2]
         << ") m left the grid (its interpolation stencil leaves the domain plus ghost layers) at t = " << s.time()
         << " s, step " << s.step_count() << "; enlarge [grid] domain_min/domain_max or use fixed/symmetry faces";
    else
      os << "a particle left the grid on another MPI rank at t = " << s.time() << " s, step " << s.step_count();
    throw SolverFailure(os.str(), true);
  }
  const double before = comm_.bytes_sent;
  const std::vector<std::vector<char>> recv = comm_.sparse(send);
  stats_.migrate_bytes += comm_.bytes_sent - before;
  stats_.migrated += sent;
  bool arrived = false;
  for (const auto& b : recv) arrived = arrived || !b.empty();
  if (sent == 0 && !arrived) return;
  Arrivals in;
  const bool with_q = s.config().artificial_viscosity;
  for (const auto& b : recv) unpack_particles(b, mats, with_q, in);
  ParticleSet out;
  std::vector<MaterialSlot> out_mats;
  merge_particles(ps, mats, keep, in, out, out_mats);
  solver_->replace_particles(std::move(out), std::move(out_mats));
}

double DomainSolver::imbalance() {
  long long total = total_work(solver_->particles(), solver_->materials());
  long long mx = total;  // integer reductions: exact, the same on every rank
  MPI_Allreduce(MPI_IN_PLACE, &mx, 1, MPI_LONG_LONG, MPI_MAX, comm_.c);
  comm_.sum(&total, 1);
  return total > 0 ? static_cast<double>(mx) * comm_.size / static_cast<double>(total) : 1.0;
}

void DomainSolver::rebalance() {
  Orb next;
  try {
    next = balanced_orb(solver_->particles(), solver_->materials());
  } catch (const common::InputError& e) {
    // the weights leave a box of several ranks too narrow to cut (orb.hpp): every rank computed
    // the same histograms and threw alike, so every rank keeps the tree
    if (stats_.rebalances_skipped++ == 0 && comm_.rank == 0)
      spdlog::warn("rebalancing left out at step {}: {} (the boxes stay; warned once, DomainStats::rebalances_skipped "
                   "counts them)", solver_->step_count(), e.what());
    migrate();
    return;
  }
  if (!(next == orb_)) {
    // every rank's new box and particles must fit its memory (DomainSolver::check_memory's
    // rule; the particle bytes at this rank's current mean per particle), else keep the tree
    const ParticleSet& ps = solver_->particles();
    std::vector<long long> count(static_cast<std::size_t>(comm_.size), 0);  // particles per new owner
    for (std::size_t p = 0; p < ps.size(); ++p) ++count[static_cast<std::size_t>(next.owner(cell(&ps.x[3 * p])))];
    comm_.sum(count.data(), comm_.size);
    const long long mine = count[static_cast<std::size_t>(comm_.rank)];
    const double nodes = static_cast<double>(next.held(comm_.rank).size());
    const double n_now = static_cast<double>(ps.size());
    const double per = n_now > 0 ? process_bytes(0.0, solver_->materials()) / n_now : 0.0;
    double per_max = per;  // a rank with no particles now takes the largest rank's mean
    comm_.max(&per_max, 1);
    const double ratio = memory_ratio(nodes, static_cast<double>(mine) * (n_now > 0 ? per : per_max)).ratio;
    if (ratio > 1.0) {
      if (stats_.rebalances_skipped++ == 0 && comm_.rank == 0)
        spdlog::warn("rebalancing left out at step {}: a rank's new box would need {:.3g} x its memory, so "
                     "the boxes stay (warned once; DomainStats::rebalances_skipped counts them)",
                     solver_->step_count(), ratio);
      migrate();
      return;
    }
    orb_ = std::move(next);
    Subdomain box = subdomain_of(orb_, comm_.rank);
    box.exchange = halo_.get();
    solver_->set_subdomain(box);
    ++stats_.rebalances;
  }
  migrate();
}

void DomainSolver::step(double dt) {
  const std::int64_t k = solver_->step_count();
  if (solver_->config().outflow_remove) {  // a rank may have removed all its particles, not all ranks
    long long n = static_cast<long long>(solver_->particles().size());
    comm_.sum(&n, 1);
    if (n == 0) {
      std::ostringstream os;
      os << "all particles left the grid by t = " << solver_->time() << " s, step " << k;
      throw SolverFailure(os.str(), true);
    }
  }
  bool due = false;
  if (opt_.rebalance_every > 0 && k > 0 && k % opt_.rebalance_every == 0) {
    const double I = imbalance();
    stats_.imbalance_max = std::max(stats_.imbalance_max, I);
    stats_.imbalance_sum += I;
    ++stats_.imbalance_checks;
    due = I > opt_.imbalance_threshold;
  }
  if (due)
    rebalance();
  else
    migrate();
  const double before = halo_->bytes_sent;
  solver_->step(dt);
  stats_.halo_bytes += halo_->bytes_sent - before;
}

void DomainSolver::save_backup() {
  backup_.particles = solver_->particles();
  backup_.materials = solver_->materials();
  backup_.time = solver_->time();
  backup_.step = solver_->step_count();
  backup_.valid = true;
}

Diagnostics DomainSolver::diagnostics() {
  const Diagnostics d = solver_->diagnostics();
  const double v[17] = {d.mass, d.momentum[0], d.momentum[1], d.momentum[2], d.angular_momentum[0],
                        d.angular_momentum[1], d.angular_momentum[2], d.kinetic, d.internal, d.work_dev,
                        d.heat_shock, d.heat_transfer, d.elastic, d.dissipated, static_cast<double>(d.removed),
                        d.removed_mass, 0.0};
  const std::vector<double> all = comm_.allgather(v, 17);
  Diagnostics t;
  for (int r = 0; r < comm_.size; ++r) {  // rank order: the same sum on every rank and every run
    const double* u = all.data() + 17 * r;
    t.mass += u[0];
    t.momentum += Eigen::Vector3d(u[1], u[2], u[3]);
    t.angular_momentum += Eigen::Vector3d(u[4], u[5], u[6]);
    t.kinetic += u[7];
    t.internal += u[8];
    t.work_dev += u[9];
    t.heat_shock += u[10];
    t.heat_transfer += u[11];
    t.elastic += u[12];
    t.dissipated += u[13];
    t.removed += static_cast<std::size_t>(u[14]);
    t.removed_mass += u[15];
  }
  return t;
}

void DomainSolver::gather(int root, ParticleSet& out, std::vector<MaterialSlot>& out_mats, Layout* layout) {
  const ParticleSet& ps = solver_->particles();
  const std::vector<MaterialSlot>& mats = solver_->materials();
  std::vector<char> buf;
  for (std::size_t p = 0; p < ps.size(); ++p) pack_particle(ps, mats, p, buf);
  const double before = comm_.bytes_sent;
  const std::vector<std::vector<char>> all = comm_.gather_per_rank(buf, root);
  stats_.migrate_bytes += comm_.bytes_sent - before;
  out = ParticleSet{};
  out_mats.clear();
  if (comm_.rank != root) return;
  Arrivals in;
  const bool with_q = solver_->config().artificial_viscosity;
  std::vector<std::size_t> first(all.size() + 1, 0);  // arrivals [first[r], first[r+1]) came from rank r
  for (std::size_t r = 0; r < all.size(); ++r) {
    unpack_particles(all[r], mats, with_q, in);
    first[r + 1] = in.ps.size();
  }
  sort_arrivals(in, in.ps.id);  // each material by id: a file independent of the rank count
  merge_particles(ps, mats, std::vector<char>(ps.size(), 0), in, out, out_mats);
  if (!layout) return;
  layout->ranks = orb_.ranks();
  layout->split = orb_.split;
  layout->rank.clear();
  layout->index.clear();
  for (const std::vector<std::size_t>& idx : in.index)  // merge order: material by material
    for (const std::size_t k : idx) {
      const std::size_t r = static_cast<std::size_t>(std::upper_bound(first.begin(), first.end(), k) - first.begin()) - 1;
      layout->rank.push_back(static_cast<std::int32_t>(r));
      layout->index.push_back(k - first[r]);
    }
}

}  // namespace mpmfrag::mpi
