/// @file run_handoff.cpp
/// Implementation of handoff/run_handoff.hpp (the header states the contract, and for physics the equations and sources).
#include "handoff/run_handoff.hpp"

#include <spdlog/spdlog.h>

#include <chrono>

#include "common/finite.hpp"
#include "common/atomic_file.hpp"
#include "common/xdmf.hpp"
#include "common/h5.hpp"
#include "common/status.hpp"
#include "handoff/conserving.hpp"
#include "handoff/outflow.hpp"

namespace handoff {

namespace {
/// Particles idx of s, and (optionally) idx2 of s2 moved ballistically to time t.
Invariants invariants_of(const common::ParticleSnapshot& s, const std::vector<std::size_t>& idx,
                         const common::ParticleSnapshot* s2 = nullptr, const std::vector<std::size_t>* idx2 = nullptr,
                         double t = 0.0) {
  std::vector<double> x, v, m;
  auto add = [&](const common::ParticleSnapshot& q, const std::vector<std::size_t>& ii, double dt) {
    for (std::size_t i : ii) {
      for (int d = 0; d < 3; ++d) {
        x.push_back(q.position[3 * i + d] + dt * q.velocity[3 * i + d]);
        v.push_back(q.velocity[3 * i + d]);
      }
      m.push_back(q.mass[i]);
    }
  };
  add(s, idx, 0.0);
  if (s2) add(*s2, *idx2, t - s2->time);
  return compute_invariants(m.size(), x.data(), v.data(), m.data());
}
std::vector<std::size_t> all_of(const common::ParticleSnapshot& s) {
  std::vector<std::size_t> i(s.count());
  for (std::size_t k = 0; k < i.size(); ++k) i[k] = k;
  return i;
}
}  // namespace

HandoffOutcome hand_off(const common::ParticleSnapshot& snap, const HandoffConfig& cfg_in,
                        const common::ParticleSnapshot* outflow) {
  HandoffConfig cfg = cfg_in;
  if (!cfg.carry_given) {  // default carry list: skip fields the snapshot does not have
    std::vector<std::string> present;
    for (const auto& f : cfg.projection.carry_fields)
      if (snap.field(f)) present.push_back(f);
    cfg.projection.carry_fields = present;
  }
  HandoffOutcome out;
  Audit& a = out.audit;
  a.method = std::string(common::choice_name(kHandoffMethods, cfg.method));
  // Without selection rules every particle is handed off: no index lists, no copies.
  const bool selecting = cfg.select.active();
  const Selection sel = selecting ? select_particles(snap, cfg.select, cfg.input) : Selection{};
  if (selecting && sel.kept.empty())
    throw common::InputError(cfg.input, "select", "the selection rules removed every particle");
  Selection osel;
  if (outflow) osel = selecting ? select_particles(*outflow, cfg.select, cfg.outflow) : Selection{all_of(*outflow), {}};
  if (outflow) {
    const std::vector<std::size_t> all = all_of(snap), oall = all_of(*outflow);
    a.input = invariants_of(snap, all, outflow, &oall, snap.time);
  } else {
    a.input = compute_invariants(snap.count(), snap.position.data(), snap.velocity.data(), snap.mass.data());
  }
  a.dropped = invariants_of(snap, sel.dropped, outflow, outflow ? &osel.dropped : nullptr, snap.time);
  const common::ParticleSnapshot kept_storage = selecting ? subset(snap, sel.kept) : common::ParticleSnapshot{};
  const common::ParticleSnapshot& kept = selecting ? kept_storage : snap;
  if (selecting || outflow) {
    const std::vector<std::size_t> all = selecting ? std::vector<std::size_t>{} : all_of(snap);
    a.before = invariants_of(snap, selecting ? sel.kept : all, outflow, outflow ? &osel.kept : nullptr, snap.time);
  } else {
    a.before = a.input;
  }

  out.result = project_to_spheres(kept, cfg.projection, cfg.input);
  if (outflow && !osel.kept.empty()) {
    a.outflow_particles = osel.kept.size();
    a.outflow_spheres = append_outflow(subset(*outflow, osel.kept), snap.grid, snap.time, out.result, cfg.outflow);
  }
  common::SphereSet& sph = out.result.spheres;
  if (cfg.method == HandoffMethod::conserving) {
    const ConservingResult cr = apply_conserving(sph, a.before);
    a.exact = cr.exact;
    a.note = cr.exact ? "lambda = " + std::to_string(cr.lambda) : cr.note;
  }
  if (cfg.bonds.enabled) sph.bonds = face_bonds(sph, cfg.bonds, cfg.input);
  a.after = compute_invariants(sph.count(), sph.position.data(), sph.velocity.data(), sph.mass.data(),
                               sph.spin.data(), sph.radius.data());
  a.occupied_mpm_cells = out.result.occupied_mpm_cells;
  a.sphere_cell = out.result.sphere_cell;
  a.min_gap = min_sphere_gap(out.result);
  a.max_overlap = std::max(0.0, -a.min_gap);
  return out;
}

int run_handoff(const HandoffConfig& cfg, const common::Provenance& prov) {
  const auto t0 = std::chrono::steady_clock::now();
  // Unusable outputs (a FIFO, /dev/null) are refused before any work and before the audit is written.
  for (const std::string& out : {cfg.output, common::xdmf_path_for(cfg.output), cfg.audit_json, cfg.ss_path})
    if (!out.empty()) common::check_output_path(out);
  const common::ParticleSnapshot snap = common::read_particle_snapshot(cfg.input);
  common::ParticleSnapshot outflow;
  common::check_input_particles(snap, cfg.input);
  if (!cfg.outflow.empty()) {
    outflow = common::read_particle_snapshot(cfg.outflow);
    common::check_input_particles(outflow, cfg.outflow);
  }
  const auto t1 = std::chrono::steady_clock::now();
  HandoffOutcome out = hand_off(snap, cfg, cfg.outflow.empty() ? nullptr : &outflow);
  const auto t2 = std::chrono::steady_clock::now();
  const Audit& a = out.audit;
  // nothing is written unless every output value (and the energies) is finite: exit 3
  common::check_output_spheres(out.result.spheres, cfg.output);
  spdlog::info("{}", audit_text(a));
  spdlog::info("read {:.3f} s, hand-off {:.3f} s ({:.2e} particles/s, {} kernels)",
               std::chrono::duration<double>(t1 - t0).count(), std::chrono::duration<double>(t2 - t1).count(),
               snap.count() / std::max(1e-9, std::chrono::duration<double>(t2 - t1).count()), out.result.kernels);
  common::write_text_atomic(cfg.audit_json, audit_json(a));
  if (a.kinetic_loss_relative() > cfg.max_energy_loss) {
    throw common::NumericalError("kinetic-energy loss " + std::to_string(100 * a.kinetic_loss_relative()) +
                                 " % exceeds audit.max_energy_loss = " + std::to_string(100 * cfg.max_energy_loss) +
                                 " %; no sphere file written (try method = \"conserving\" or a finer grid). Audit: " +
                                 cfg.audit_json);
  }
  const SphereParticleMap& map = out.result.map;
  common::write_sphere_set(cfg.output, out.result.spheres, prov, [&](long long f) {
    namespace h5 = common::h5;
    h5::Handle g = h5::create_group(static_cast<hid_t>(f), "handoff");
    h5::write_dataset(g, "sphere_particle_offset", map.offset.data(), map.offset.size(), 1, "1");
    h5::write_dataset(g, "particle_id", map.particle_id.data(), map.particle_id.size(), 1, "1");
    h5::write_attr(g, "description", std::string("sphere s holds particles particle_id[sphere_particle_offset[s] : "
                                                 "sphere_particle_offset[s+1]] of the input snapshot"));
    h5::write_attr(g, "input", cfg.input);
    h5::write_attr(g, "outflow", cfg.outflow);
    h5::write_attr(g, "method", a.method);
    h5::write_attr(g, "coarsen", static_cast<std::int64_t>(cfg.projection.coarsen));
    h5::write_attr(g, "kernels", out.result.kernels);  // "avx2" or "portable": same results, bit for bit
    if (cfg.bonds.enabled) {  // the bond law's inputs (face_bonds.hpp); the bonds are in /bonds
      h5::write_attr(g, "bonds_damage_law", std::string("f = 1 - max(D_a, D_b) / D_c, none for D >= D_c"));
      h5::write_attr(g, "bonds_damage_critical", cfg.bonds.damage_critical);
      h5::write_attr(g, "bonds_count", static_cast<std::int64_t>(out.result.spheres.bonds.size()));
    }
    write_audit_h5(f, a);
  });
  if (!cfg.ss_path.empty())
    common::write_ss(cfg.ss_path, out.result.spheres, common::SsUnits::of(cfg.ss_units), cfg.ss_color);
  spdlog::info("wrote {} spheres{} to {} (audit {})", out.result.spheres.count(),
               cfg.bonds.enabled ? " and " + std::to_string(out.result.spheres.bonds.size()) + " bonds" : std::string(),
               cfg.output, cfg.audit_json);
  return 0;
}

}  // namespace handoff
