/// @file output.cpp
/// Snapshot assembly (the particle-array -> dataset mapping shared with the outflow record) and
/// the time-series CSV (no physics here).
#include "mpm/output.hpp"

#include <iomanip>
#include <map>
#include <stdexcept>
#include <string_view>
#include <type_traits>

#include "common/status.hpp"
#include "mpm/energy_budget.hpp"

namespace mpmfrag {

namespace {
/// The snapshot's core dataset `name` of element type T, or nullptr for a state dataset.
template <class T>
std::vector<T>* core_dataset(common::ParticleSnapshot& s, std::string_view name) {
  if constexpr (std::is_same_v<T, std::uint64_t>) {
    if (name == "id") return &s.id;
  } else if constexpr (std::is_same_v<T, std::int32_t>) {
    if (name == "material") return &s.material;
  } else if constexpr (std::is_same_v<T, double>) {
    if (name == "position") return &s.position;
    if (name == "velocity") return &s.velocity;
    if (name == "mass") return &s.mass;
    if (name == "volume") return &s.volume;
    if (name == "size") return &s.size;
  }
  return nullptr;
}
}  // namespace

void add_particle_datasets(common::ParticleSnapshot& s, const ParticleSet& ps) {
  ParticleSet::for_each_array([&](const auto& a) {
    using T = typename std::decay_t<decltype(a)>::element_type;
    if (!a.info.dataset) return;
    const std::vector<T>& src = ps.*a.member;
    std::vector<T> values = src;
    if constexpr (std::is_same_v<T, double>)
      if (a.info.dataset_scale != 1.0)
        for (double& v : values) v = a.info.dataset_scale * v;
    if (std::vector<T>* core = core_dataset<T>(s, a.info.dataset)) {
      *core = std::move(values);
    } else if constexpr (std::is_same_v<T, double>) {
      s.fields.push_back({a.info.dataset, a.info.unit, static_cast<std::size_t>(a.info.width), std::move(values),
                          a.info.description});
    } else {
      throw std::logic_error(std::string("particle array '") + a.info.name + "': state datasets must be double");
    }
  });
}

common::ParticleSnapshot make_snapshot(const ParticleSet& ps, const std::vector<MaterialSlot>& mats,
                                       const common::GridInfo& grid, double time, std::int64_t step) {
  common::ParticleSnapshot s;
  const std::size_t n = ps.size();
  s.time = time;
  s.step = step;
  s.grid = grid;
  add_particle_datasets(s, ps);  // core datasets, then stress and internal_energy
  // style fields, merged by name across materials
  std::map<std::string, std::size_t> index;
  for (const MaterialSlot& m : mats) {
    for (std::size_t f = 0; f < m.state.size(); ++f) {
      const StateField& sf = m.style->state_fields[f];
      if (!sf.output) continue;
      auto it = index.find(sf.name);
      if (it == index.end()) {
        common::Field fld{sf.name, sf.unit, static_cast<std::size_t>(sf.ncomp),
                          std::vector<double>(n * sf.ncomp, sf.initial), sf.description};
        index[sf.name] = s.fields.size();
        s.fields.push_back(std::move(fld));
        it = index.find(sf.name);
      }
      common::Field& fld = s.fields[it->second];
      if (fld.ncomp != static_cast<std::size_t>(sf.ncomp))
        throw common::InputError("state field '" + sf.name + "' declared with different component counts");
      std::copy(m.state[f].begin(), m.state[f].end(), fld.values.begin() + m.begin * sf.ncomp);
    }
  }
  return s;
}

namespace {
common::SeriesFormat series_format(const std::vector<std::size_t>& drive_bodies) {
  std::vector<common::SeriesColumn> cols{{"step", ""},
                               {"time_s", "s"},
                               {"dt_s", "s"},
                               {"mass_kg", "kg"},
                               {"px_kgm_s", "kg m/s"},
                               {"py_kgm_s", "kg m/s"},
                               {"pz_kgm_s", "kg m/s"},
                               {"Lx_kgm2_s", "kg m^2/s"},
                               {"Ly_kgm2_s", "kg m^2/s"},
                               {"Lz_kgm2_s", "kg m^2/s"},
                               {"kinetic_J", "J"},
                               {"internal_J", "J"},
                               {"total_J", "J"},
                               {"eos_J", "J"},
                               {"elastic_J", "J"},
                               {"plastic_J", "J"},
                               {"damage_J", "J"},
                               {"shock_heat_J", "J"},
                               {"transfer_heat_J", "J"}};
  for (const std::size_t b : drive_bodies) {  // the load of each driven body (body_drive.hpp)
    const std::string p = "body" + std::to_string(b) + "_";
    for (const char* c : {"Fx_N", "Fy_N", "Fz_N"}) cols.push_back({p + c, "N"});
    for (const char* c : {"Jx_Ns", "Jy_Ns", "Jz_Ns"}) cols.push_back({p + c, "N s"});
  }
  return common::SeriesFormat(std::move(cols), {.precision = 12});
}
}  // namespace

SeriesWriter::SeriesWriter(const std::string& path, const std::vector<std::size_t>& drive_bodies,
                           std::optional<std::string> continued)
    : file_(continued ? common::SeriesFile(path, series_format(drive_bodies),
                                           common::SeriesFile::Initial{std::move(*continued)})
                      : common::SeriesFile(path, series_format(drive_bodies))) {}

void SeriesWriter::write(std::int64_t step, double t, double dt, const Diagnostics& d,
                         const std::vector<DriveLoad>& loads) {
  common::SeriesRow row = file_.row();
  row.integer(step).num(t).num(dt).num(d.mass);
  row.num(d.momentum[0]).num(d.momentum[1]).num(d.momentum[2]);
  row.num(d.angular_momentum[0]).num(d.angular_momentum[1]).num(d.angular_momentum[2]);
  row.num(d.kinetic).num(d.internal).num(d.total());
  const EnergyBudget e = energy_budget(d);
  row.num(e.eos).num(e.elastic).num(e.plastic).num(e.damage).num(e.shock_heat).num(e.transfer_heat);
  for (const DriveLoad& l : loads) {
    row.num(l.force[0]).num(l.force[1]).num(l.force[2]);
    row.num(l.impulse[0]).num(l.impulse[1]).num(l.impulse[2]);
  }
  file_.write(row);
}

}  // namespace mpmfrag
