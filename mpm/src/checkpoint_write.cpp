/// @file checkpoint_write.cpp
/// Writing mpm-frag checkpoints (layout in checkpoint.hpp; the rows contract in
/// checkpoint_rows.hpp). Reading is in checkpoint.cpp.
#include <type_traits>

#include "common/finite.hpp"
#include "common/particle_file.hpp"
#include "common/run_identity.hpp"
#include "common/status.hpp"
#include "mpm/checkpoint.hpp"
#include "mpm/checkpoint_rows.hpp"
#include "mpm/output.hpp"

namespace mpmfrag {
namespace {

namespace h5 = common::h5;
constexpr const char* kFormat = kCheckpointFormat;
constexpr std::int64_t kVersion = kCheckpointVersion;

// The series text as little-endian uint64 words (the h5 wrappers write numbers, not byte strings).
std::vector<std::uint64_t> pack_bytes(const std::string& s) {
  std::vector<std::uint64_t> w((s.size() + 7) / 8, 0);
  for (std::size_t i = 0; i < s.size(); ++i)
    w[i / 8] |= static_cast<std::uint64_t>(static_cast<unsigned char>(s[i])) << (8 * (i % 8));
  return w;
}

// Every ParticleSet array under `group` (raw values; the optional arrays only if `optional`).
bool write_set(hid_t group, const ParticleSet& ps, const h5::RowBlock& block, bool optional) {
  bool ok = true;
  ParticleSet::for_each_array([&](const auto& a) {
    if (a.info.optional && !optional) return;
    const auto& v = ps.*a.member;
    const std::size_t w = static_cast<std::size_t>(a.info.width);
    if (v.size() != ps.size() * w)
      throw std::logic_error(std::string("checkpoint: array ") + a.info.name + " does not hold one row per particle");
    ok = h5::write_dataset_rows(group, a.info.name, v.data(), ps.size(), w, a.info.unit, block) && ok;
  });
  return ok;
}

}  // namespace

bool uses_optional_arrays(const ParticleSet& ps) {
  bool any = false;
  ParticleSet::for_each_array([&](const auto& a) { any = any || (a.info.optional && !(ps.*a.member).empty()); });
  return any;
}

CheckpointRows CheckpointRows::whole(const ParticleSet& ps, const std::vector<MaterialSlot>& mats, const SolverResume& r) {
  CheckpointRows rows;
  rows.particles = {0, ps.size(), H5P_DEFAULT};
  for (const MaterialSlot& s : mats) rows.slots.push_back({0, s.end - s.begin, H5P_DEFAULT});
  rows.outflow_total = r.outflow.size();
  rows.optional_arrays = uses_optional_arrays(ps);
  rows.outflow_optional = uses_optional_arrays(r.outflow);
  return rows;
}

bool write_mpm_state(hid_t f, const ParticleSet& ps, const std::vector<MaterialSlot>& mats, const SolverResume& r,
                     const DriverState& driver, const std::string& identity, const CheckpointRows& rows) {
  bool ok = true;
  // a dataset one process holds whole: rows [0, total) from the single writer, none elsewhere
  auto single = [&](std::size_t total) { return h5::RowBlock{0, total, rows.xfer}; };
  auto mine = [&](std::size_t n) { return rows.single_writer ? n : std::size_t{0}; };
  h5::Handle g = h5::create_group(f, "mpm_state");
  h5::write_attr(g, "format", std::string(kFormat));
  h5::write_attr(g, "format_version", kVersion);
  h5::write_attr(g, "step", static_cast<std::int64_t>(r.step));
  h5::write_attr(g, "time", r.time);
  h5::write_attr(g, "max_speed", r.max_speed);
  h5::write_attr(g, "min_node_mass", r.min_node_mass);
  h5::write_attr(g, "next_snapshot", driver.next_snapshot);
  h5::write_attr(g, "first_dt", driver.first_dt);
  h5::write_attr(g, "min_dt", driver.min_dt);
  h5::write_attr(g, "max_dt", driver.max_dt);
  h5::write_attr(g, "initial_totals", pack_totals(driver.initial));
  h5::write_attr(g, "outflow_totals", pack_totals(r.outflow_totals));
  if (!r.drive_loads.empty()) {  // force and impulse of each drive (body_drive.hpp)
    std::vector<double> dl;
    for (const DriveLoad& l : r.drive_loads)
      for (const Eigen::Vector3d* v : {&l.force, &l.impulse}) dl.insert(dl.end(), v->data(), v->data() + 3);
    h5::write_attr(g, "drive_loads", dl);
  }
  h5::write_attr(g, "run_identity", identity);
  h5::write_attr(g, "run_identity_digest", common::RunIdentity::parse(identity).digest());
  {
    h5::Handle p = h5::create_group(g, "particles");
    ok = write_set(p, ps, rows.particles, rows.optional_arrays) && ok;
  }
  h5::write_attr(g, "material_count", static_cast<std::int64_t>(mats.size()));
  h5::Handle mg = h5::create_group(g, "materials");
  for (std::size_t m = 0; m < mats.size(); ++m) {
    const MaterialSlot& s = mats[m];
    h5::Handle sg = h5::create_group(mg, std::to_string(m));
    h5::write_attr(sg, "name", s.name);
    h5::write_attr(sg, "begin", static_cast<std::int64_t>(s.begin));
    h5::write_attr(sg, "end", static_cast<std::int64_t>(s.end));
    for (std::size_t k = 0; k < s.state.size(); ++k) {
      const StateField& sf = s.style->state_fields[k];
      const std::size_t nc = static_cast<std::size_t>(sf.ncomp);
      ok = h5::write_dataset_rows(sg, sf.name, s.state[k].data(), s.state[k].size() / nc, nc, sf.unit, rows.slots[m]) && ok;
    }
  }
  h5::Handle og = h5::create_group(g, "outflow");
  const h5::RowBlock ob{rows.outflow_first, rows.outflow_total, rows.xfer};  // this process's rows
  const std::size_t on = r.outflow_time.size();
  {
    h5::Handle p = h5::create_group(og, "particles");
    ok = write_set(p, r.outflow, ob, rows.outflow_optional) && ok;
  }
  ok = h5::write_dataset_rows(og, "removal_time", r.outflow_time.data(), on, 1, "s", ob) && ok;
  h5::Handle fg = h5::create_group(og, "fields");
  for (std::size_t k = 0; k < r.outflow_fields.size(); ++k) {
    const common::Field& fl = r.outflow_fields[k];
    const std::string name = std::to_string(k);
    ok = h5::write_dataset_rows(fg, name, fl.values.data(), on, fl.ncomp, fl.unit, ob) && ok;
    h5::Handle ds(H5Dopen2(fg, name.c_str(), H5P_DEFAULT));
    h5::write_attr(ds, "name", fl.name);
    h5::write_attr(ds, "description", fl.description);
    h5::write_attr(ds, "initial", r.outflow_init[k]);
  }
  const std::vector<std::uint64_t> words = pack_bytes(driver.series);
  h5::write_attr(g, "series_bytes", static_cast<std::int64_t>(driver.series.size()));
  ok = h5::write_dataset_rows(g, "series", words.data(), mine(words.size()), 1, "1", single(words.size())) && ok;
  return ok;
}

void write_checkpoint(const std::string& path, const Solver& solver, const DriverState& driver,
                      const common::Provenance& prov, const std::string& identity) {
  write_checkpoint(path, solver.particles(), solver.materials(), solver.grid(), solver.resume_state(), driver, prov,
                   identity);
}

void write_checkpoint(const std::string& path, const ParticleSet& ps, const std::vector<MaterialSlot>& mats,
                      const common::GridInfo& grid, const SolverResume& r, const DriverState& driver,
                      const common::Provenance& prov, const std::string& identity, const common::H5Hook& extra) {
  const common::ParticleSnapshot snap = make_snapshot(ps, mats, grid, r.time, r.step);
  common::check_output_particles(snap, path);  // never Inf/NaN in an output (exit 3)
  auto hook = [&](long long fid) {
    const hid_t f = static_cast<hid_t>(fid);
    if (!write_mpm_state(f, ps, mats, r, driver, identity, CheckpointRows::whole(ps, mats, r)))
      throw common::IoError("HDF5: writing " + path + " failed (disk full or file not writable?)");
    if (extra) extra(fid);
  };
  common::write_particle_snapshot(path, snap, prov, hook);
}

}  // namespace mpmfrag
