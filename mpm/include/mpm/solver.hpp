/// @file solver.hpp
/// Explicit 3D MPM time integrator (uGIMP or linear weights; USL, USF, MUSL; PIC/FLIP blend;
/// CFL time step; bulk artificial viscosity; minimum-nodal-mass rule; free/fixed/symmetry grid
/// faces), after the Uintah explicit step described in shared/reference/mpm.md §1.2–1.6:
///
///   P2G:   m_i = sum_p S_ip m_p,  (mv)_i = sum_p S_ip m_p v_p,
///          f_i = -sum_p V_p (sigma_p - q_p I) . grad S_ip + sum_p S_ip m_p b_p + m_i g
///   grid:  v_i = (mv)_i/m_i;  v*_i = v_i + dt f_i/m_i  (only where m_i > m_min, else v*_i = v_i)
///   BCs:   fixed: v = 0 on the face plane and the ghost layers; symmetry: normal component 0 on
///          the plane, mirror image on the ghost layers (Uintah MPMBoundCond); then driven bodies:
///          v = v_T(t) on the nodes they occupy, reaction recorded (body_drive.hpp, drive.cpp)
///   G2P:   v_p <- alpha (v_p + sum S (v* - v)) + (1 - alpha) sum S v*   (alpha = FLIP fraction)
///          x_p <- x_p + dt sum S v*
///   L_p = sum_i v^L_i (x) grad S_ip,  F <- (I + L dt) F,  V = V0 det F, then the material style.
///   USL: v^L = v*. MUSL (Sulsky et al. 1995): the updated particle momenta are projected again
///   (v**), v^L = v**. USF: L from v before the force is computed with the new stress.
///   midpoint: the USL step, with e from the power of the grid force V_n (sigma_n - q_n I) : L(v_mid),
///   v_mid = (v + v*)/2, and the transfer kinetic-energy fix-up (energy_budget.hpp).
///   q = rho (A1 c_bulk |tr D| h + A2 (tr D h)^2) if tr D < 0 else 0 (Uintah; mpm.md §1.5)
///   dt = C min(h) / max_p (s_p + |v_p|), capped by dt_max; s = c_dil, or with the viscosity acting
///   s = Q + sqrt(Q^2 + c_dil^2), Q = A2 h |tr D| (material_update.cpp).
///
/// Deterministic parallel scatter: particles are binned every step into blocks of 4^3 cells
/// (counting sort, stable in particle index); P2G runs over the 8 block colours in turn, blocks
/// of one colour in parallel (their node footprints are disjoint), particles of a block in index
/// order, so every nodal sum is accumulated in the same order for any thread count. Reductions
/// use fixed chunks summed in chunk order. Results are bit-identical for any OMP_NUM_THREADS.
///
/// Bodies share one velocity field (no contact algorithm): bodies that meet stick
/// (mpm.md §1.7). A particle whose stencil leaves the grid stops the run (SolverFailure with
/// state_intact = true, before anything is modified), or, with `outflow_remove`, is taken out of
/// the grid computation (outflow.cpp): from then on it moves ballistically (no stress, no grid
/// force: material that has left a domain drawn well around the bodies is free ejecta), its
/// record is kept (outflow_snapshot()) and its mass, momentum, angular momentum and energies stay
/// in diagnostics(), which therefore still measure conservation of the whole system.
///
/// Implementation, one file per stage in mpm/src/solver/: step.cpp (construction, initialize,
/// stable_dt, the USL/MUSL/USF schedule, save_backup), binning.cpp (bin, reorder, chunks),
/// transfer.cpp (P2G, G2P, MUSL re-projection), grid.cpp (make_grid, grid velocity and update,
/// boundary conditions), drive.cpp (velocity-driven bodies), material_update.cpp (style call,
/// energy, artificial viscosity),
/// outflow.cpp, diagnostics.cpp; shared kernels in kernels.hpp. Scene names of the choices are the
/// tables kSchemes and kBoundaryTypes below.
///
/// Subdomains (MPI domain decomposition, mpm/mpi/domain.hpp): a Solver may hold only a box of the
/// global grid (Subdomain: global index `lo` of its node 0 and its node `shape`) and the particles
/// whose stencils lie in it. Weights are still computed against the global grid origin (stencil
/// node indices are global; the local index is the global one minus Subdomain::lo, one constant
/// `shift_` per linear index), so a particle's weights do not depend on the decomposition. The
/// GridExchange completes the nodal sums of nodes shared with other processes after every P2G
/// pass and reduces the few scalars the step needs (dt, m_min, failures) over all processes.
/// Without a Subdomain (the serial build and mpm-frag) the box is the whole grid and nothing is
/// exchanged; the serial library contains no MPI code.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "common/choice.hpp"
#include "common/field.hpp"
#include "common/grid.hpp"
#include "common/status.hpp"
#include "mpm/body_drive.hpp"
#include "mpm/particles.hpp"
#include "mpm/shape_functions.hpp"

namespace common {
struct ParticleSnapshot;  // common/particle_file.hpp (include it to call Solver::outflow_snapshot)
}

namespace mpmfrag {

class GridExchange;  // below

/// The box of the global grid that one process of a domain decomposition holds (see the file
/// comment). Default (exchange == nullptr): the whole grid, no exchange.
struct Subdomain {
  Eigen::Vector3i lo = Eigen::Vector3i::Zero();     ///< global index of local node (0,0,0)
  Eigen::Vector3i shape = Eigen::Vector3i::Zero();  ///< local nodes per axis
  GridExchange* exchange = nullptr;                 ///< completes shared nodes, global reductions
  /// The nodes [own_lo, own_hi) (global, per axis) this process owns, for sums over nodes that
  /// count each node once (drive reactions); owns_all: every node held (no decomposition).
  bool owns_all = true;
  Eigen::Vector3i own_lo = Eigen::Vector3i::Zero(), own_hi = Eigen::Vector3i::Zero();
};

/// Stress-update order.
enum class Scheme { usl, usf, musl, midpoint };
/// Scene names of the schemes (`solver.scheme`): the one table the schema and the log use.
inline constexpr std::array kSchemes{common::Choice{"usl", Scheme::usl}, common::Choice{"usf", Scheme::usf},
                                     common::Choice{"musl", Scheme::musl},
                                     common::Choice{"midpoint", Scheme::midpoint}};
/// Grid face condition.
enum class BoundaryType { free, fixed, symmetry };
/// Scene names of the face conditions (`boundary.<face>`).
inline constexpr std::array kBoundaryTypes{common::Choice{"free", BoundaryType::free},
                                           common::Choice{"fixed", BoundaryType::fixed},
                                           common::Choice{"symmetry", BoundaryType::symmetry}};

/// Which of a grid node's two velocity slots a stage reads or constrains (Solver::Node):
/// the grid velocity v_i (MUSL: the re-projected v**_i) or the updated velocity v*_i;
/// `midpoint` (only in G2P): L from v*_i as USL, and the energy from L at (v_i + v*_i)/2.
enum class GridSlot { velocity, updated_velocity, midpoint };


/// Solver options (scene keys under [solver], [boundary], [time], [grid] and gravity.uniform).
struct SolverConfig {
  ShapeKind shape = ShapeKind::ugimp;
  Scheme scheme = Scheme::musl;
  double flip = 1.0;                 ///< FLIP fraction alpha in [0,1]
  double courant = 0.3;              ///< C in dt = C h / (s + |v|), s the signal speed
  double dt_max = std::numeric_limits<double>::infinity();  ///< cap on dt [s]
  /// m_min = fraction * smallest particle mass; nodes with m <= m_min get no acceleration. Any
  /// m_min > 0 discards the force on those nodes, so momentum is then conserved only to ~1e-6.
  double min_mass_fraction = 0.0;
  bool artificial_viscosity = false;
  double av_a1 = 0.2, av_a2 = 2.0;
  /// x-, x+, y-, y+, z-, z+
  std::array<BoundaryType, 6> boundary{BoundaryType::free, BoundaryType::free, BoundaryType::free,
                                       BoundaryType::free, BoundaryType::free, BoundaryType::free};
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  ///< [m/s^2]
  int ghost_layers = 2;              ///< node layers outside the domain on each side
  std::uint64_t seed = 0;
  int reorder_every = 25;            ///< steps between particle re-sorting (locality); 0 = never
  bool outflow_remove = false;       ///< particles leaving the grid: stop (false) or remove (true)
};

/// Grid covering [lo, hi] with cubic cells of size h plus `ghost` node layers on each side;
/// the domain faces lie on nodes `ghost` and `shape-1-ghost`.
common::GridInfo make_grid(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double h, int ghost);

/// Conserved / monitored totals.
struct Diagnostics {
  double mass = 0;
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_momentum = Eigen::Vector3d::Zero();  ///< about the origin
  double kinetic = 0, internal = 0;
  // The parts of `internal` (energy_budget.hpp) [J]: deviatoric stress work, shock (artificial
  // viscosity) heating, transfer heating; stored deviatoric elastic energy and plastic/granular
  // dissipation reported by the material styles.
  double work_dev = 0, heat_shock = 0, heat_transfer = 0, elastic = 0, dissipated = 0;
  std::size_t removed = 0;   ///< particles that left the grid (included in the totals above)
  double removed_mass = 0;   ///< their mass [kg]
  double total() const { return kinetic + internal; }
};

/// A numerical failure inside a step. `state_intact`: the particle state is still that of the
/// last completed step (e.g. a particle left the grid, detected before any update).
class SolverFailure : public common::NumericalError {
 public:
  SolverFailure(const std::string& what, bool intact) : common::NumericalError(what), state_intact(intact) {}
  bool state_intact;
};

/// Per-particle external acceleration callback: write 3*(end-begin) values [m/s^2] for
/// particles [begin, end) at time t (used by the manufactured-solution tests).
using BodyForce = std::function<void(std::size_t begin, std::size_t end, double t,
                                     const ParticleSet& ps, double* accel)>;

/// Copy of the particle state of a completed step (the "last good state").
struct Backup {
  ParticleSet particles;
  std::vector<MaterialSlot> materials;
  double time = 0;
  std::int64_t step = 0;
  bool valid = false;
};

/// The solver's state outside its particles and material state arrays that later steps read.
/// A checkpoint (mpm/checkpoint.hpp) saves it with them, and Solver::resume() (instead of
/// initialize()) continues bit-identically. A Solver member that carries over from one step to
/// the next (an accumulator, a running maximum) belongs here and in resume_state()/resume().
struct SolverResume {
  double time = 0;
  std::int64_t step = 0;
  double max_speed = 0;      ///< max (s + |v|) of the last update: the next stable_dt() [m/s]
  double min_node_mass = 0;  ///< m_min, fixed at construction from that run's particles [kg]
  ParticleSet outflow;       ///< the outflow record (core arrays at removal)
  std::vector<double> outflow_time;         ///< removal times [s]
  std::vector<common::Field> outflow_fields;  ///< output state fields of the removed particles
  std::vector<double> outflow_init;         ///< initial value of each of those fields
  Diagnostics outflow_totals;               ///< totals of the removed particles
  std::vector<DriveLoad> drive_loads;       ///< load of each drive (Solver::set_drives order)
};

class Solver {
 public:
  /// `materials[m]` holds the particles [begin, end) with ParticleSet::material == m; the state
  /// arrays are allocated here. Throws common::InputError on inconsistent input.
  /// `sub`: hold only a box of `grid` (domain decomposition; then a process may have no
  /// particles, drives are refused with common::InputError; with outflow_remove each process
  /// removes its own particles and may be left with none).
  Solver(SolverConfig cfg, common::GridInfo grid, ParticleSet particles,
         std::vector<MaterialSlot> materials, Subdomain sub = {});

  /// Initial stress and wave speeds (material initialize); call once before step().
  void initialize();
  /// Largest stable dt for the next step: C h / max(c + |v|), capped by dt_max.
  double stable_dt() const;
  /// Advance by `dt` (the caller passes min(stable_dt(), time to the next output)).
  /// Throws SolverFailure.
  void step(double dt);
  /// Copy the current state into the backup (cheap relative to a step when done every ~20 steps).
  void save_backup();
  const Backup& backup() const { return backup_; }
  /// The carried state (SolverResume) of the current step.
  SolverResume resume_state() const;
  /// Continue a checkpointed run: the solver was constructed with the checkpoint's particles and
  /// material state; `s` restores the rest. Call instead of initialize().
  void resume(SolverResume s);

  double time() const { return time_; }
  std::int64_t step_count() const { return step_; }
  void set_time(double t, std::int64_t step) { time_ = t; step_ = step; }
  const ParticleSet& particles() const { return ps_; }
  ParticleSet& particles_mutable() { return ps_; }
  const std::vector<MaterialSlot>& materials() const { return mats_; }
  /// The global grid (a subdomain holds the box subdomain() of it).
  const common::GridInfo& grid() const { return grid_; }
  const Subdomain& subdomain() const { return sub_; }
  /// Domain decomposition: move to another box of the same global grid (rebalancing), between
  /// steps; every particle's stencil must lie in the new box (the caller migrates first).
  void set_subdomain(const Subdomain& sub);
  /// Domain decomposition: replace the particles and material state (after migration). Each
  /// material's particles must be contiguous (MaterialSlot ranges) and their state arrays sized.
  void replace_particles(ParticleSet particles, std::vector<MaterialSlot> materials);
  const SolverConfig& config() const { return cfg_; }
  void set_body_force(BodyForce f) { body_force_ = std::move(f); }
  /// Velocity-driven bodies (body_drive.hpp): set before initialize() or resume(). Sets the
  /// particles of each body to v_T(t). Throws common::InputError on overlapping id ranges.
  void set_drives(std::vector<BodyDrive> drives);
  const std::vector<BodyDrive>& drives() const { return drives_; }
  /// The load of each drive on the rest of the system (body_drive.hpp), set_drives order.
  const std::vector<DriveLoad>& drive_loads() const { return drive_load_; }
  /// Totals (deterministic chunked sums).
  Diagnostics diagnostics() const;
  /// Bytes of per-particle storage (particles + material state) divided by the particle count.
  double bytes_per_particle() const;
  /// Bytes of the grid.
  std::size_t grid_bytes() const;
  /// Whether the last stable_dt() was limited by dt_max.
  bool dt_capped() const { return dt_capped_; }
  /// Particles removed at the grid edge (SolverConfig::outflow_remove), in removal order, with
  /// positions moved ballistically to the current time, dataset `removal_time` [s], their stress,
  /// internal energy and output state fields at removal. Empty when none left the grid.
  common::ParticleSnapshot outflow_snapshot() const;
  std::size_t outflow_count() const { return out_.size(); }

  /// Node record (one cache line, 64 bytes: grid_bytes() = 64 per node). Each of the two
  /// 3-vectors holds two quantities in turn during a step; stages use the accessor named for
  /// the quantity of their phase (the storage is shared so that the node stays one cache line):
  ///
  ///   phase (Solver::step)           momentum_or_velocity       force_or_updated_velocity
  ///   P2G scatter                    momentum()  (m v)_i        force()  f_i
  ///   grid_velocity()                velocity()  v_i = (mv)_i/m_i
  ///   grid_integrate()                                          updated_velocity()  v*_i
  ///   MUSL musl_remap()              momentum()  re-projected (m v)_i from the new v_p
  ///   MUSL grid_velocity()           velocity()  v**_i
  ///
  /// slot(GridSlot) picks a velocity slot by name for the boundary conditions and G2P.
  struct alignas(64) Node {
    double m;                             ///< nodal mass m_i [kg]
    double momentum_or_velocity[3];       ///< (m v)_i [kg m/s], then v_i [m/s]
    double force_or_updated_velocity[3];  ///< f_i [N], then v*_i [m/s]
    double pad;                           ///< to 64 bytes

    double* momentum() { return momentum_or_velocity; }
    double* velocity() { return momentum_or_velocity; }
    const double* velocity() const { return momentum_or_velocity; }
    double* force() { return force_or_updated_velocity; }
    double* updated_velocity() { return force_or_updated_velocity; }
    const double* updated_velocity() const { return force_or_updated_velocity; }
    /// The velocity slot `s` (v_i or v*_i) as a member pointer.
    using Slot3 = double (Node::*)[3];
    static constexpr Slot3 slot(GridSlot s) {
      return s == GridSlot::velocity ? &Node::momentum_or_velocity : &Node::force_or_updated_velocity;
    }
  };
  static_assert(sizeof(Node) == 64, "Node must stay one cache line");

 private:
  template <int NPA> void bin();
  template <int NPA, int MODE> void scatter();
  void grid_velocity();
  void grid_integrate(double dt);
  /// Boundary conditions (fixed / symmetry faces, SolverConfig::boundary) on velocity slot `s`.
  void apply_bc(GridSlot s);
  /// Drives (drive.cpp): reset the driven particles to v_T(time_) and list the nodes C_k.
  void drive_prepare();
  /// Constrain velocity slot `s` of the nodes C_k to v_T(t); `record` 1: this is v_i (keep
  /// sum m c1), 2: this is v*_i (sum m c2, then the step's DriveLoad), 0: nothing recorded.
  void apply_drive(GridSlot s, double t, int record, double dt);
  /// Index of the drive holding particle id `id`, or -1.
  int drive_of(std::uint64_t id) const {
    for (std::size_t k = 0; k < drives_.size(); ++k)
      if (drives_[k].holds(id)) return static_cast<int>(k);
    return -1;
  }
  /// G2P; `flags` (detail::G2P) selects what is updated, `Lfrom` the grid velocity of L.
  template <int NPA, int flags, GridSlot Lfrom> void g2p(double dt);
  template <int NPA> void musl_remap();
  void reorder();
  void build_chunks();
  /// Move the particles flagged in `out` to the outflow record and compact every array.
  void remove_particles(const std::vector<char>& out);
  /// The style's stored_energies() of particles [begin, begin + n) of material `mat` into el, di.
  void material_energies(std::size_t mat, std::size_t begin, std::size_t n, double* el, double* di) const;
  /// Material update of chunk c. `econs` (scheme midpoint, from G2P): per particle the specific
  /// energy increment of the force power, its deviatoric and its artificial-viscosity part.
  void run_material_chunk(std::size_t c, double dt, const double* L, double* wpre, double* ws, double* bs,
                          const double* econs = nullptr);

  /// Largest value over all processes (the local value without a GridExchange).
  double global_max(double v) const;
  /// Whether any process has `local` set (collective with a GridExchange).
  bool any_process(bool local) const { return global_max(local ? 1.0 : 0.0) > 0.0; }

  SolverConfig cfg_;
  common::GridInfo grid_;  ///< the global grid
  Subdomain sub_;          ///< the box held (the whole grid when serial)
  std::size_t shift_ = 0;  ///< global linear node index of local node 0 (stencil base - shift_)
  ParticleSet ps_;
  std::vector<MaterialSlot> mats_;
  std::vector<Node> nodes_;
  double h_min_ = 0, m_min_ = 0;
  double time_ = 0;
  std::int64_t step_ = 0;
  double max_speed_ = 0;   ///< max (s + |v|) of the last update
  mutable bool dt_capped_ = false;
  BodyForce body_force_;
  std::vector<double> body_accel_;
  std::vector<double> mom2_;  ///< MUSL re-projected nodal momentum (3 per node)
  // velocity drives (drive.cpp)
  std::vector<BodyDrive> drives_;
  std::vector<DriveLoad> drive_load_;
  std::vector<double> drive_mass_;                 ///< M_k [kg]
  std::vector<std::vector<std::size_t>> drive_nodes_;  ///< C_k of the current step
  std::vector<std::int32_t> node_drive_;           ///< per node: drive index, or -1
  std::vector<Eigen::Vector3d> drive_c1_;          ///< sum m_i c1_i of the current step

  // binning
  Eigen::Vector3i nblocks_;
  std::vector<std::uint32_t> key_;
  std::vector<char> out_flag_;  ///< particles outside the grid (outflow_remove only)
  bool rebinning_ = false;      ///< bin() binning again after removing particles (no reduction)
  std::vector<std::uint32_t> order_;
  std::vector<std::uint32_t> block_start_;
  std::array<std::vector<std::uint32_t>, 8> colour_blocks_;
  // chunks over material ranges
  struct Chunk {
    std::size_t begin, end;
    int mat;
  };
  std::vector<Chunk> chunks_;
  std::vector<double> chunk_speed_;
  std::vector<std::size_t> chunk_fail_;
  std::vector<std::string> chunk_msg_;
  Backup backup_;
  // outflow record (outflow.cpp)
  ParticleSet out_;                     ///< removed particles (core arrays at removal)
  std::vector<double> out_time_;        ///< removal times [s]
  std::vector<common::Field> out_fields_;  ///< output state fields of the removed particles
  std::vector<double> out_init_;        ///< initial value of each of those fields
  Diagnostics out_diag_;                ///< their totals (constant in ballistic flight)
};

/// Communication of a Solver that holds a Subdomain (implemented in mpm/mpi/ for MPI; the serial
/// library only calls it). Every method is collective over the processes of the decomposition.
class GridExchange {
 public:
  virtual ~GridExchange() = default;
  /// After a P2G pass: make every node that other processes also hold carry the complete sum
  /// over all processes of the fields `fields` (OR of 1 mass, 2 momentum, 4 force: the P2G
  /// bits of the step), identical in every bit on every process that holds the node.
  virtual void sum_shared(Solver::Node* nodes, int fields) = 0;
  /// Element-wise maximum over all processes of v[0..n), in place.
  virtual void max(double* v, int n) = 0;
  /// Element-wise sum over all processes of v[0..n), in place, the same bits on every process
  /// (a fixed order of the processes).
  virtual void sum(double* v, int n) = 0;
  /// Velocity drives (body_drive.hpp): make node_drive (per local node, the index of the drive
  /// constraining it or -1) the same on every process that holds the node, the smallest
  /// non-negative value of the processes; append to `added` each local node that had -1 here and
  /// now has a drive.
  virtual void min_shared_drive(std::int32_t* node_drive, std::vector<std::size_t>& added) = 0;
};

}  // namespace mpmfrag
