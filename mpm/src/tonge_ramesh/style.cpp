/// @file style.cpp
/// "tonge_ramesh" material style: parameter schema, state fields and the batched update over
/// SoA particles (model equations: point_update.hpp, micromechanics.hpp, granular.hpp).
/// Per batch, each particle is independent (no shared mutable data), so results do not depend
/// on the thread count; flaws are sampled in initialize() from common::KeyedRng keyed by
/// (scene seed + user seed, global particle id or block of initial positions, material
/// population), using volume0 and the material's body size (MaterialBatch::specimen_size).
/// Energy: the solver owns e (material.hpp); the model reads e_n for the Tillotson pressure.
/// The last state field, damage_substeps, is the update's damage sub-step count M (StepDiag),
/// not physics: a cost field (StateField::work) that the MPI cuts weigh (mpm/mpi/domain.hpp).
#include "mpm/tonge_ramesh/style.hpp"

#include <Eigen/Core>
#include <cmath>

#include "common/status.hpp"
#include "mpm/tonge_ramesh/flaws.hpp"
#include "mpm/tonge_ramesh/moduli.hpp"
#include "mpm/tonge_ramesh/point_update.hpp"

namespace mpmfrag {
namespace {
namespace tr = tonge_ramesh;
using RowMap = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>;

enum Field { fD = 0, fJGP, fIel, fGPS, fGPE, fLoc, fOmega, fSize, fLen, fSub, nFields };

/// Cost of one damage sub-step relative to a plain particle-step (one particle's P2G + G2P):
/// measured on the Tonge-Ramesh impact (pipelines/impact/fragment.toml, 700 m cells, 2 particles
/// per cell, one thread, 2026-12-07): a sub-step 1.10 us, the grid transfers 1.85 us per
/// particle-step. The MPI cuts weigh each particle by 1 + kSubstepWork M (StateField::work).
constexpr double kSubstepWork = 0.6;

class TongeRamesh final : public Material {
 public:
  explicit TongeRamesh(const tr::Params& p) : p_(p), d_(p) {
    p_.validate();
    if (p_.total_bins() > kTongeRameshBinSlots)
      throw common::InputError("", "tonge_ramesh bins", "more than 50 flaw bins in total");
  }
  double density() const override { return p_.density; }
  double reference_wave_speed() const override { return tr::wave_speed(p_, 1.0, 1.0, 0.0); }
  /// Energy budget: isochoric neo-Hookean energy (G(D)/2)(tr be - 3) = (3/2) G(D) (I_el - 1) and the
  /// granular + compaction dissipation, both per reference volume, times V0.
  void stored_energies(const MaterialBatch& b, double* elastic, double* dissipated) const override {
    for (std::size_t k = 0; k < b.n; ++k) {
      elastic[k] = 1.5 * tr::damaged_shear(p_, d_, b.state[fD][k]) * (b.state[fIel][k] - 1.0) * b.volume0[k];
      dissipated[k] = b.state[fGPE][k] * b.volume0[k];
    }
  }

  void initialize(const MaterialBatch& b) const override {
    const int nb = p_.total_bins();
    tr::Params ps = p_;
    ps.flaw_seed = p_.flaw_seed ^ (b.seed * 0x9E3779B97F4A7C15ull);
    if (!(ps.specimen_size > 0.0)) ps.specimen_size = b.specimen_size;
    for (std::size_t k = 0; k < b.n; ++k) {
      double* om = b.state[fOmega] + kTongeRameshBinSlots * k;
      double* sz = b.state[fSize] + kTongeRameshBinSlots * k;
      double* ln = b.state[fLen] + kTongeRameshBinSlots * k;
      for (int i = 0; i < kTongeRameshBinSlots; ++i) om[i] = sz[i] = ln[i] = 0.0;
      if (p_.use_damage) tr::sample_flaws(ps, b.volume0[k], b.x ? b.x + 3 * k : nullptr, b.id[k], 0, om, sz);
      const tr::PointState st = tr::initial_state(p_, nb, om, sz);
      store(b, k, st);
      const double J = det3(b.F + 9 * k);
      const double pK = tr::kirchhoff_mean(p_, J, b.energy[k], tr::damaged_bulk(d_, st.D) / d_.K0);
      double* s = b.stress + 6 * k;
      s[0] = s[1] = s[2] = pK / J;
      s[3] = s[4] = s[5] = 0.0;
      speeds(b, k, J, st);
    }
  }

  BatchResult update(const MaterialBatch& b) const override {
    BatchResult r;
    const int nb = p_.total_bins();
    for (std::size_t k = 0; k < b.n; ++k) {
      double* s = b.stress + 6 * k;
      Eigen::Matrix3d sig;
      sig << s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2];
      tr::StepInput in;
      in.L = RowMap(b.L + 9 * k);
      in.dt = b.dt;
      in.Jnp1 = det3(b.F + 9 * k);
      in.Jn = jacobian_old(in.Jnp1, b.L + 9 * k, b.dt);
      tr::PointState st = load(b, k);
      st.e = std::max(b.energy[k], 0.0);
      tr::StepDiag diag;
      const auto status = tr::update_point(
          p_, d_, in, sig, st, nb, b.state[fOmega] + kTongeRameshBinSlots * k,
          b.state[fSize] + kTongeRameshBinSlots * k, b.state[fLen] + kTongeRameshBinSlots * k, &diag);
      if (status != tr::UpdateStatus::ok) {
        if (!r.failed++) {
          r.first_failed = k;
          r.reason = "tonge_ramesh: non-finite input or J <= 0";
        }
        continue;
      }
      s[0] = sig(0, 0);
      s[1] = sig(1, 1);
      s[2] = sig(2, 2);
      s[3] = sig(1, 2);
      s[4] = sig(0, 2);
      s[5] = sig(0, 1);
      store(b, k, st);
      b.state[fSub][k] = diag.substeps;
      speeds(b, k, in.Jnp1, st);
    }
    return r;
  }

 private:
  tr::PointState load(const MaterialBatch& b, std::size_t k) const {
    tr::PointState st;
    st.D = b.state[fD][k];
    st.JGP = b.state[fJGP][k];
    st.Iel = b.state[fIel][k];
    st.gp_strain = b.state[fGPS][k];
    st.gp_energy = b.state[fGPE][k];
    st.flags = static_cast<int>(b.state[fLoc][k]);
    return st;
  }
  void store(const MaterialBatch& b, std::size_t k, const tr::PointState& st) const {
    b.state[fD][k] = st.D;
    b.state[fJGP][k] = st.JGP;
    b.state[fIel][k] = st.Iel;
    b.state[fGPS][k] = st.gp_strain;
    b.state[fGPE][k] = st.gp_energy;
    b.state[fLoc][k] = st.flags;
  }
  void speeds(const MaterialBatch& b, std::size_t k, double J, const tr::PointState& st) const {
    const double e = std::max(b.energy[k], 0.0);
    b.wave_speed[k] = tr::wave_speed(p_, J, st.JGP, e);
    if (b.bulk_speed) b.bulk_speed[k] = tr::bulk_speed(p_, d_, J, st.JGP, e, st.D);
  }
  tr::Params p_;
  tr::Derived d_;
};

}  // namespace

std::vector<StateField> tonge_ramesh_state_fields() {
  const int n = kTongeRameshBinSlots;
  return {
      {"damage", 1, "1", 0.0, true, "Tonge-Ramesh damage D = sum omega (s+l)^3, capped at D_max"},
      {"distension", 1, "1", 1.0, true, "granular Jacobian J_GP = P-alpha distension"},
      {"iel", 1, "1", 1.0, false, "tr(bbar_e)/3 of the isochoric elastic left Cauchy-Green tensor"},
      {"granular_strain", 1, "1", 0.0, true, "accumulated granular deviatoric strain"},
      {"granular_energy", 1, "J/m^3", 0.0, true, "granular + compaction dissipation per reference volume"},
      {"localized", 1, "1", 0.0, true, "bit flags: 1 D >= D_c, 2 J_GP >= JLoc"},
      {"flaw_density", n, "1/m^3", 0.0, false, "flaw number density per bin"},
      {"flaw_size", n, "m", 0.0, false, "representative flaw half-size per bin"},
      {"wing_length", n, "m", 0.0, false, "wing-crack length per bin"},
      {"damage_substeps", 1, "1", 1.0, false, "damage sub-steps M of the last update (MPI cut weight)", kSubstepWork},
  };
}

std::unique_ptr<Material> make_tonge_ramesh(const tonge_ramesh::Params& p) {
  return std::make_unique<TongeRamesh>(p);
}

void register_tonge_ramesh(MaterialRegistry& reg) {
  StyleInfo s;
  s.name = "tonge_ramesh";
  s.description =
      "Tonge-Ramesh brittle damage (wing cracks, DP granular flow, P-alpha) with cold Tillotson; "
      "defaults: basalt, El Mir et al. 2019 Table 1";
  const tr::Params d = tr::basalt_el_mir();
  common::Schema& c = s.schema;
  c.add_real("A", d.eos.A, "Pa", 0.0, 1e15, "Tillotson A (= K0)", true);
  c.add_real("B", d.eos.B, "Pa", 0.0, 1e15, "Tillotson B");
  c.add_real("a", d.eos.a, "1", 0.0, 10.0, "Tillotson a");
  c.add_real("b", d.eos.b, "1", 0.0, 10.0, "Tillotson b");
  c.add_real("E0", d.eos.E0, "J/kg", 0.0, 1e15, "Tillotson E0", true);
  c.add_real("shear_modulus", d.shear_modulus, "Pa", 0.0, 1e15, "G0 (basalt 22.7 GPa, Benz & Asphaug 1999)", true);
  c.add_bool("use_damage", true, "micromechanical wing-crack damage");
  c.add_bool("use_granular", true, "granular flow (Drucker-Prager) and P-alpha compaction");
  c.add_real("KIc", d.KIc, "Pa m^0.5", 0.0, 1e12, "fracture toughness K_IC", true);
  c.add_real("flaw_friction", d.flaw_friction, "1", 0.0, 10.0, "crack-face friction mu");
  c.add_real("flaw_angle", -1.0, "rad", -1.0, 1.5707963267948966,
             "flaw angle phi; -1: pi/2 - atan(1/mu)/2");
  c.add_real("growth_exponent", d.growth_exponent, "1", 0.0, 10.0, "gamma_c");
  c.add_real("growth_alpha", d.growth_alpha, "1", 1.0, 1e6, "alpha_c: v_max = C_R/alpha_c");
  c.add_real("critical_damage", d.critical_damage, "1", 0.0, 1.0, "D_c", true);
  c.add_real("max_damage", d.max_damage, "1", 0.0, 1.0, "D_max", true);
  c.add_real("max_damage_inc", d.max_damage_inc, "1", 0.0, 1.0, "damage increment per sub-step", true);
  c.add_int("max_substeps", d.max_substeps, 1, 1000000, "cap on damage sub-steps per step");
  c.add_bool("friction_in_tension", false, "reproduce PTR's friction-in-tension quirk");
  c.add_bool("include_initial_damage", true, "D includes the starter flaws (El Mir)");
  c.add_real("dp_slope", d.dp_slope, "1", 0.0, 10.0, "Drucker-Prager A_DP");
  c.add_real("dp_cohesion", d.dp_cohesion, "Pa", 0.0, 1e12, "Drucker-Prager B_DP");
  c.add_real("granular_time", 0.0, "s", 0.0, 1e6, "Duvaut-Lions relaxation time (0: rate independent)");
  c.add_real("pa_P0", d.pa_P0, "Pa", 0.0, 1e15, "P-alpha onset pressure P_e at alpha0", true);
  c.add_real("pa_alpha0", d.pa_alpha0, "1", 1.0, 100.0, "P-alpha alpha0", true);
  c.add_real("pa_Pc", d.pa_Pc, "Pa", 0.0, 1e15, "P-alpha full-compaction pressure", true);
  c.add_int("flaw_seed", 0, 0, 1LL << 62, "user part of the flaw-sampling seed (xor scene seed)");
  c.add_choice("flaw_sampling", tr::FlawSampling::scale_aware, tr::kFlawSamplings,
               "scale_aware: each bin is drawn per particle where a particle expects >= flaw_block_count "
               "of its flaws, else once per block of particles about the flaws' spacing (shared by the "
               "block; expected density where the block exceeds the specimen); poisson: each particle "
               "draws its own flaws (El Mir/PTR; strength depends on the cell size); expected: every "
               "particle carries the expected density of every bin (no heterogeneity)");
  c.add_real("flaw_block_count", d.block_count, "1", 1e-6, 1e6,
             "scale_aware: least expected number of a bin's flaws per sampling block");
  c.add_real("flaw_block_size_factor", d.block_size_factor, "1", 0.0, 1e3,
             "scale_aware: block edge >= this x the bin's largest flaw half-size");
  c.add_real("specimen_size", 0.0, "m", 0.0, 1e12,
             "body size for the populations' min/max_specimen (0: the largest extent of this "
             "material's particles)");
  for (int ip = 0; ip < 2; ++ip) {
    const std::string pre = ip == 0 ? "small_" : "large_";
    const tr::FlawPopulation& f = d.populations[ip];
    c.add_real(pre + "s_min", f.s_min, "m", 0.0, 1e6, pre + "flaws: smallest half-size", true);
    c.add_real(pre + "s_max", f.s_max, "m", 0.0, 1e6, pre + "flaws: largest half-size", true);
    c.add_real(pre + "exponent", f.exponent, "1", 0.0, 100.0, pre + "flaws: Pareto exponent", true);
    c.add_real(pre + "density", f.density, "1/m^3", 0.0, 1e30, pre + "flaws: number density (0: off)");
    c.add_int(pre + "bins", f.bins, 1, kTongeRameshBinSlots, pre + "flaws: bins");
    c.add_real(pre + "bin_bias", f.bin_bias, "1", -100.0, 100.0, pre + "flaws: bin bias (1 uniform, <0 rational)");
    c.add_real(pre + "min_specimen", f.min_specimen, "m", 0.0, 1e30,
               pre + "flaws: realised only in bodies at least this large");
    c.add_real(pre + "max_specimen", f.max_specimen, "m", 0.0, 1e30,
               pre + "flaws: realised only in bodies at most this large");
  }
  s.state_fields = tonge_ramesh_state_fields();
  s.create = [](const common::Scene& e) -> std::unique_ptr<Material> {
    tr::Params p = tr::basalt_el_mir();
    p.density = e.real("density");
    p.eos.A = e.real("A");
    p.eos.B = e.real("B");
    p.eos.a = e.real("a");
    p.eos.b = e.real("b");
    p.eos.E0 = e.real("E0");
    p.shear_modulus = e.real("shear_modulus");
    p.use_damage = e.boolean("use_damage");
    p.use_granular = e.boolean("use_granular");
    p.KIc = e.real("KIc");
    p.flaw_friction = e.real("flaw_friction");
    p.flaw_angle = e.real("flaw_angle");
    p.growth_exponent = e.real("growth_exponent");
    p.growth_alpha = e.real("growth_alpha");
    p.critical_damage = e.real("critical_damage");
    p.max_damage = e.real("max_damage");
    p.max_damage_inc = e.real("max_damage_inc");
    p.max_substeps = static_cast<int>(e.integer("max_substeps"));
    p.friction_in_tension = e.boolean("friction_in_tension");
    p.include_initial_damage = e.boolean("include_initial_damage");
    p.dp_slope = e.real("dp_slope");
    p.dp_cohesion = e.real("dp_cohesion");
    p.granular_time = e.real("granular_time");
    p.pa_P0 = e.real("pa_P0");
    p.pa_alpha0 = e.real("pa_alpha0");
    p.pa_Pc = e.real("pa_Pc");
    p.flaw_seed = static_cast<std::uint64_t>(e.integer("flaw_seed"));
    p.flaw_sampling = e.choice("flaw_sampling", tr::kFlawSamplings);
    p.block_count = e.real("flaw_block_count");
    p.block_size_factor = e.real("flaw_block_size_factor");
    p.specimen_size = e.real("specimen_size");
    p.populations.clear();
    for (const std::string pre : {"small_", "large_"}) {
      tr::FlawPopulation f;
      f.s_min = e.real(pre + "s_min");
      f.s_max = e.real(pre + "s_max");
      f.exponent = e.real(pre + "exponent");
      f.density = e.real(pre + "density");
      f.bins = static_cast<int>(e.integer(pre + "bins"));
      f.bin_bias = e.real(pre + "bin_bias");
      f.min_specimen = e.real(pre + "min_specimen");
      f.max_specimen = e.real(pre + "max_specimen");
      if (f.density > 0.0) p.populations.push_back(f);
    }
    return std::make_unique<TongeRamesh>(p);
  };
  reg.add(std::move(s));
}

}  // namespace mpmfrag
