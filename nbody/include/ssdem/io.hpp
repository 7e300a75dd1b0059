/// @file io.hpp
/// Sphere files and checkpoints of ssdem-grav.
///
/// Snapshots are `ssdem.spheres` files (common::write_sphere_set, XDMF sidecar) with the carried
/// per-sphere fields (e.g. damage from mpm2spheres). Checkpoints are the same format plus a group
///   /ssdem_state  attrs: step, time [s], gravity_step, dt [s], gravity_every, kn [N/m]
///                 a (N x 3, m/s^2), alpha (N x 3, rad/s^2), ag (N x 3, m/s^2; self-gravity only),
///                 a_prev, alpha_prev (N x 3; previous step, for the extrapolated predictor)
///                 history/{id_a, id_b (uint64 P), and one dataset per history field of the
///                          contact table (contact/table.hpp): n_old (P x 3, 1), S (P x 3, m),
///                          theta_r (P x 3, rad), theta_q (P, rad), ...}
///                 bonds/ (only with bonds; bonds.hpp): attrs released_energy [J] (the total),
///                          released_base [J] (BondSet::released_base);
///                          id_a, id_b (uint64 B), kn, ks (N/m^3), sigma_c, tau_c (Pa), radius,
///                          length0 (m), broken (0/1), Fs (B x 3, N), Mb (B x 3, N m), n_old (B x 3),
///                          Mt (N m), released (J: what each broken bond released; a file without
///                          it, written before 2026-12-05, keeps its total in released_energy)
/// written through the common::H5Hook extra-group mechanism. Wall contacts have
/// id_b = 0xFFFFFFFF00000000 + wall index. Together with positions, velocities and spins this is
/// the complete dynamic state: a restart continues bit-identically.
#pragma once
#include <string>

#include "common/provenance.hpp"
#include "common/sphere_file.hpp"
#include "ssdem/simulation.hpp"

namespace ssdem {

/// Convert to/from the common file structure: every array of Spheres::zip_arrays (the file's core
/// arrays by name, any other one as the per-sphere field of its name) and the carried fields.
common::SphereSet to_sphere_set(const Spheres& sp, double time, std::int64_t step);
Spheres from_sphere_set(const common::SphereSet& s);

/// Bonds of a file (common/bond_file.hpp) as a BondSet at rest (zero shear and moments, frame
/// normal from the positions of `sp`), and back (the file keeps ids, stiffness, strength,
/// geometry and the broken flags; the dynamic state stays in checkpoints).
BondSet from_bond_table(const common::BondTable& t, const Spheres& sp);
common::BondTable to_bond_table(const BondSet& b);

/// Snapshot (state of the spheres, and the bonds with their broken flags if `bonds` is given
/// and not empty: /bonds, drawn as lines by the XDMF sidecar).
void write_snapshot(const std::string& path, const Spheres& sp, double time, std::int64_t step,
                    const common::Provenance& prov, const BondSet* bonds = nullptr);
/// Checkpoint: snapshot + /ssdem_state.
/// `kn` is the resolved normal stiffness (the k_n rule depends on the state, so a restart must
/// reuse the value the run started with).
/// `identity`: the run's identity (common::RunIdentity::text()), stored as the attributes
/// /ssdem_state/run_identity and run_identity_digest ("" = not recorded).
void write_checkpoint(const std::string& path, const SimState& st, double dt, int gravity_every,
                      const common::Provenance& prov, double kn = 0.0, const std::string& identity = {});
/// What the /ssdem_state group records besides the state's arrays (write_state_group).
struct StateHeader {
  double dt = 0;
  int gravity_every = 1;
  double kn = 0;
  std::string identity;
  bool has_ag = false, has_prev = false, has_level = false;  ///< ag; a_prev, alpha_prev; level, tau_prev
};
/// The /ssdem_state group of a checkpoint, written into the open HDF5 file `file`: this process's
/// rows `sph` of the per-sphere arrays (st.a.size() rows of st.a, st.alpha, ...) and `hist` of the
/// history records (st.history), the attributes from st and h (the same on every process).
/// write_checkpoint writes the whole state; the MPI writer (mpi/io_mpi.hpp) each rank's blocks;
/// `bond` the rows of st.bonds (no bonds group when bond.total == 0), `bond_released` the run's
/// total released energy (BondSet::released_total of all the bonds). False if a data write
/// failed; IoError if a group or dataset cannot be created.
bool write_state_group(long long file, const SimState& st, const StateHeader& h, const common::h5::RowBlock& sph,
                       const common::h5::RowBlock& hist, const common::h5::RowBlock& bond, double bond_released);
/// Read a checkpoint; `dt`, `gravity_every` and `kn` return the values it was written with,
/// `identity` the recorded run identity text ("" for a checkpoint written without one).
SimState read_checkpoint(const std::string& path, double* dt = nullptr, int* gravity_every = nullptr,
                         double* kn = nullptr, std::string* identity = nullptr);
/// A checkpoint's sphere and history-record counts and whether it holds bonds (/bonds or a bond
/// state), from its header and dataset shapes (no rows read); InputError if it is not a checkpoint.
struct CheckpointShape {
  std::size_t spheres = 0, history = 0;
  bool bonds = false;
};
CheckpointShape checkpoint_shape(const std::string& path);
/// One MPI rank's part of a checkpoint without bonds: rows `spheres` of the spheres and of the
/// per-sphere state arrays, rows `history` of the contact history records (the scalars as
/// read_checkpoint). The checks of read_checkpoint on those rows; unique ids across the blocks
/// are the caller's (mpi/domain_sim.hpp). std::logic_error for a checkpoint with a bond state
/// (checkpoint_shape().bonds: read it whole).
SimState read_checkpoint_rows(const std::string& path, const common::h5::RowRange& spheres,
                              const common::h5::RowRange& history, double* dt = nullptr,
                              int* gravity_every = nullptr, double* kn = nullptr, std::string* identity = nullptr);

}  // namespace ssdem
