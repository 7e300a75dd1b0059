/// @file scene_setup.cpp
/// ssdem-grav scene schema and setup (scene_setup.hpp).
#include "ssdem/scene_setup.hpp"

#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "common/finite.hpp"
#include "common/rng.hpp"
#include "common/sphere_file.hpp"
#include "common/ss_file.hpp"
#include "common/status.hpp"
#include "ssdem/dt_rule.hpp"
#include "ssdem/generators.hpp"
#include "ssdem/io.hpp"

namespace ssdem {
namespace {

enum class InitialSource { file, ss, lattice_pile, random_pile, two_bodies };
constexpr std::array kInitialSources{common::Choice{"file", InitialSource::file},
                                     common::Choice{"ss", InitialSource::ss},
                                     common::Choice{"lattice_pile", InitialSource::lattice_pile},
                                     common::Choice{"random_pile", InitialSource::random_pile},
                                     common::Choice{"two_bodies", InitialSource::two_bodies}};

enum class GravitySolver { tree, direct };
constexpr std::array kGravitySolvers{common::Choice{"tree", GravitySolver::tree},
                                     common::Choice{"direct", GravitySolver::direct}};

enum class GravityInner { held, impulse };
constexpr std::array kGravityInner{common::Choice{"held", GravityInner::held},
                                   common::Choice{"impulse", GravityInner::impulse}};

constexpr std::array kTeamModes{common::Choice{"auto", TeamMode::automatic}, common::Choice{"size", TeamMode::size},
                                common::Choice{"every-pass", TeamMode::every_pass},
                                common::Choice{"one-thread", TeamMode::one_thread}};

enum class ContactPreset { none, gravel };
constexpr std::array kContactPresets{common::Choice{"none", ContactPreset::none},
                                     common::Choice{"gravel", ContactPreset::gravel}};

enum class Predictor { automatic, extrapolated, pkdgrav };
enum class LevelAnchor { lightest, median };
constexpr std::array kLevelAnchors{common::Choice{"lightest", LevelAnchor::lightest},
                                   common::Choice{"median", LevelAnchor::median}};

constexpr std::array kPredictors{common::Choice{"auto", Predictor::automatic},
                                 common::Choice{"extrapolated", Predictor::extrapolated},
                                 common::Choice{"pkdgrav", Predictor::pkdgrav}};

}  // namespace

const ContactPartRegistry& builtin_contact_parts() {
  static const ContactPartRegistry reg = [] {
    ContactPartRegistry r;
    register_builtin_contact_parts(r);
    return r;
  }();
  return reg;
}

common::Schema ssdem_schema() {
  common::Schema s("ssdem-grav: self-gravity + soft-sphere DEM");
  const double inf = INFINITY;
  // physical bounds (common/finite.hpp): every derived quantity stays finite
  const double kLen = common::bounds::kMaxLength, kV = common::bounds::kMaxSpeed;
  // time
  s.add_real("time.end", std::nullopt, "s", 0.0, inf, "simulated end time", true);
  s.add_real("time.dt", 0.0, "s", 0.0, inf,
             "timestep; 0 = from the dt rule: tau_min / time.steps_per_contact");
  s.add_real("time.steps_per_contact", 30.0, "1", 1.0, 1e6,
             "steps per contact duration used by the dt rule (pkdgrav demparams default 30)");
  s.add_bool("time.multirate", false,
             "multi-rate block time steps: each contact pair steps at 2^l dt <= its own contact time / "
             "time.steps_per_contact, spheres with no contact in reach once per gravity block (nbody/README.md)");
  s.add_choice("time.level_anchor", LevelAnchor::lightest, kLevelAnchors,
               "multi-rate base step when time.dt = 0: lightest = tau_min / N; median = the ladder "
               "anchored on a pair of median-mass spheres, which then gets exactly N steps (dt_rule.hpp)");
  s.add_real("time.min_steps_per_contact", 10.0, "1", 1.0, 1e6,
             "refuse dt that resolves the shortest contact with fewer steps (exit 2)");
  // initial condition
  s.add_choice("initial.source", InitialSource::lattice_pile, kInitialSources,
               "initial condition: an ssdem.spheres file, a pkdgrav .ss file or a generator");
  s.add_string("initial.file", std::string(""), "ssdem.spheres input file (initial.source = file)");
  s.add_string("initial.ss", std::string(""),
               "pkdgrav .ss input file, standard records; ids from org_idx (initial.source = ss)");
  s.add_choice("initial.ss_units", common::SsUnitSystem::pkdgrav, common::kSsUnitSystems,
               "units of the .ss file (pkdgrav: G = 1, AU, M_sun, time yr/(2 pi); si: m, kg, s)");
  s.add_real("initial.body_radius", 10.0, "m", 0.0, kLen,
             "radius of the (first) body (generated spheres: about 0.74 (body_radius / sphere_radius)^3, at most 1e8)", true);
  s.add_real("initial.sphere_radius", 1.0, "m", 0.0, kLen, "sphere radius of generated bodies", true);
  s.add_real("initial.density", 2000.0, "kg/m^3", 0.0, common::bounds::kMaxDensity,
             "grain (sphere material) density (physical bound: masses and energies stay finite)", true);
  s.add_real("initial.jitter", 0.0, "1", 0.0, 0.5, "relative random shrink of generated radii");
  s.add_int("initial.count", 1000, 1, 100000000, "number of spheres (random_pile)");
  s.add_vec3("initial.velocity", Eigen::Vector3d::Zero(), "m/s", -kV, kV,
             "bulk velocity of body 1 (|v| + |w| body_radius <= 1e7 m/s)");
  s.add_vec3("initial.angular_velocity", Eigen::Vector3d::Zero(), "rad/s", -common::bounds::kMaxAngularVelocity,
             common::bounds::kMaxAngularVelocity,
             "rigid rotation of body 1 about its centre");
  s.add_real("initial.body2_radius", 5.0, "m", 0.0, kLen, "radius of body 2 (two_bodies)", true);
  s.add_vec3("initial.body2_offset", Eigen::Vector3d(30, 0, 0), "m", -kLen, kLen,
             "centre of body 2 relative to body 1 (two_bodies)");
  s.add_vec3("initial.body2_velocity", Eigen::Vector3d(-1, 0, 0), "m/s", -kV, kV,
             "velocity of body 2 (two_bodies)");
  // gravity
  s.add_bool("gravity.self", true, "self-gravity on/off (off: no tree is built)");
  s.add_choice("gravity.solver", GravitySolver::tree, kGravitySolvers,
               "tree (Barnes-Hut octree, quadrupoles) or direct summation (reference, small N)");
  s.add_real("gravity.G", 6.674e-11, "m^3/(kg s^2)", 0.0, inf, "gravitational constant");
  const GravityParams gd;
  s.add_real("gravity.theta", gd.theta, "1", 0.0, 1.0,
             "opening angle (0.25: rms relative force error 7.6e-4 on a 5e3-sphere pile, 4.3e-4 on "
             "debris, <= 1.4e-4 uniform and Plummer; 0.35: 2.4e-3 on the pile)", true);
  s.add_int("gravity.bucket", gd.bucket, 1, 1024, "max spheres per tree leaf");
  s.add_int("gravity.group", gd.group, 1, 4096, "max spheres per sink group sharing one interaction list");
  s.add_real("gravity.tolerance", SimConfig{}.gravity_tolerance, "1", 0.0, 1.0,
             "error-controlled cadence (gravity.every = 0): rms relative force change allowed per gravity block", true);
  s.add_int("gravity.max_every", SimConfig{}.gravity_max_every, 1, 1000000,
            "error-controlled cadence (gravity.every = 0): longest gravity block (steps)");
  s.add_int("gravity.every", 0, 0, 1000000,
            "0 = error-controlled cadence (block length from the measured force change, "
            "gravity.tolerance); k >= 1 = fixed: self-gravity every k contact steps (impulse RESPA "
            "outer step k*dt)");
  s.add_choice("gravity.inner_steps", GravityInner::held, kGravityInner,
               "multi-rate: how self-gravity enters spheres whose step is shorter than the gravity "
               "block (in or near contact): held = the block-start field as a force at their own "
               "kicks plus a trapezoid residual at the block's end (same block endpoints as impulse "
               "for a free sphere; a resting pile feels its weight throughout the block), impulse "
               "= the block's two half-kicks (RESPA; a pile breathes between them)");
  s.add_vec3("gravity.uniform", Eigen::Vector3d::Zero(), "m/s^2", -inf, inf, "uniform gravity field");
  // contacts
  s.add_bool("contact.enabled", true, "soft-sphere contacts on/off (off: no neighbour list)");
  s.add_choice("contact.preset", ContactPreset::none, kContactPresets,
               "parameter preset for keys not given explicitly: gravel = e_n = e_t = 0.55, "
               "mu_s = 1.0, mu_r = 1.05, mu_t = 1.3, beta = 0.5, all parts (ssdem.md §1.8)");
  builtin_contact_parts().declare(s);
  s.add_real("contact.vmax", 0.0, "m/s", 0.0, inf,
             "expected max impact speed for the k_n rule (k_n = m vmax^2 / (f s)^2) when "
             "contact.normal.kn = 0; 0 = 1.2 x escape speed of the initial body");
  s.add_real("contact.overlap_fraction", 0.01, "1", 0.0, 1.0,
             "allowed overlap / radius for the k_n rule", true);
  s.add_choice("contact.predictor", Predictor::automatic, kPredictors,
               "velocity predictor for the dashpots: extrapolated (v + h/2 (2a_n - a_{n-1}); e_n "
               "error 1.2e-4 at 50 steps) or pkdgrav (v + h/2 a_n; 1.4e-3). The extrapolation "
               "amplifies strongly damped modes when a contact is resolved by few steps (a 3 km sphere "
               "pile at 4 steps per contact ran away); auto = extrapolated when the shortest contact has "
               ">= 8 steps, else pkdgrav");
  s.add_real("contact.skin", 0.0, "m", 0.0, inf, "neighbour-list skin (spheres moving more than skin/2 are re-inserted); 0 = 0.25 x max radius");
  s.add_real("contact.max_overlap_fraction", 1.0, "1", 0.0, 10.0,
             "overlap / smaller radius that stops the run with exit code 3", true);
  // parallel bonds of a bonded body (bonds.hpp)
  s.add_bool("bonds.generate", false, "bond every pair of spheres closer than s_a + s_b + bonds.gap min(s) (a bonded body)");
  s.add_real("bonds.kn", 0.0, "N/m^3", 0.0, 1e30, "bond normal stiffness per unit area (E = kn L0 of the equivalent beam)");
  s.add_real("bonds.ks", 0.0, "N/m^3", 0.0, 1e30, "bond shear stiffness per unit area");
  s.add_real("bonds.sigma_c", 1e300, "Pa", 0.0, 1e300, "bond tensile strength");
  s.add_real("bonds.tau_c", 1e300, "Pa", 0.0, 1e300, "bond shear strength");
  s.add_real("bonds.radius_ratio", 1.0, "1", 0.0, 10.0, "bond radius / smaller sphere radius");
  s.add_real("bonds.gap", 0.01, "1", 0.0, 1.0, "largest gap bonded by the generator, / smaller radius");
  s.add_bool("bonds.from_file", true,
             "use the bonds of initial.file (its /bonds group, e.g. written by mpm2spheres bonds.enabled) when it "
             "has them; false ignores them");
  {
    auto& w = s.add_table_array("wall", "infinite plane walls");
    w.add_vec3("point", Eigen::Vector3d::Zero(), "m", -inf, inf, "a point on the plane");
    w.add_vec3("normal", Eigen::Vector3d::UnitZ(), "1", -inf, inf, "normal pointing into the domain");
  }
  // output
  s.add_string("output.directory", std::string("ssdem_out"), "output directory");
  s.add_real("output.snapshot_interval", 0.0, "s", 0.0, inf, "snapshot interval (0 = none)");
  s.add_real_list("output.times", std::vector<double>{}, "s", 0.0, inf,
                  "extra snapshot times (first block boundary at or after each)");
  s.add_int("output.series_every", 100, 1, 1LL << 40,
            "time-series row every N steps (rounded up to a multiple of gravity.every)");
  s.add_real("output.checkpoint_wall", 600.0, "s", 0.0, inf,
             "checkpoint every this many wall-clock seconds (0 = only at the end / on signals)");
  s.add_int("output.checkpoint_every", 0, 0, 1LL << 40, "checkpoint every N steps (0 = off)");
  s.add_real("output.progress_interval", 10.0, "s", 0.0, inf, "wall-clock seconds between progress lines");
  // run
  s.add_int("run.seed", 1, 0, 1LL << 62, "random seed (keyed by sphere id)");
  s.add_choice("run.teams", TeamMode::automatic, kTeamModes,
               "which loops get an OpenMP team (one process; MPI ranks use size): size = by loop "
               "size; every-pass = also every pass over all spheres (drift, level scan); one-thread "
               "= none of the gated loops (the gravity tree and bonds keep their teams); auto = "
               "whichever of the three is fastest, measured while the run goes (team_tuner.hpp). "
               "Results are the same bits under every rule");
  s.add_int("run.sort_every", 16384, 0, 1LL << 40,
            "renumber the spheres by cells of 2 x the largest radius (z, y, x order) at the start and at the first "
            "gravity-block boundary after every N base steps, so that touching spheres lie near in memory "
            "(sphere_order.hpp; the serial build; 0 = keep the file order). Changes the round-off, not the physics");
  // renamed keys, read with a warning for one release (same names as mpm-frag)
  s.add_alias("output.dir", "output.directory");
  s.add_alias("output.snapshot_every", "output.snapshot_interval");
  s.add_alias("initial.seed", "run.seed");
  return s;
}

namespace {
std::string fmt_g(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}
}  // namespace

Spheres initial_spheres(const common::Scene& sc, BondSet* file_bonds) {
  const InitialSource src = sc.choice("initial.source", kInitialSources);
  Spheres sp;
  if (src == InitialSource::file || src == InitialSource::ss) {
    // an ssdem.spheres file (initial.file) or a pkdgrav .ss file (initial.ss, common/ss_file.hpp)
    const bool ss = src == InitialSource::ss;
    const std::string key = ss ? "initial.ss" : "initial.file";
    const std::string f = sc.string(key);
    if (f.empty())
      throw common::InputError(sc.where(key) + ": required for source = " + std::string(common::choice_name(kInitialSources, src)));
    const common::SphereSet in =
        ss ? common::read_ss(f, common::SsUnits::of(sc.choice("initial.ss_units", common::kSsUnitSystems)))
           : common::read_sphere_set(f);
    common::check_input_spheres(in, f, ss ? "" : "/spheres/");  // .ss: bounds on the SI values, fields unprefixed
    sp = from_sphere_set(in);
    if (sp.size() == 0) throw common::InputError(f + ": no spheres");
    if (file_bonds) *file_bonds = from_bond_table(in.bonds, sp);
    return sp;
  }
  const double R = sc.real("initial.body_radius"), s = sc.real("initial.sphere_radius");
  const double rho = sc.real("initial.density"), jit = sc.real("initial.jitter");
  const auto seed = static_cast<std::uint64_t>(sc.integer("run.seed"));
  if (s > R) throw common::InputError(sc.where("initial.sphere_radius") + ": larger than the body radius");
  {
    // Estimate the generator's sphere count before generating (FCC packing 0.74 of each body's
    // volume) and refuse more than bounds::kMaxGeneratedSpheres.
    const double R2 = src == InitialSource::two_bodies ? sc.real("initial.body2_radius") : 0.0;
    const double est = src == InitialSource::random_pile
                           ? static_cast<double>(sc.integer("initial.count"))
                           : 0.7405 * (std::pow(R / s, 3) + std::pow(R2 / s, 3));
    if (!(est <= common::bounds::kMaxGeneratedSpheres))
      throw common::InputError(sc.where("initial.body_radius") + ", " + sc.where("initial.sphere_radius") +
                               (R2 > 0 ? ", " + sc.where("initial.body2_radius") : std::string()) +
                               ": the generator would create about " + fmt_g(est) + " spheres; at most " +
                               fmt_g(common::bounds::kMaxGeneratedSpheres) + " are allowed (raise initial.sphere_radius or lower the body radius)");
    const Vec3 v0 = sc.vec3("initial.velocity"), w0 = sc.vec3("initial.angular_velocity");
    if (!(v0.norm() + w0.norm() * R <= common::bounds::kMaxSpeed))
      throw common::InputError(sc.where("initial.velocity") + ", " + sc.where("initial.angular_velocity") +
                               ": surface speed |v| + |w| body_radius = " + fmt_g(v0.norm() + w0.norm() * R) +
                               " m/s exceeds the allowed maximum 1e7 m/s");
  }
  if (src == InitialSource::random_pile)
    sp = random_cloud(static_cast<std::size_t>(sc.integer("initial.count")), R, s, rho, seed);
  else
    sp = lattice_pile(R, s, rho, jit, seed);
  const Vec3 v = sc.vec3("initial.velocity"), W = sc.vec3("initial.angular_velocity");
  for (std::size_t i = 0; i < sp.size(); ++i) sp.v[i] = v + W.cross(sp.x[i]);
  if (src == InitialSource::two_bodies) {
    const Spheres b = lattice_pile(sc.real("initial.body2_radius"), s, rho, jit, seed + 1);
    append_body(sp, b, sc.vec3("initial.body2_offset"), sc.vec3("initial.body2_velocity"));
  }
  if (sp.size() == 0) throw common::InputError("initial: the generator produced no spheres");
  return sp;
}

std::string block_input_file(const common::Scene& sc) {
  if (sc.choice("initial.source", kInitialSources) != InitialSource::file || sc.boolean("bonds.generate")) return {};
  const std::string f = sc.string("initial.file");
  if (f.empty() || common::sphere_file_shape(f).bonds) return {};
  return f;
}

SimConfig sim_config(const common::Scene& sc, const Spheres& sp, std::string* info, const BondSet* file_bonds,
                     const std::string& checkpoint) {
  return sim_config(sc, summarise(sp), &sp, info, file_bonds, checkpoint);
}

SimConfig sim_config(const common::Scene& sc, const SphereSummary& sum, const Spheres* all, std::string* info,
                     const BondSet* file_bonds, const std::string& checkpoint) {
  SimConfig c;
  std::ostringstream os;
  c.self_gravity = sc.boolean("gravity.self");
  c.direct_gravity = sc.choice("gravity.solver", kGravitySolvers) == GravitySolver::direct;
  c.gravity.G = sc.real("gravity.G");
  c.gravity.theta = sc.real("gravity.theta");
  c.gravity.bucket = static_cast<int>(sc.integer("gravity.bucket"));
  c.gravity.group = static_cast<int>(sc.integer("gravity.group"));
  c.gravity_every = static_cast<int>(sc.integer("gravity.every"));
  c.adaptive_gravity = c.gravity_every == 0;
  if (c.adaptive_gravity) c.gravity_every = 1;
  c.gravity_tolerance = sc.real("gravity.tolerance");
  c.gravity_max_every = static_cast<int>(sc.integer("gravity.max_every"));
  c.gravity_held = sc.choice("gravity.inner_steps", kGravityInner) == GravityInner::held;
  c.uniform_g = sc.vec3("gravity.uniform");
  c.contacts = sc.boolean("contact.enabled");
  c.min_steps_per_contact = sc.real("time.min_steps_per_contact");
  c.dt = sc.real("time.dt");
  c.multirate = sc.boolean("time.multirate");
  c.teams = sc.choice("run.teams", kTeamModes);
  c.pair_steps_per_contact = sc.real("time.steps_per_contact");
  const double mmax = sum.mmax, smin = sum.smin;
  // bonds (generated, or their contact times) need the spheres themselves
  auto spheres = [&]() -> const Spheres& {
    if (!all) throw std::logic_error("sim_config: bonds need every sphere (no summary-only set-up)");
    return *all;
  };
  if (c.contacts) {
    ContactParams p = builtin_contact_parts().resolve(sc);
    if (sc.choice("contact.preset", kContactPresets) == ContactPreset::gravel) {
      const ContactParams g = gravel_preset(p.kn);
      if (!sc.given("contact.parts")) p.parts = g.parts;
      if (!sc.given("contact.damping.en")) p.en = g.en;
      if (!sc.given("contact.tangential.et")) p.et = g.et;
      if (!sc.given("contact.tangential.mu_s")) p.mu_s = g.mu_s;
      if (!sc.given("contact.rolling.mu_r")) p.mu_r = g.mu_r;
      if (!sc.given("contact.twisting.mu_t")) p.mu_t = g.mu_t;
      if (!sc.given("contact.beta")) p.beta = g.beta;
    }
    double vmax = sc.real("contact.vmax");
    if (p.kn <= 0.0 || p.has(kPartHertz)) {  // Hertz: vmax sets the contact time (dt rule)
      if (vmax <= 0.0) {
        vmax = 1.2 * std::sqrt(2.0 * c.gravity.G * sum.M / sum.R);
        vmax = std::max(vmax, 2.0 * sum.vmax);
        os << "k_n rule: vmax = " << vmax << " m/s (1.2 v_esc or 2 max|v|)\n";
      }
      if (!(vmax > 0)) throw common::InputError(sc.where("contact.vmax") + ": cannot derive k_n (no speed scale); give contact.normal.kn or contact.vmax");
      if (p.has(kPartHertz)) {
        p.vmax = vmax;
        os << "Hertz contact time at vmax = " << vmax << " m/s\n";
      }
    }
    if (p.kn <= 0.0 && !p.has(kPartHertz)) {
      const DtAdvice a = choose_kn_dt(mmax, smin, vmax, (p.parts & kPartDamping) ? p.en : 1.0,
                                      sc.real("contact.overlap_fraction"),
                                      sc.real("time.steps_per_contact"));
      p.kn = a.kn;
      os << "k_n = " << p.kn << " N/m (kinetic rule, m = " << mmax << " kg, s = " << smin << " m)\n";
      if (p.has(kPartCohesion)) {  // cohesion criterion: F_c,max / x_max (contact/cohesion.hpp)
        const double smax = sum.smax;
        const double kc = p.sigma_c * M_PI * p.beta * p.beta * smax * smax /
                          (sc.real("contact.overlap_fraction") * smin);
        if (kc > p.kn) {
          p.kn = kc;
          os << "k_n = " << p.kn << " N/m (cohesion rule F_c,max / x_max)\n";
        }
      }
    }
    c.contact = p;
    for (std::size_t w = 0; w < sc.count("wall"); ++w) {
      const common::Scene e = sc.element("wall", w);
      c.walls.push_back(Plane{e.vec3("point"), e.vec3("normal")});
    }
    c.skin = sc.real("contact.skin");
    c.max_overlap_frac = sc.real("contact.max_overlap_fraction");
    if (!checkpoint.empty()) {
      // a restart: the checkpoint's bonds (generated or from the file at the start) with their broken flags
      if (file_bonds && !file_bonds->empty()) {
        c.bonds = *file_bonds;
        os << c.bonds.size() << " bonds from checkpoint " << checkpoint << " (" << c.bonds.broken_count()
           << " of them broken)\n";
      }
    } else if (sc.boolean("bonds.generate")) {
      BondParams bp;
      bp.kn = sc.real("bonds.kn");
      bp.ks = sc.real("bonds.ks");
      bp.sigma_c = sc.real("bonds.sigma_c");
      bp.tau_c = sc.real("bonds.tau_c");
      bp.radius_ratio = sc.real("bonds.radius_ratio");
      bp.gap = sc.real("bonds.gap");
      c.bonds = generate_bonds(spheres(), bp);
      os << c.bonds.size() << " bonds generated\n";
    }
    if (checkpoint.empty() && file_bonds && !file_bonds->empty() && sc.boolean("bonds.from_file")) {
      if (sc.boolean("bonds.generate"))
        throw common::InputError(sc.where("bonds.generate") + ": the input file " + sc.string("initial.file") +
                                 " has bonds; set bonds.from_file = false to generate bonds instead");
      c.bonds = *file_bonds;
      os << c.bonds.size() << " bonds from " << sc.string("initial.file") << " (" << c.bonds.broken_count()
         << " of them broken)\n";
    }
    const double tau_c = shortest_contact_time(p, sum, !c.walls.empty());
    const double tau_b = c.bonds.empty() ? INFINITY : shortest_bond_time(c.bonds, spheres());
    const double tau_min = std::min(tau_c, tau_b);
    if (c.dt <= 0.0) {
      const double N = sc.real("time.steps_per_contact");
      c.dt = tau_min / N;
      os << "dt = " << c.dt << " s (tau_min / " << N << "; shortest contact "
         << tau_c << " s" << (c.bonds.empty() ? std::string() : ", shortest bond mode " + std::to_string(tau_b) + " s")
         << ")\n";
      if (c.multirate && sc.choice("time.level_anchor", kLevelAnchors) == LevelAnchor::median) {
        const double tau_ref = median_contact_time(p, sum);
        const int m = anchored_levels(tau_ref, tau_min);
        // with the lightest anchor the reference pair gets N r / 2^floor(log2 r) steps (r = tau_ref
        // / tau_min); a finer base step is worth it only where that saves >= 10 %
        const double r = tau_ref / tau_min, save = r / std::exp2(std::floor(std::log2(r)));
        if (m >= 1 && save >= 1.1) {
          // 1e-12 below the exact anchor: rounding in the level rule cannot put the pair a level finer
          c.dt = tau_ref / (N * std::ldexp(1.0, m)) * (1.0 - 1e-12);
          os << "dt = " << c.dt << " s (time.level_anchor = median: the median pair's contact " << tau_ref
             << " s gets " << N << " steps on level " << m << "; the shortest gets " << tau_min / c.dt << ")\n";
        } else {
          os << "time.level_anchor = median not applied: the median pair's contact " << tau_ref << " s already gets "
             << N * save << " steps (< 1.1 N) with the lightest anchor\n";
        }
      }
    }
    const Predictor pred = sc.choice("contact.predictor", kPredictors);
    c.extrapolated_predictor =
        pred == Predictor::extrapolated || (pred == Predictor::automatic && tau_min >= 8.0 * c.dt);
    os << "dashpot velocity predictor: "
       << common::choice_name(kPredictors, c.extrapolated_predictor ? Predictor::extrapolated : Predictor::pkdgrav)
       << (pred == Predictor::automatic ? " (auto: " + std::to_string(tau_min / c.dt) + " steps per shortest contact)" : "") << "\n";
  }
  if (!c.contacts && checkpoint.empty() && file_bonds && !file_bonds->empty() && sc.boolean("bonds.from_file"))
    throw common::InputError(sc.where("contact.enabled") + ": the input file " + sc.string("initial.file") +
                             " has bonds, which need the soft-sphere contacts; enable them or set bonds.from_file = false");
  if (!(c.dt > 0.0))
    throw common::InputError(sc.where("time.dt") + ": must be > 0 when contacts are off");
  if (info) *info = os.str();
  return c;
}

}  // namespace ssdem
