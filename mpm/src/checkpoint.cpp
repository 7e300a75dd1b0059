/// @file checkpoint.cpp
/// mpm-frag checkpoint files (layout and contract in checkpoint.hpp): reading, and the totals
/// packing shared with the writer (checkpoint_write.cpp).
#include "mpm/checkpoint.hpp"

#include <algorithm>
#include <stdexcept>
#include <type_traits>

#include "common/h5.hpp"
#include "common/particle_file.hpp"
#include "common/status.hpp"
#include "mpm/checkpoint_rows.hpp"

namespace mpmfrag {
namespace {

namespace h5 = common::h5;
constexpr const char* kFormat = kCheckpointFormat;
constexpr std::int64_t kVersion = kCheckpointVersion;
constexpr std::size_t kTotals = 16;

}  // namespace

std::vector<double> pack_totals(const Diagnostics& d) {
  return {d.mass,
          d.momentum[0],
          d.momentum[1],
          d.momentum[2],
          d.angular_momentum[0],
          d.angular_momentum[1],
          d.angular_momentum[2],
          d.kinetic,
          d.internal,
          static_cast<double>(d.removed),
          d.removed_mass,
          d.work_dev,
          d.heat_shock,
          d.heat_transfer,
          d.elastic,
          d.dissipated};
}
Diagnostics unpack_totals(const std::vector<double>& v) {
  Diagnostics d;
  d.mass = v[0];
  d.momentum = Eigen::Vector3d(v[1], v[2], v[3]);
  d.angular_momentum = Eigen::Vector3d(v[4], v[5], v[6]);
  d.kinetic = v[7];
  d.internal = v[8];
  d.removed = static_cast<std::size_t>(v[9]);
  d.removed_mass = v[10];
  d.work_dev = v[11];
  d.heat_shock = v[12];
  d.heat_transfer = v[13];
  d.elastic = v[14];
  d.dissipated = v[15];
  return d;
}

namespace {

Diagnostics unpack_totals(const std::vector<double>& v, const std::string& file, const std::string& name) {
  if (v.size() != kTotals) throw common::InputError(file, "/mpm_state", name + " must hold " + std::to_string(kTotals) + " numbers");
  return mpmfrag::unpack_totals(v);
}

std::string unpack_bytes(const std::vector<std::uint64_t>& w, std::size_t n) {
  std::string s(n, '\0');
  for (std::size_t i = 0; i < n; ++i) s[i] = static_cast<char>((w[i / 8] >> (8 * (i % 8))) & 0xff);
  return s;
}

template <class T>
std::vector<T> read_array(hid_t f, const std::string& name, long long rows, std::size_t cols, const std::string& file,
                          const h5::RowRange& range) {
  if constexpr (std::is_same_v<T, double>)
    return h5::read_doubles(f, name, rows, cols, file, range);
  else if constexpr (std::is_same_v<T, std::uint64_t>)
    return h5::read_u64(f, name, rows, cols, file, range);
  else
    return h5::read_i32(f, name, rows, cols, file, range);
}

/// Rows `range` of every ParticleSet array under `group` (n rows each).
ParticleSet read_set(hid_t f, const std::string& group, long long n, const std::string& file, const h5::RowRange& range) {
  ParticleSet ps;
  ParticleSet::for_each_array([&](const auto& a) {
    using T = typename std::decay_t<decltype(a)>::element_type;
    const std::string name = group + "/" + a.info.name;
    if (a.info.optional && !h5::exists(f, name)) return;
    ps.*a.member = read_array<T>(f, name, n, static_cast<std::size_t>(a.info.width), file, range);
  });
  return ps;
}
long long rows_of(hid_t f, const std::string& name, const std::string& file) {
  const std::vector<hsize_t> s = h5::shape(f, name, file);
  if (s.empty()) throw common::InputError(file, name, "is a scalar, expected an array");
  return static_cast<long long>(s[0]);
}
std::size_t cols_of(hid_t f, const std::string& name, const std::string& file) {
  const std::vector<hsize_t> s = h5::shape(f, name, file);
  return s.size() >= 2 ? static_cast<std::size_t>(s[1]) : 1;
}

/// Read /mpm_state of the open checkpoint `f` into `ck`: the scalars, `part`'s rows of the
/// particles and of each material's state, and (part.records) the outflow record and series.
void read_mpm_state(hid_t f, const std::string& path, const CheckpointPart& part, Checkpoint& ck) {
  h5::Handle g = h5::open_group(f, "mpm_state", path);
  if (!h5::has_attr(g, "format") || h5::read_attr_string(g, "format", path) != kFormat)
    throw common::InputError(path, "/mpm_state", std::string("format is not ") + kFormat);
  const std::int64_t version = h5::read_attr_int(g, "format_version", path);
  if (version > kVersion)
    throw common::InputError(path, "/mpm_state", "format_version " + std::to_string(version) +
                                                     " is newer than this mpm-frag reads (" + std::to_string(kVersion) + ")");
  SolverResume& r = ck.solver;
  r.step = h5::read_attr_int(g, "step", path);
  r.time = h5::read_attr_double(g, "time", path);
  r.max_speed = h5::read_attr_double(g, "max_speed", path);
  r.min_node_mass = h5::read_attr_double(g, "min_node_mass", path);
  ck.driver.next_snapshot = h5::read_attr_double(g, "next_snapshot", path);
  ck.driver.first_dt = h5::read_attr_double(g, "first_dt", path);
  ck.driver.min_dt = h5::read_attr_double(g, "min_dt", path);
  ck.driver.max_dt = h5::read_attr_double(g, "max_dt", path);
  ck.driver.initial = unpack_totals(h5::read_attr_doubles(g, "initial_totals", path), path, "initial_totals");
  r.outflow_totals = unpack_totals(h5::read_attr_doubles(g, "outflow_totals", path), path, "outflow_totals");
  if (h5::has_attr(g, "drive_loads")) {
    const std::vector<double> dl = h5::read_attr_doubles(g, "drive_loads", path);
    if (dl.size() % 6 != 0) throw common::InputError(path, "/mpm_state", "drive_loads is not 6 numbers per drive");
    for (std::size_t k = 0; k < dl.size(); k += 6)
      r.drive_loads.push_back({Eigen::Vector3d(dl[k], dl[k + 1], dl[k + 2]), Eigen::Vector3d(dl[k + 3], dl[k + 4], dl[k + 5])});
  }
  ck.identity = h5::read_attr_string(g, "run_identity", path);
  const long long n = rows_of(f, "/mpm_state/particles/id", path);
  // this part's rows [first, last) of the particles
  const std::size_t nn = static_cast<std::size_t>(n), parts = static_cast<std::size_t>(part.count);
  const std::size_t first = nn * static_cast<std::size_t>(part.index) / parts;
  const std::size_t last = nn * static_cast<std::size_t>(part.index + 1) / parts;
  ck.first = first;
  ck.total = nn;
  ck.particles = read_set(f, "/mpm_state/particles", n, path, {first, last - first});
  const std::int64_t nm = h5::read_attr_int(g, "material_count", path);
  if (nm < 1 || nm > 1 << 16) throw common::InputError(path, "/mpm_state", "material_count out of range");
  std::size_t next = 0;
  for (std::int64_t m = 0; m < nm; ++m) {
    const std::string sp = "/mpm_state/materials/" + std::to_string(m);
    h5::Handle sg = h5::open_group(f, sp, path);
    MaterialState ms;
    ms.name = h5::read_attr_string(sg, "name", path);
    const std::int64_t b = h5::read_attr_int(sg, "begin", path), e = h5::read_attr_int(sg, "end", path);
    if (b != static_cast<std::int64_t>(next) || e < b || e > n)
      throw common::InputError(path, sp, "particle range [begin, end) does not continue the previous material's");
    next = static_cast<std::size_t>(e);
    // its rows among this part's, relative to the part
    const std::size_t lb = std::clamp(static_cast<std::size_t>(b), first, last), le = std::clamp(next, first, last);
    // the part's rows within the material's [b, e) (none if they do not meet): its state rows
    const std::size_t lo = std::clamp(first, static_cast<std::size_t>(b), next);
    const std::size_t hi = std::clamp(last, static_cast<std::size_t>(b), next);
    ms.begin = lb - first;
    ms.end = le - first;
    H5G_info_t info;
    H5Gget_info(sg, &info);
    for (hsize_t k = 0; k < info.nlinks; ++k) {
      char name[256] = {0};
      H5Lget_name_by_idx(sg, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT);
      const std::string ds = sp + "/" + name;
      ms.fields.emplace_back(name, h5::read_doubles(f, ds, e - b, cols_of(f, ds, path), path,
                                                    {lo - static_cast<std::size_t>(b), hi - lo}));
    }
    ck.materials.push_back(std::move(ms));
  }
  if (next != static_cast<std::size_t>(n))
    throw common::InputError(path, "/mpm_state/materials", "the materials' ranges do not cover every particle");
  // the outflow record: this part's rows of it (the same split as the particles')
  const long long no = rows_of(f, "/mpm_state/outflow/removal_time", path);
  const std::size_t ofirst = static_cast<std::size_t>(no) * static_cast<std::size_t>(part.index) / parts;
  const h5::RowRange orows{ofirst, static_cast<std::size_t>(no) * static_cast<std::size_t>(part.index + 1) / parts - ofirst};
  r.outflow = read_set(f, "/mpm_state/outflow/particles", no, path, orows);
  r.outflow_time = h5::read_doubles(f, "/mpm_state/outflow/removal_time", no, 1, path, orows);
  h5::Handle fg = h5::open_group(f, "/mpm_state/outflow/fields", path);
  H5G_info_t info;
  H5Gget_info(fg, &info);
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    const std::string ds = "/mpm_state/outflow/fields/" + std::to_string(k);
    h5::Handle d(H5Dopen2(f, ds.c_str(), H5P_DEFAULT));
    if (!d.valid()) throw common::InputError(path, ds, "dataset is missing");
    const std::size_t nc = cols_of(f, ds, path);
    r.outflow_fields.push_back({h5::read_attr_string(d, "name", path), h5::unit_of(f, ds), nc,
                                h5::read_doubles(f, ds, no, nc, path, orows), h5::read_attr_string(d, "description", path)});
    r.outflow_init.push_back(h5::read_attr_double(d, "initial", path));
  }
  if (!part.records) return;  // the series: one process reads it
  const std::int64_t bytes = h5::read_attr_int(g, "series_bytes", path);
  const std::vector<std::uint64_t> words = h5::read_u64(f, "/mpm_state/series", -1, 1, path);
  if (bytes < 0 || static_cast<std::uint64_t>(bytes) > 8 * words.size())
    throw common::InputError(path, "/mpm_state/series", "series_bytes exceeds the stored words");
  ck.driver.series = unpack_bytes(words, static_cast<std::size_t>(bytes));
}

}  // namespace

Checkpoint read_checkpoint(const std::string& path, const common::H5Hook& extra) {
  Checkpoint ck;
  bool found = false;
  auto hook = [&](long long fid) {
    const hid_t f = static_cast<hid_t>(fid);
    if (!h5::exists(f, "mpm_state")) return;
    found = true;
    read_mpm_state(f, path, CheckpointPart{}, ck);
    if (extra) extra(fid);
  };
  const common::ParticleSnapshot snap = common::read_particle_snapshot(path, hook);
  if (!found) throw common::InputError(path + ": not an mpm-frag checkpoint (no /mpm_state group)");
  if (snap.count() != ck.particles.size() || snap.step != ck.solver.step)
    throw common::InputError(path + ": /mpm_state does not match the snapshot it accompanies");
  return ck;
}

Checkpoint read_checkpoint_part(const std::string& path, const CheckpointPart& part, const PartHook& extra) {
  if (part.count < 1 || part.index < 0 || part.index >= part.count)
    throw std::logic_error("read_checkpoint_part: part index outside [0, count)");
  h5::Handle f = h5::open_file_read(path);
  if (!h5::exists(f, "mpm_state")) throw common::InputError(path + ": not an mpm-frag checkpoint (no /mpm_state group)");
  Checkpoint ck;
  read_mpm_state(f, path, part, ck);
  // the snapshot part (not read here) must describe the same state
  if (static_cast<std::size_t>(rows_of(f, "/particles/id", path)) != ck.total || h5::read_attr_int(f, "step", path) != ck.solver.step)
    throw common::InputError(path + ": /mpm_state does not match the snapshot it accompanies");
  if (extra) extra(f, ck);
  return ck;
}

void apply_materials(const Checkpoint& ck, std::vector<MaterialSlot>& mats, const std::string& path) {
  if (ck.materials.size() != mats.size())
    throw common::InputError(path + ": checkpoint has " + std::to_string(ck.materials.size()) +
                             " materials, the scene " + std::to_string(mats.size()));
  for (std::size_t m = 0; m < mats.size(); ++m) {
    MaterialSlot& s = mats[m];
    const MaterialState& c = ck.materials[m];
    if (c.name != s.name)
      throw common::InputError(path + ": material " + std::to_string(m) + " is '" + c.name + "', the scene's '" + s.name + "'");
    // a cost-weight field (StateField::work) may be missing: a checkpoint from before it existed
    std::size_t need = 0;
    for (const StateField& sf : s.style->state_fields) need += sf.work > 0.0 ? 0 : 1;
    if (c.fields.size() < need || c.fields.size() > s.style->state_fields.size())
      throw common::InputError(path + ": material '" + s.name + "' has " + std::to_string(c.fields.size()) +
                               " state fields, its style " + std::to_string(s.style->state_fields.size()));
    s.begin = c.begin;
    s.end = c.end;
    s.state.assign(s.style->state_fields.size(), {});
    for (std::size_t k = 0; k < s.state.size(); ++k) {
      const StateField& sf = s.style->state_fields[k];
      auto it = std::find_if(c.fields.begin(), c.fields.end(), [&](const auto& p) { return p.first == sf.name; });
      if (it == c.fields.end() && sf.work > 0.0) {
        s.state[k].assign((c.end - c.begin) * static_cast<std::size_t>(sf.ncomp), sf.initial);
        continue;
      }
      if (it == c.fields.end() || it->second.size() != (c.end - c.begin) * static_cast<std::size_t>(sf.ncomp))
        throw common::InputError(path + ": material '" + s.name + "': state field '" + sf.name +
                                 "' missing or of the wrong size");
      s.state[k] = it->second;
    }
  }
}

}  // namespace mpmfrag
