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

SeriesWriter::SeriesWriter(const std::string& path) : file_(path) {
  file_.stream() << "step,time_s,dt_s,mass_kg,px_kgm_s,py_kgm_s,pz_kgm_s,Lx_kgm2_s,Ly_kgm2_s,Lz_kgm2_s,"
                    "kinetic_J,internal_J,total_J\n";
}

void SeriesWriter::write(std::int64_t step, double t, double dt, const Diagnostics& d) {
  std::ostream& out = file_.stream();
  out << step << std::setprecision(12) << ',' << t << ',' << dt << ',' << d.mass << ',' << d.momentum[0] << ','
      << d.momentum[1] << ',' << d.momentum[2] << ',' << d.angular_momentum[0] << ',' << d.angular_momentum[1]
      << ',' << d.angular_momentum[2] << ',' << d.kinetic << ',' << d.internal << ',' << d.total() << '\n';
  file_.flush();
}

}  // namespace mpmfrag
