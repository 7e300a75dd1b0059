/// @file scene_setup.cpp
/// Scene schema and body/particle generation for mpm-frag (no physics here).
#include "mpm/scene_setup.hpp"

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>

#include <spdlog/spdlog.h>

#include "common/finite.hpp"
#include "mpm/body_drive.hpp"
#include "common/status.hpp"

namespace mpmfrag {
namespace {

constexpr double kBig = 1e30;

/// One generated particle (before grouping by material).
struct Gen {
  Eigen::Vector3d x, v;
  double V, m, lp;
  int mat;
  std::uint64_t id;  ///< generation order over every body (the same with or without a part)
};

enum class BodyShape { sphere, box, cylinder };
constexpr std::array kBodyShapes{common::Choice{"sphere", BodyShape::sphere}, common::Choice{"box", BodyShape::box},
                                 common::Choice{"cylinder", BodyShape::cylinder}};

enum class Axis { x, y, z };  // the value is the coordinate index
constexpr std::array kAxes{common::Choice{"x", Axis::x}, common::Choice{"y", Axis::y}, common::Choice{"z", Axis::z}};

enum class Outflow { stop, remove };
constexpr std::array kOutflows{common::Choice{"stop", Outflow::stop}, common::Choice{"remove", Outflow::remove}};

common::Schema body_shapes_sphere() {
  common::Schema s("sphere");
  s.add_vec3("center", std::nullopt, "m", -kBig, kBig, "sphere centre");
  s.add_real("radius", std::nullopt, "m", 0.0, kBig, "sphere radius", true);
  return s;
}
common::Schema body_shapes_box() {
  common::Schema s("box");
  s.add_vec3("min", std::nullopt, "m", -kBig, kBig, "lower corner");
  s.add_vec3("max", std::nullopt, "m", -kBig, kBig, "upper corner");
  return s;
}
common::Schema body_shapes_cylinder() {
  common::Schema s("cylinder");
  s.add_vec3("center", std::nullopt, "m", -kBig, kBig, "centre of the cylinder (mid-length)");
  s.add_choice("axis", Axis::z, kAxes, "cylinder axis");
  s.add_real("radius", std::nullopt, "m", 0.0, kBig, "radius", true);
  s.add_real("length", std::nullopt, "m", 0.0, kBig, "length along the axis (a thin disk: one cell)", true);
  return s;
}

/// The style schema of each body shape (keys valid only for that shape).
std::map<std::string, common::Schema> body_shape_styles() {
  std::map<std::string, common::Schema> styles;
  for (const auto& c : kBodyShapes)
    styles.emplace(c.name, c.value == BodyShape::sphere ? body_shapes_sphere()
                           : c.value == BodyShape::box  ? body_shapes_box()
                                                        : body_shapes_cylinder());
  return styles;
}

}  // namespace

BodyPrimitive make_body_primitive(const common::Scene& b, const std::string& where) {
  BodyPrimitive p;
  const BodyShape shape = b.choice("shape", kBodyShapes);
  if (shape == BodyShape::sphere) {
    const Eigen::Vector3d c = b.vec3("center");
    const double r = b.real("radius");
    p.depth = [c, r](const Eigen::Vector3d& x) { return r - (x - c).norm(); };
    p.lo = c.array() - r;
    p.hi = c.array() + r;
    p.center = c;
    p.volume = 4.0 / 3.0 * M_PI * r * r * r;
    p.radius = r;
  } else if (shape == BodyShape::box) {
    const Eigen::Vector3d lo = b.vec3("min"), hi = b.vec3("max");
    if (!((hi - lo).minCoeff() > 0)) throw common::InputError(where, "max", "box max must exceed min in every axis");
    p.depth = [lo, hi](const Eigen::Vector3d& x) { return std::min((x - lo).minCoeff(), (hi - x).minCoeff()); };
    p.lo = lo;
    p.hi = hi;
    p.center = 0.5 * (lo + hi);
    p.volume = (hi - lo).prod();
  } else {
    const Eigen::Vector3d c = b.vec3("center");
    const double r = b.real("radius"), len = b.real("length");
    const int a = static_cast<int>(b.choice("axis", kAxes));
    p.depth = [c, r, len, a](const Eigen::Vector3d& x) {
      Eigen::Vector3d d = x - c;
      const double along = d[a];
      d[a] = 0;
      return std::min(0.5 * len - std::fabs(along), r - d.norm());
    };
    p.lo = c.array() - r;
    p.hi = c.array() + r;
    p.lo[a] = c[a] - 0.5 * len;
    p.hi[a] = c[a] + 0.5 * len;
    p.center = c;
    p.volume = M_PI * r * r * len;
  }
  return p;
}

int lattice_owner(const std::vector<BodyPrimitive>& earlier, const BodyPrimitive& self, const Eigen::Vector3d& x,
                  double tol, const std::string& where) {
  const double depth = self.depth(x);
  if (depth < -tol) return -1;
  // Tie rule: a lattice point inside an earlier body or within tol of its surface belongs to that
  // body; only a point deeper than tol inside both bodies is an overlap.
  for (std::size_t q = 0; q < earlier.size(); ++q) {
    const double dq = earlier[q].depth(x);
    if (dq < -tol) continue;
    if (dq > tol && depth > tol) throw common::InputError(where, "", "body overlaps body[" + std::to_string(q) + "]");
    return static_cast<int>(q);
  }
  return static_cast<int>(earlier.size());
}

common::Schema mpm_schema(const MaterialRegistry& reg) {
  common::Schema s("mpm-frag scene");
  s.add_vec3("grid.domain_min", std::nullopt, "m", -kBig, kBig, "lower corner of the simulation domain (boundary planes)");
  s.add_vec3("grid.domain_max", std::nullopt, "m", -kBig, kBig, "upper corner of the simulation domain");
  s.add_real("grid.cell_size", std::nullopt, "m", 0.0, kBig, "cubic cell edge h", true);
  s.add_int("grid.ghost_layers", 2, 1, 8, "node layers outside each domain face");
  s.add_choice("grid.outflow", Outflow::stop, kOutflows,
               "a particle whose stencil leaves the grid: stop the run (exit 3, state saved) or remove it "
               "from the grid computation (it then flies ballistically, is kept in <prefix>_outflow.h5 "
               "and stays in the conserved totals)");

  s.add_choice("solver.shape", ShapeKind::ugimp, kShapeKinds, "interpolation: uGIMP (default) or classic linear MPM");
  s.add_choice("solver.scheme", Scheme::musl, kSchemes, "stress-update order");
  s.add_real("solver.flip", 1.0, "1", 0.0, 1.0, "FLIP fraction of the particle velocity update (1 = FLIP, 0 = PIC)");
  s.add_real("solver.courant", 0.3, "1", 0.0, 1.0, "Courant number C in dt = C h / max(s + |v|) (s: the signal speed, with the viscosity's where it acts)", true);
  s.add_real("solver.min_mass_fraction", 0.0, "1", 0.0, 1.0,
             "nodes lighter than this fraction of the smallest particle mass get no acceleration "
             "(0 = off, exact momentum conservation; uGIMP needs none, use ~1e-2 with linear shape functions)");
  s.add_bool("solver.artificial_viscosity.enabled", false, "bulk artificial viscosity (linear + quadratic), for shocks");
  s.add_real("solver.artificial_viscosity.a1", 0.2, "1", 0.0, 10.0, "linear coefficient A1");
  s.add_real("solver.artificial_viscosity.a2", 2.0, "1", 0.0, 10.0, "quadratic coefficient A2");
  s.add_int("solver.reorder_every", 25, 0, 1000000, "steps between particle re-sorting for locality (0 = never)");
  for (const char* f : {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"})
    s.add_choice(std::string("boundary.") + f, BoundaryType::free, kBoundaryTypes,
                 std::string("condition on the domain face ") + f);

  s.add_vec3("gravity.uniform", Eigen::Vector3d::Zero(), "m/s^2", -kBig, kBig,
             "uniform gravitational acceleration (as in ssdem-grav)");

  s.add_real("time.end", std::nullopt, "s", 0.0, kBig, "end time", true);
  s.add_real("time.dt_max", 1e30, "s", 0.0, kBig, "upper bound on dt (the CFL limit always applies)", true);
  s.add_int("time.max_steps", 0, 0, std::numeric_limits<int>::max(), "stop after this many steps (0 = no limit)");

  s.add_string("output.directory", std::string("out"), "output directory (created)");
  s.add_string("output.prefix", std::string("mpm"), "file name prefix");
  s.add_real("output.snapshot_interval", 0.0, "s", 0.0, kBig, "time between particle snapshots (0: initial and final only)");
  s.add_int("output.series_every", 10, 1, 1000000000, "steps between rows of the time-series CSV");
  s.add_real("output.progress_interval", 10.0, "s", 0.0, kBig, "wall-clock seconds between progress lines");
  s.add_real("output.checkpoint_wall", 600.0, "s", 0.0, kBig,
             "checkpoint every this many wall-clock seconds (0 = only at the end / on signals)");
  s.add_int("output.checkpoint_every", 0, 0, 1LL << 40, "checkpoint every N steps (0 = off)");

  s.add_int("run.seed", 0, 0, std::numeric_limits<long long>::max(), "random seed (keyed per particle id)");
  s.add_int("run.backup_every", 20, 1, 1000000000, "steps between copies of the last good state (saved on failure)");
  s.add_int("run.threads", 0, 0, 4096, "OpenMP threads (0 = OMP_NUM_THREADS / all)");
  // renamed keys, read with a warning for one release (same names as ssdem-grav)
  s.add_alias("run.progress_interval", "output.progress_interval");
  s.add_alias("solver.gravity", "gravity.uniform");

  common::Schema& m = s.add_table_array("material", "materials (one per [[material]])", 1);
  m.add_string("name", std::nullopt, "name referenced by bodies");
  m.add_choice("model", std::nullopt, reg.names(), "material style");
  m.add_real("density", std::nullopt, "kg/m^3", 0.0, common::bounds::kMaxDensity,
             "reference density rho0 (physical bound 1e5 kg/m^3)", true);
  m.add_style_switch("model", reg.schemas());

  common::Schema& b = s.add_table_array("body", "bodies (one per [[body]])", 1);
  b.add_string("name", std::string(""), "label (for messages)");
  b.add_string("material", std::nullopt, "name of a [[material]]");
  b.add_choice("shape", std::nullopt, kBodyShapes, "primitive");
  b.add_vec3("velocity", Eigen::Vector3d::Zero(), "m/s", -common::bounds::kMaxSpeed, common::bounds::kMaxSpeed,
             "initial velocity (physical bound 1e7 m/s per component)");
  b.add_vec3("angular_velocity", Eigen::Vector3d::Zero(), "rad/s", -common::bounds::kMaxAngularVelocity,
             common::bounds::kMaxAngularVelocity,
             "initial rigid rotation about the primitive centre");
  b.add_int("ppc", 2, 1, 8, "particles per cell per axis");
  b.add_bool("drive.enabled", false,
             "move the body rigidly at drive.velocity: a velocity condition on the grid nodes it occupies, "
             "its reaction in the series (body_drive.hpp: platens of a lab test); velocity and "
             "angular_velocity are then not used");
  b.add_vec3("drive.velocity", Eigen::Vector3d::Zero(), "m/s", -common::bounds::kMaxSpeed, common::bounds::kMaxSpeed,
             "prescribed velocity of a driven body");
  b.add_real("drive.ramp_time", 0.0, "s", 0.0, kBig, "driven body: linear ramp of the velocity from 0");
  b.add_bool("exact", true,
             "scale particle masses and volumes so that the body's mass is rho0 x its true volume, and shift "
             "its lattice (< h/(2 ppc)) so that its centre of mass is the primitive's centre (false: the raw "
             "lattice, rho0 (h/ppc)^3 per particle)");
  b.add_style_switch("shape", body_shape_styles());
  return s;
}

Setup build_setup(const common::Scene& sc, const MaterialRegistry& reg, const SetupPart* part) {
  Setup st;
  SolverConfig& c = st.solver;
  c.shape = sc.choice("solver.shape", kShapeKinds);
  c.scheme = sc.choice("solver.scheme", kSchemes);
  c.flip = sc.real("solver.flip");
  c.courant = sc.real("solver.courant");
  c.min_mass_fraction = sc.real("solver.min_mass_fraction");
  c.gravity = sc.vec3("gravity.uniform");
  c.artificial_viscosity = sc.boolean("solver.artificial_viscosity.enabled");
  c.av_a1 = sc.real("solver.artificial_viscosity.a1");
  c.av_a2 = sc.real("solver.artificial_viscosity.a2");
  c.reorder_every = static_cast<int>(sc.integer("solver.reorder_every"));
  c.dt_max = sc.real("time.dt_max");
  c.ghost_layers = static_cast<int>(sc.integer("grid.ghost_layers"));
  c.outflow_remove = sc.choice("grid.outflow", kOutflows) == Outflow::remove;
  c.seed = static_cast<std::uint64_t>(sc.integer("run.seed"));
  const char* faces[6] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
  for (int f = 0; f < 6; ++f) c.boundary[f] = sc.choice(std::string("boundary.") + faces[f], kBoundaryTypes);

  RunConfig& r = st.run;
  r.t_end = sc.real("time.end");
  r.max_steps = sc.integer("time.max_steps");
  r.out_dir = sc.string("output.directory");
  r.prefix = sc.string("output.prefix");
  r.snapshot_interval = sc.real("output.snapshot_interval");
  r.series_every = static_cast<int>(sc.integer("output.series_every"));
  r.backup_every = static_cast<int>(sc.integer("run.backup_every"));
  r.progress_interval = sc.real("output.progress_interval");
  r.threads = static_cast<int>(sc.integer("run.threads"));

  const Eigen::Vector3d lo = sc.vec3("grid.domain_min"), hi = sc.vec3("grid.domain_max");
  const double h = sc.real("grid.cell_size");
  if (!((hi - lo).minCoeff() > 0)) throw common::InputError(sc.source(), "grid.domain_max", "must exceed grid.domain_min in every axis");
  if (((hi - lo) / h).maxCoeff() > 4096) throw common::InputError(sc.source(), "grid.cell_size", "more than 4096 cells per axis");
  st.grid = make_grid(lo, hi, h, c.ghost_layers);
  const Eigen::Vector3d dom_hi = st.grid.origin + (st.grid.shape.cast<double>() - Eigen::Vector3d::Constant(1 + c.ghost_layers)) * h;

  // materials
  const std::size_t nm = sc.count("material");
  std::vector<std::string> mat_names;
  std::vector<MaterialSlot> slots(nm);
  for (std::size_t i = 0; i < nm; ++i) {
    const common::Scene e = sc.element("material", i);
    const std::string name = e.string("name");
    for (const auto& n : mat_names)
      if (n == name) throw common::InputError(sc.source(), "material[" + std::to_string(i) + "].name", "duplicate material name '" + name + "'");
    mat_names.push_back(name);
    const StyleInfo* style = reg.find(e.string("model"));
    if (!style) throw common::InputError(sc.source(), "material[" + std::to_string(i) + "].model", "unknown model");
    slots[i].name = name;
    slots[i].style = style;
    try {
      slots[i].model = style->create(e);
    } catch (const std::invalid_argument& ex) {
      throw common::InputError(sc.source(), "material[" + std::to_string(i) + "]", ex.what());
    }
  }

  // bodies -> particles (generation order = id order), then grouped by material
  std::vector<Gen> gen;
  std::uint64_t next_id = 0;
  std::vector<BodyPrimitive> prims;
  std::vector<BodyDrive> drives;
  const std::size_t nb = sc.count("body");
  st.bodies.resize(nb);
  for (std::size_t i = 0; i < nb; ++i) {
    const common::Scene b = sc.element("body", i);
    const std::string where = sc.source() + ": body[" + std::to_string(i) + "]";
    int mat = -1;
    for (std::size_t k = 0; k < nm; ++k)
      if (mat_names[k] == b.string("material")) mat = static_cast<int>(k);
    if (mat < 0) throw common::InputError(where, "material", "no [[material]] named '" + b.string("material") + "'");
    const BodyPrimitive pr = make_body_primitive(b, where);
    if ((pr.lo.array() < lo.array() - 1e-9 * h).any() || (pr.hi.array() > dom_hi.array() + 1e-9 * h).any())
      throw common::InputError(where, "", "body extends outside the domain [grid.domain_min, grid.domain_max]");
    const double tol = kSurfaceTolerance * h;
    for (std::size_t q = 0; q < prims.size(); ++q)  // spheres: the exact test, independent of the lattice
      if (pr.radius > 0 && prims[q].radius > 0 &&
          (pr.center - prims[q].center).norm() < pr.radius + prims[q].radius - tol)
        throw common::InputError(where, "", "body overlaps body[" + std::to_string(q) + "] (the spheres intersect)");
    const int ppc = static_cast<int>(b.integer("ppc"));
    const double dx = h / ppc, V = dx * dx * dx, rho = slots[mat].model->density();
    Eigen::Vector3i c0, c1;
    for (int d = 0; d < 3; ++d) {
      c0[d] = static_cast<int>(std::floor((pr.lo[d] - lo[d]) / h)) - 1;
      c1[d] = static_cast<int>(std::ceil((pr.hi[d] - lo[d]) / h)) + 1;
    }
    // the body's lattice points (owned by no earlier body), in id order
    auto for_points = [&](auto&& f) {
      for (int k = c0[2] * ppc; k < c1[2] * ppc; ++k)
        for (int j = c0[1] * ppc; j < c1[1] * ppc; ++j)
          for (int ii = c0[0] * ppc; ii < c1[0] * ppc; ++ii) {
            const Eigen::Vector3d x = lo + dx * Eigen::Vector3d(ii + 0.5, j + 0.5, k + 0.5);
            if (lattice_owner(prims, pr, x, tol, where) == static_cast<int>(prims.size())) f(x);
          }
    };
    // pass 1: count and lattice centre (nothing stored: a part of a distributed set-up keeps
    // only its own particles, pass 2)
    std::size_t count = 0;
    Eigen::Vector3d com = Eigen::Vector3d::Zero();
    for_points([&](const Eigen::Vector3d& x) {
      ++count;
      com += x;
    });
    if (count == 0) throw common::InputError(where, "", "body contains no particle (smaller than a particle spacing?)");
    const std::uint64_t first = next_id;
    if (b.boolean("drive.enabled"))
      drives.push_back({i, first, first + count, b.vec3("drive.velocity"), b.real("drive.ramp_time")});
    BodyInfo& bi = st.bodies[i];
    bi.name = b.string("name");
    bi.particles = count;
    bi.nominal_mass = rho * pr.volume;
    bi.lattice_mass = rho * V * static_cast<double>(count);
    bi.center = pr.center;
    bi.exact = b.boolean("exact");
    com /= static_cast<double>(count);
    bi.lattice_center = com;
    // Exact body: every particle's mass AND volume scaled by M/(n rho V) (the density stays rho0,
    // so the initial state is stress-free), the lattice shifted by less than dx/2 so that the
    // centre of mass is the primitive's centre.
    const double scale = bi.nominal_mass / bi.lattice_mass;
    const Eigen::Vector3d shift = pr.center - com;
    const bool driven = b.boolean("drive.enabled");  // a driven body starts at v_T(0)
    const Eigen::Vector3d v0 = driven ? drives.back().velocity_at(0.0) : b.vec3("velocity");
    const Eigen::Vector3d w = driven ? Eigen::Vector3d::Zero() : b.vec3("angular_velocity");
    double mass = 0;
    Eigen::Vector3d mx = Eigen::Vector3d::Zero();
    // pass 2: every particle's final state (the body's totals); the part's particles stored
    for_points([&](const Eigen::Vector3d& x) {
      Gen q{x, Eigen::Vector3d::Zero(), V, rho * V, 0.5 * dx, mat, next_id++};
      if (bi.exact) {
        q.x += shift;
        q.V *= scale;
        q.m *= scale;
      }
      q.v = v0 + w.cross(q.x - pr.center);
      mass += q.m;
      mx += q.m * q.x;
      if (part && part->each) part->each(q.x);
      if (!part || (part->keep && part->keep(q.x))) gen.push_back(q);
    });
    bi.mass = mass;
    if (driven) drives.back().mass = mass;  // M_k over every particle, kept or not (SetupPart)
    bi.mass_center = mx / mass;
    bi.velocity = v0;
    prims.push_back(pr);
  }
  ParticleSet& ps = st.particles;
  ps.resize(gen.size(), c.artificial_viscosity);
  std::size_t p = 0;
  for (std::size_t m = 0; m < nm; ++m) {
    slots[m].begin = p;
    for (std::size_t g = 0; g < gen.size(); ++g) {
      if (gen[g].mat != static_cast<int>(m)) continue;
      ps.id[p] = gen[g].id;
      ps.material[p] = static_cast<std::int32_t>(m);
      for (int d = 0; d < 3; ++d) {
        ps.x[3 * p + d] = gen[g].x[d];
        ps.v[3 * p + d] = gen[g].v[d];
        ps.half_width[3 * p + d] = gen[g].lp;
      }
      ps.mass[p] = gen[g].m;
      ps.volume0[p] = ps.volume[p] = gen[g].V;
      ++p;
    }
    slots[m].end = p;
  }
  // drop unused materials? keep them (empty ranges) so indices match the scene order.
  for (auto& s : slots) s.allocate_state();
  st.materials = std::move(slots);
  st.drives = std::move(drives);
  return st;
}

double impact_energy(const std::vector<BodyInfo>& bodies, bool discretised) {
  if (bodies.size() < 2) return 0.0;
  const BodyInfo *t = &bodies[0], *i = &bodies[1];
  if (i->nominal_mass > t->nominal_mass) std::swap(t, i);
  const double mi = discretised ? i->mass : i->nominal_mass, mt = discretised ? t->mass : t->nominal_mass;
  return 0.5 * mi * (i->velocity - t->velocity).squaredNorm() / mt;
}

void log_bodies(const std::vector<BodyInfo>& bodies) {
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const BodyInfo& b = bodies[i];
    const Eigen::Vector3d d = b.mass_center - b.center, s = b.lattice_center - b.center;
    spdlog::info("body[{}] '{}': {} particles, mass {:.10g} kg (nominal rho0 V {:.10g} kg, lattice {:.6g} x nominal{}), "
                 "centre of mass - centre = ({:.3g}, {:.3g}, {:.3g}) m (lattice: ({:.3g}, {:.3g}, {:.3g}) m)",
                 i, b.name, b.particles, b.mass, b.nominal_mass, b.lattice_mass / b.nominal_mass,
                 b.exact ? ", scaled to nominal" : ", body[].exact = false", d[0], d[1], d[2], s[0], s[1], s[2]);
  }
  if (bodies.size() >= 2) {
    const double q = impact_energy(bodies, true), qn = impact_energy(bodies, false);
    spdlog::info("impact: Q = m_imp U^2 / (2 M_target) = {:.10g} J/kg from the particles, {:.10g} J/kg nominal "
                 "(ratio - 1 = {:.3g})", q, qn, q / qn - 1.0);
  }
}

}  // namespace mpmfrag
