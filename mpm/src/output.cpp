/// @file output.cpp
/// Snapshot assembly and the time-series CSV (no physics here).
#include "mpm/output.hpp"

#include <iomanip>
#include <map>

#include "common/status.hpp"

namespace mpmfrag {

common::ParticleSnapshot make_snapshot(const ParticleSet& ps, const std::vector<MaterialSlot>& mats,
                                       const common::GridInfo& grid, double time, std::int64_t step) {
  common::ParticleSnapshot s;
  const std::size_t n = ps.size();
  s.time = time;
  s.step = step;
  s.grid = grid;
  s.id = ps.id;
  s.position = ps.x;
  s.velocity = ps.v;
  s.mass = ps.mass;
  s.volume = ps.volume;
  s.size.resize(3 * n);
  for (std::size_t i = 0; i < 3 * n; ++i) s.size[i] = 2.0 * ps.half_width[i];
  s.material = ps.material;
  s.fields.push_back({"stress", "Pa", 6, ps.stress, "Cauchy stress, Voigt order xx,yy,zz,yz,xz,xy, tension positive"});
  s.fields.push_back({"internal_energy", "J/kg", 1, ps.energy, "specific internal energy"});
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

SeriesWriter::SeriesWriter(const std::string& path)
    : file_(path, common::SeriesFormat({{"step", ""},
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
                                        {"total_J", "J"}},
                                       {.precision = 12})) {}

void SeriesWriter::write(std::int64_t step, double t, double dt, const Diagnostics& d) {
  common::SeriesRow row = file_.row();
  row.integer(step).num(t).num(dt).num(d.mass);
  row.num(d.momentum[0]).num(d.momentum[1]).num(d.momentum[2]);
  row.num(d.angular_momentum[0]).num(d.angular_momentum[1]).num(d.angular_momentum[2]);
  row.num(d.kinetic).num(d.internal).num(d.total());
  file_.write(row);
}

}  // namespace mpmfrag
