/// @file sphere_file.hpp
/// Sphere-set file (written by mpm2spheres and ssdem-grav, read by ssdem-grav):
///
///   / attrs: format = "ssdem.spheres", format_version, time [s], step
///   /spheres: id (uint64 N), position (N x 3, m), velocity (N x 3, m/s),
///             spin (N x 3 angular velocity, rad/s), mass (N, kg), radius (N, m),
///             optional damage (N, 1) and other per-sphere fields
///   /bonds (optional): parallel bonds between spheres of the file, by ids (bond_file.hpp)
///   /provenance attrs: tool, version, git_sha, command_line, scene
/// Tools may add groups (hand-off audit and id map, contact history in checkpoints) through
/// the extra hook. Every dataset has a `unit` attribute; XDMF sidecar beside it.
/// The core arrays are enumerated once, in SphereSet::zip_arrays (name, unit, type, width);
/// the writer, the reader, the size checks and the XDMF sidecar all go through it.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/bond_file.hpp"
#include "common/field.hpp"
#include "common/particle_file.hpp"
#include "common/provenance.hpp"

namespace common {

inline constexpr const char* kSphereFormat = "ssdem.spheres";
inline constexpr std::int64_t kSphereFormatVersion = 1;

/// Element type of a sphere array.
enum class SphereScalar { UInt64, Float64 };

/// Descriptor of one per-sphere array: HDF5 dataset `/spheres/<name>`, `width` values of type
/// `scalar` per sphere (1: a 1-D dataset of length N, else N x width).
struct SphereArray {
  const char* name;
  const char* unit;       ///< SI unit; "1" for ids and dimensionless values
  SphereScalar scalar = SphereScalar::Float64;
  std::size_t width = 1;
  bool positive = false;  ///< the reader requires every value > 0
  bool geometry = false;  ///< the XDMF geometry (positions), not an attribute
  constexpr std::size_t bytes() const { return width * 8; }
};

/// The core arrays of every sphere file, in file order.
inline constexpr SphereArray kSphereId{"id", "1", SphereScalar::UInt64, 1};
inline constexpr SphereArray kSpherePosition{"position", "m", SphereScalar::Float64, 3, false, true};
inline constexpr SphereArray kSphereVelocity{"velocity", "m/s", SphereScalar::Float64, 3};
inline constexpr SphereArray kSphereSpin{"spin", "rad/s", SphereScalar::Float64, 3};
inline constexpr SphereArray kSphereMass{"mass", "kg", SphereScalar::Float64, 1, true};
inline constexpr SphereArray kSphereRadius{"radius", "m", SphereScalar::Float64, 1, true};

struct SphereSet {
  double time = 0.0;
  std::int64_t step = 0;
  std::vector<std::uint64_t> id;
  std::vector<double> position;  ///< N*3
  std::vector<double> velocity;  ///< N*3
  std::vector<double> spin;      ///< N*3
  std::vector<double> mass;      ///< N
  std::vector<double> radius;    ///< N
  std::vector<Field> fields;     ///< optional: damage, ...
  BondTable bonds;               ///< optional: /bonds (empty: the file has none)

  std::size_t count() const { return id.size(); }
  const Field* field(const std::string& name) const;

  /// The one list of the core arrays: f(const SphereArray&, std::vector<T>& of each set...) in
  /// file order, for any number of sets (zero: descriptors only). Adding a core array is one line here.
  template <class F, class... S>
  static constexpr void zip_arrays(F&& f, S&... s) {
    f(kSphereId, s.id...);
    f(kSpherePosition, s.position...);
    f(kSphereVelocity, s.velocity...);
    f(kSphereSpin, s.spin...);
    f(kSphereMass, s.mass...);
    f(kSphereRadius, s.radius...);
  }
  /// f(const SphereArray&, array) for each core array (flat: N * width values).
  template <class F>
  void for_each_array(F&& f) { zip_arrays(f, *this); }
  template <class F>
  void for_each_array(F&& f) const { zip_arrays(f, *this); }
  /// Size every core array for `n` spheres (N * width values; new entries are zero).
  void resize(std::size_t n) {
    for_each_array([n](const SphereArray& a, auto& v) { v.resize(n * a.width); });
  }
};

void write_sphere_set(const std::string& path, const SphereSet& s, const Provenance& prov,
                      const H5Hook& extra = {});
/// The content of a sphere file written into the open HDF5 file `file`: root attributes, this
/// process's rows `block` of every /spheres dataset, /bonds (only with the whole set in one
/// block), /provenance. write_sphere_set writes the whole set; the MPI writer
/// (common/mpi/sphere_file_mpi.hpp) gives each rank its block of the rows (every rank calls it,
/// with the same fields). False if a data write failed; throws IoError if a group or dataset
/// cannot be created.
bool write_sphere_content(long long file, const SphereSet& s, const Provenance& prov, const h5::RowBlock& block);
/// The XDMF sidecar of the sphere file `path` of `n` spheres (the fields and bonds of `s`).
void write_sphere_xdmf(const std::string& path, const SphereSet& s, std::size_t n);
/// The same for a file of `bonds` bonds (with the broken column if `broken`), whatever s.bonds
/// holds (the MPI writer: each rank holds a block of them).
void write_sphere_xdmf(const std::string& path, const SphereSet& s, std::size_t n, std::size_t bonds, bool broken);
/// Validates like read_particle_snapshot, plus positive radius and finite spin, and /bonds if
/// present (read_bonds: ids, ranges; InputError naming file, dataset and range).
SphereSet read_sphere_set(const std::string& path, const H5Hook& extra = {});
/// Rows [range.offset, range.offset + range.count) of a sphere file: one MPI rank's block, so that
/// no rank reads the whole file. The checks of read_sphere_set on those rows, except two that
/// span all rows and are the caller's: unique ids (across the blocks) and /bonds (not read).
SphereSet read_sphere_rows(const std::string& path, const h5::RowRange& range, const H5Hook& extra = {});
/// A sphere file's sphere count (the rows of /spheres/id) and whether it holds /bonds, from its
/// header and dataset shapes (no rows read).
struct SphereFileShape {
  std::size_t count = 0;
  bool bonds = false;
};
SphereFileShape sphere_file_shape(const std::string& path);

}  // namespace common
