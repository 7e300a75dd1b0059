/// @file io.cpp
/// Snapshot and checkpoint files (io.hpp); the sphere arrays go through Spheres::zip_arrays.
#include "ssdem/io.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string_view>
#include <type_traits>
#include <unordered_map>

#include "common/finite.hpp"
#include "common/h5.hpp"
#include "common/run_identity.hpp"
#include "common/status.hpp"
#include "io_bonds.hpp"
#include "vec3_rows.hpp"

namespace ssdem {
namespace {
using io_rows::flat;
using io_rows::unflat;

// Copy one array between the in-memory form (Vec3 rows) and the file form (flat values).
template <class From, class To>
void convert(const std::vector<From>& from, std::vector<To>& to) {
  if constexpr (std::is_same_v<From, To>)
    to = from;
  else if constexpr (std::is_same_v<From, Vec3> && std::is_same_v<To, double>)
    to = flat(from);
  else if constexpr (std::is_same_v<From, double> && std::is_same_v<To, Vec3>)
    to = unflat(from);
  else
    throw std::logic_error("sphere array: element types of the run and the file do not match");
}

// Call f(file array) for the core array of `s` named `name`; returns false if there is none.
template <class Set, class F>
bool with_core_array(Set& s, const char* name, F&& f) {
  bool found = false;
  s.for_each_array([&](const common::SphereArray& a, auto& arr) {
    if (std::string_view(a.name) == name) {
      found = true;
      f(arr);
    }
  });
  return found;
}
}  // namespace

common::SphereSet to_sphere_set(const Spheres& sp, double time, std::int64_t step) {
  common::SphereSet s;
  s.time = time;
  s.step = step;
  s.fields = sp.carried;
  sp.for_each_array([&](const common::SphereArray& a, const auto& arr) {
    if (!with_core_array(s, a.name, [&](auto& to) { convert(arr, to); })) {
      if constexpr (std::is_same_v<typename std::decay_t<decltype(arr)>::value_type, std::uint64_t>)
        throw std::logic_error(std::string("sphere array '") + a.name + "': only float arrays can be fields");
      else
        s.fields.push_back({a.name, a.unit, a.width, flat(arr), {}});
    }
  });
  return s;
}

Spheres from_sphere_set(const common::SphereSet& s) {
  Spheres sp;
  sp.carried = s.fields;
  sp.for_each_array([&](const common::SphereArray& a, auto& arr) {
    if (with_core_array(s, a.name, [&](const auto& from) { convert(from, arr); })) return;
    // not a core array of the file: the field of that name (absent: zero, e.g. a fresh input)
    auto f = std::find_if(sp.carried.begin(), sp.carried.end(),
                          [&](const common::Field& fl) { return fl.name == a.name; });
    if (f == sp.carried.end()) return;
    if (f->ncomp != a.width)
      throw common::InputError("", std::string("/spheres/") + a.name,
                               "has " + std::to_string(f->ncomp) + " components, expected " + std::to_string(a.width));
    convert(f->values, arr);
    sp.carried.erase(f);
  });
  sp.resize(s.count());
  return sp;
}

BondSet from_bond_table(const common::BondTable& t, const Spheres& sp) {
  BondSet b;
  if (t.empty()) return b;
  std::unordered_map<std::uint64_t, std::size_t> row;
  row.reserve(2 * sp.size());
  for (std::size_t i = 0; i < sp.size(); ++i) row.emplace(sp.id[i], i);
  for (std::size_t k = 0; k < t.size(); ++k) {
    const auto a = row.find(t.id_a[k]), c = row.find(t.id_b[k]);
    if (a == row.end() || c == row.end())
      throw common::InputError("bond " + std::to_string(k) + " names a sphere id that is not in the sphere set");
    const Vec3 r = sp.x[c->second] - sp.x[a->second];
    const double d = r.norm();
    b.add(t.id_a[k], t.id_b[k], t.kn[k], t.ks[k], t.sigma_c[k], t.tau_c[k], t.radius[k], t.length0[k],
          d > 0.0 ? Vec3(r / d) : Vec3(Vec3::UnitX()));
    if (!t.broken.empty() && t.broken[k] != 0.0) b.broken.back() = 1;
  }
  return b;
}

common::BondTable to_bond_table(const BondSet& b) {
  common::BondTable t;
  t.id_a = b.id_a;
  t.id_b = b.id_b;
  t.kn = b.kn;
  t.ks = b.ks;
  t.sigma_c = b.sigma_c;
  t.tau_c = b.tau_c;
  t.radius = b.radius;
  t.length0 = b.length0;
  t.broken.assign(b.broken.begin(), b.broken.end());
  return t;
}

void write_snapshot(const std::string& path, const Spheres& sp, double time, std::int64_t step,
                    const common::Provenance& prov, const BondSet* bonds) {
  common::SphereSet set = to_sphere_set(sp, time, step);
  if (bonds && !bonds->empty()) set.bonds = to_bond_table(*bonds);
  common::check_output_spheres(set, path);  // never Inf/NaN in an output: NumericalError (exit 3)
  common::write_sphere_set(path, set, prov);
}

bool write_state_group(long long file, const SimState& st, const StateHeader& h, const common::h5::RowBlock& sph,
                       const common::h5::RowBlock& hist, const common::h5::RowBlock& bond, double bond_released) {
  namespace h5 = common::h5;
  const hid_t f = static_cast<hid_t>(file);
  const std::size_t n = st.a.size();
  h5::Handle g = h5::create_group(f, "ssdem_state");
  h5::write_attr(g, "step", static_cast<std::int64_t>(st.step));
  h5::write_attr(g, "time", st.time);
  h5::write_attr(g, "gravity_step", static_cast<std::int64_t>(st.gravity_step));
  h5::write_attr(g, "dt", h.dt);
  h5::write_attr(g, "gravity_every", static_cast<std::int64_t>(h.gravity_every));
  h5::write_attr(g, "kn", h.kn);
  // the run's initial accounted energy (Diagnostics::accounted), so that a restarted run
  // reports its energy error against the same E_0
  if (std::isfinite(st.energy0)) h5::write_attr(g, "energy0_J", st.energy0);
  if (!h.identity.empty()) {
    h5::write_attr(g, "run_identity", h.identity);
    h5::write_attr(g, "run_identity_digest", common::RunIdentity::parse(h.identity).digest());
  }
  bool ok = true;
  auto vec3 = [&](hid_t loc, const char* name, const std::vector<Vec3>& v, const char* unit, std::size_t rows,
                  const h5::RowBlock& b) {
    const std::vector<double> x = flat(v);
    ok = h5::write_dataset_rows(loc, name, x.data(), rows, 3, unit, b) && ok;
  };
  vec3(g, "a", st.a, "m/s^2", n, sph);
  vec3(g, "alpha", st.alpha, "rad/s^2", n, sph);
  if (h.has_ag) vec3(g, "ag", st.ag, "m/s^2", n, sph);
  if (h.has_prev) {
    vec3(g, "a_prev", st.a_prev, "m/s^2", n, sph);
    vec3(g, "alpha_prev", st.alpha_prev, "rad/s^2", n, sph);
  }
  if (h.has_level) {  // multi-rate levels and previous steps (multirate.hpp)
    std::vector<std::int32_t> lv(st.level.begin(), st.level.end());
    ok = h5::write_dataset_rows(g, "level", lv.data(), n, 1, "1", sph) && ok;
    ok = h5::write_dataset_rows(g, "tau_prev", st.tau_prev.data(), n, 1, "s", sph) && ok;
  }
  if (!st.sphere_order.empty()) {  // a sorted run's storage order (sphere_order.hpp)
    const std::vector<std::uint64_t> rows(st.sphere_order.begin(), st.sphere_order.end());
    ok = h5::write_dataset_rows(g, "sphere_order", rows.data(), n, 1, "1", sph) && ok;
  }
  h5::Handle hg = h5::create_group(g, "history");
  const std::size_t P = st.history.size();
  std::vector<std::uint64_t> ia(P), ib(P);
  for (std::size_t p = 0; p < P; ++p) {
    ia[p] = st.history[p].id_a;
    ib[p] = st.history[p].id_b;
  }
  ok = h5::write_dataset_rows(hg, "id_a", ia.data(), P, 1, "1", hist) && ok;
  ok = h5::write_dataset_rows(hg, "id_b", ib.data(), P, 1, "1", hist) && ok;
  // one dataset per history field of the contact table (contact/table.hpp)
  std::vector<double> buf;
  for (int k = 0; k < kHistVec; ++k) {
    buf.assign(3 * P, 0.0);
    for (std::size_t p = 0; p < P; ++p)
      for (int c = 0; c < 3; ++c) buf[3 * p + c] = st.history[p].v[k][c];
    ok = h5::write_dataset_rows(hg, kHistVecFields[k].name, buf.data(), P, 3, kHistVecFields[k].unit, hist) && ok;
  }
  for (int k = 0; k < kHistScal; ++k) {
    buf.assign(P, 0.0);
    for (std::size_t p = 0; p < P; ++p) buf[p] = st.history[p].q[k];
    ok = h5::write_dataset_rows(hg, kHistScalFields[k].name, buf.data(), P, 1, kHistScalFields[k].unit, hist) && ok;
  }
  if (bond.total > 0) ok = write_bond_state(g, st.bonds, bond, bond_released) && ok;  // io_bonds.cpp
  return ok;
}

void write_checkpoint(const std::string& path, const SimState& st, double dt, int gravity_every,
                      const common::Provenance& prov, double kn, const std::string& identity) {
  const StateHeader h{dt, gravity_every, kn, identity, !st.ag.empty(), !st.a_prev.empty(), !st.level.empty()};
  auto hook = [&](long long fid) {
    if (!write_state_group(fid, st, h, common::h5::RowBlock{0, st.a.size(), H5P_DEFAULT},
                           common::h5::RowBlock{0, st.history.size(), H5P_DEFAULT},
                           common::h5::RowBlock{0, st.bonds.size(), H5P_DEFAULT}, st.bonds.released_total()))
      throw common::IoError("HDF5: writing " + path + " failed (disk full or file not writable?)");
  };
  const common::SphereSet set = to_sphere_set(st.sp, st.time, st.step);
  common::check_output_spheres(set, path);
  common::write_sphere_set(path, set, prov, hook);
}

namespace {
// read_checkpoint, or with `rows` one rank's blocks (read_checkpoint_rows): sph of the spheres and
// per-sphere arrays, hist of the history records.
struct Blocks {
  common::h5::RowRange sph, hist;
};
SimState read_state(const std::string& path, double* dt, int* gravity_every, double* kn, std::string* identity,
                    const Blocks* rows) {
  namespace h5 = common::h5;
  SimState st;
  bool found = false;
  auto hook = [&](long long fid) {
    const hid_t f = static_cast<hid_t>(fid);
    if (!h5::exists(f, "ssdem_state")) return;
    found = true;
    h5::Handle g = h5::open_group(f, "ssdem_state", path);
    st.step = h5::read_attr_int(g, "step", path);
    st.time = h5::read_attr_double(g, "time", path);
    st.gravity_step = h5::read_attr_int(g, "gravity_step", path);
    if (dt) *dt = h5::read_attr_double(g, "dt", path);
    if (gravity_every) *gravity_every = static_cast<int>(h5::read_attr_int(g, "gravity_every", path));
    if (kn) *kn = h5::read_attr_double(g, "kn", path);
    if (H5Aexists(g, "energy0_J") > 0) st.energy0 = h5::read_attr_double(g, "energy0_J", path);
    if (identity)
      *identity = H5Aexists(g, "run_identity") > 0 ? h5::read_attr_string(g, "run_identity", path) : std::string();
    // per-sphere arrays: all rows (their count checked against the spheres' below), or the block
    // (each dataset's shape checked against the spheres' count N by the reader)
    const long long N = rows ? static_cast<long long>(h5::rows(f, "/spheres/id", path)) : -1;
    auto doubles = [&](const char* name, std::size_t w) {
      return rows ? h5::read_doubles(f, name, N, w, path, rows->sph) : h5::read_doubles(f, name, -1, w, path);
    };
    st.a = unflat(doubles("/ssdem_state/a", 3));
    st.alpha = unflat(doubles("/ssdem_state/alpha", 3));
    if (h5::exists(f, "/ssdem_state/ag")) st.ag = unflat(doubles("/ssdem_state/ag", 3));
    if (h5::exists(f, "/ssdem_state/a_prev")) {
      st.a_prev = unflat(doubles("/ssdem_state/a_prev", 3));
      st.alpha_prev = unflat(doubles("/ssdem_state/alpha_prev", 3));
    }
    if (h5::exists(f, "/ssdem_state/level")) {
      const std::vector<std::int32_t> lv = rows ? h5::read_i32(f, "/ssdem_state/level", N, 1, path, rows->sph)
                                                : h5::read_i32(f, "/ssdem_state/level", -1, 1, path);
      for (std::int32_t l : lv)
        if (l < 0 || l > 30) throw common::InputError(path + ": /ssdem_state/level must be in [0, 30]");
      st.level.assign(lv.begin(), lv.end());
      st.tau_prev = doubles("/ssdem_state/tau_prev", 1);
    }
    if (!rows && h5::exists(f, "/ssdem_state/sphere_order")) {  // a sorted run's (sphere_order.hpp)
      const std::vector<std::uint64_t> o = h5::read_u64(f, "/ssdem_state/sphere_order", -1, 1, path);
      st.sphere_order.resize(o.size());
      for (std::size_t k = 0; k < o.size(); ++k) {
        if (o[k] > 0xffffffffULL) throw common::InputError(path + ": /ssdem_state/sphere_order holds a row beyond 2^32");
        st.sphere_order[k] = static_cast<std::uint32_t>(o[k]);
      }
    }
    const char* kIdA = "/ssdem_state/history/id_a";
    const long long P = rows ? static_cast<long long>(h5::rows(f, kIdA, path)) : -1;
    const auto ia = rows ? h5::read_u64(f, kIdA, P, 1, path, rows->hist) : h5::read_u64(f, kIdA, -1, 1, path);
    const long long Pr = rows ? P : static_cast<long long>(ia.size());
    auto hist = [&](const std::string& name, std::size_t w) {
      return rows ? h5::read_doubles(f, name, Pr, w, path, rows->hist) : h5::read_doubles(f, name, Pr, w, path);
    };
    const auto ib = rows ? h5::read_u64(f, "/ssdem_state/history/id_b", Pr, 1, path, rows->hist)
                         : h5::read_u64(f, "/ssdem_state/history/id_b", Pr, 1, path);
    st.history.resize(ia.size());
    for (std::size_t p = 0; p < ia.size(); ++p) {
      st.history[p].id_a = ia[p];
      st.history[p].id_b = ib[p];
    }
    // every field of the table that the file holds (a field it lacks stays zero)
    for (int k = 0; k < kHistVec; ++k) {
      const std::string name = std::string("/ssdem_state/history/") + kHistVecFields[k].name;
      if (!h5::exists(f, name)) continue;
      const auto v = hist(name, 3);
      for (std::size_t p = 0; p < ia.size(); ++p) st.history[p].v[k] = Vec3(v[3 * p], v[3 * p + 1], v[3 * p + 2]);
    }
    for (int k = 0; k < kHistScal; ++k) {
      const std::string name = std::string("/ssdem_state/history/") + kHistScalFields[k].name;
      if (!h5::exists(f, name)) continue;
      const auto v = hist(name, 1);
      for (std::size_t p = 0; p < ia.size(); ++p) st.history[p].q[k] = v[p];
    }
    if (h5::exists(f, "/ssdem_state/bonds")) {
      if (rows) throw std::logic_error(path + ": read_checkpoint_rows of a checkpoint with bonds (read it whole)");
      st.bonds = read_bond_state(f, path);  // io_bonds.cpp
    }
  };
  const common::SphereSet s = rows ? common::read_sphere_rows(path, rows->sph, hook) : common::read_sphere_set(path, hook);
  if (!found) throw common::InputError(path + ": not an ssdem-grav checkpoint (no /ssdem_state group)");
  st.sp = from_sphere_set(s);
  if (st.a.size() != st.sp.size() || st.alpha.size() != st.sp.size())
    throw common::InputError(path + ": /ssdem_state arrays do not match the sphere count");
  return st;
}
}  // namespace

SimState read_checkpoint(const std::string& path, double* dt, int* gravity_every, double* kn, std::string* identity) {
  return read_state(path, dt, gravity_every, kn, identity, nullptr);
}

CheckpointShape checkpoint_shape(const std::string& path) {
  namespace h5 = common::h5;
  const common::SphereFileShape s = common::sphere_file_shape(path);
  h5::Handle f = h5::open_file_read(path);
  if (!h5::exists(f, "ssdem_state"))
    throw common::InputError(path + ": not an ssdem-grav checkpoint (no /ssdem_state group)");
  CheckpointShape c;
  c.spheres = s.count;
  c.history = h5::rows(f, "/ssdem_state/history/id_a", path);
  c.bonds = s.bonds || h5::exists(f, "/ssdem_state/bonds");
  return c;
}

SimState read_checkpoint_rows(const std::string& path, const common::h5::RowRange& spheres,
                              const common::h5::RowRange& history, double* dt, int* gravity_every, double* kn,
                              std::string* identity) {
  const Blocks b{spheres, history};
  return read_state(path, dt, gravity_every, kn, identity, &b);
}

}  // namespace ssdem
