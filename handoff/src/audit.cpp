/// @file audit.cpp
/// Implementation of handoff/audit.hpp (the header states the contract, and for physics the equations and sources).
#include "handoff/audit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/h5.hpp"

namespace handoff {

namespace {
double rms_speed(const Invariants& i) { return i.mass > 0 ? std::sqrt(2.0 * i.kinetic_translational / i.mass) : 0.0; }

std::string num(double x) {
  if (!std::isfinite(x)) return "null";
  std::ostringstream o;
  o.precision(17);
  o << x;
  return o.str();
}
std::string vec(const Eigen::Vector3d& v) {
  std::string s("[");  // appended, not "[" + ...: GCC 12 warns falsely on that (-Wrestrict, bug 105329)
  s.append(num(v[0])).append(", ").append(num(v[1])).append(", ").append(num(v[2])).append("]");
  return s;
}

std::string inv_json(const Invariants& i) {
  std::ostringstream o;
  o << "{\"count\": " << i.count << ", \"mass\": " << num(i.mass) << ", \"centre_of_mass\": " << vec(i.centre_of_mass)
    << ", \"momentum\": " << vec(i.momentum) << ", \"angular_momentum_about_com\": " << vec(i.angular_momentum)
    << ", \"kinetic_translational\": " << num(i.kinetic_translational)
    << ", \"kinetic_rotational\": " << num(i.kinetic_rotational) << ", \"kinetic\": " << num(i.kinetic()) << "}";
  return o.str();
}

void inv_h5(hid_t g, const std::string& prefix, const Invariants& i) {
  namespace h5 = common::h5;
  auto v3 = [](const Eigen::Vector3d& v) { return std::vector<double>{v[0], v[1], v[2]}; };
  h5::write_attr(g, prefix + "count", static_cast<std::int64_t>(i.count));
  h5::write_attr(g, prefix + "mass", i.mass);
  h5::write_attr(g, prefix + "centre_of_mass", v3(i.centre_of_mass));
  h5::write_attr(g, prefix + "momentum", v3(i.momentum));
  h5::write_attr(g, prefix + "angular_momentum_about_com", v3(i.angular_momentum));
  h5::write_attr(g, prefix + "kinetic_translational", i.kinetic_translational);
  h5::write_attr(g, prefix + "kinetic_rotational", i.kinetic_rotational);
}
}  // namespace

double Audit::mass_error_relative() const { return before.mass > 0 ? (after.mass - before.mass) / before.mass : 0.0; }
double Audit::momentum_error_relative() const {
  const double scale = before.mass * rms_speed(before);
  return scale > 0 ? (after.momentum - before.momentum).norm() / scale : 0.0;
}
double Audit::angular_momentum_error_relative() const {
  const double scale = std::max(before.angular_momentum.norm(), before.angular_momentum_scale);
  return scale > 0 ? (after.angular_momentum - before.angular_momentum).norm() / scale : 0.0;
}

double min_sphere_gap(const ProjectionResult& r) {
  const auto& s = r.spheres;
  const std::size_t n = r.cell.size();  // the projection's spheres (outflow spheres follow them)
  double best = std::numeric_limits<double>::infinity();
  const Eigen::Vector3i sh = r.cell_shape;
  const std::int64_t ncells = std::int64_t(sh[0]) * sh[1] * sh[2];
  // Sphere index by cell: a dense table when it is small enough, else binary search in r.cell
  // (sorted ascending: spheres are emitted in cell order).
  std::vector<std::int32_t> dense;
  if (ncells <= (std::int64_t(1) << 27) && n < (std::size_t(1) << 31)) {
    dense.assign(static_cast<std::size_t>(ncells), -1);
    for (std::size_t i = 0; i < n; ++i) dense[r.cell[i]] = static_cast<std::int32_t>(i);
  }
  auto find = [&](std::int64_t key) -> std::int64_t {
    if (!dense.empty()) return dense[key];
    const auto it = std::lower_bound(r.cell.begin(), r.cell.end(), key);
    return (it == r.cell.end() || *it != key) ? -1 : it - r.cell.begin();
  };
#pragma omp parallel for reduction(min : best) schedule(static)
  for (std::int64_t a = 0; a < static_cast<std::int64_t>(n); ++a) {
    const std::int64_t c = r.cell[a];
    // 32-bit division: cell indices are < 2^32 (project_to_spheres refuses larger grids).
    const auto c32 = static_cast<std::uint32_t>(c), sx = static_cast<std::uint32_t>(sh[0]), sy = static_cast<std::uint32_t>(sh[1]);
    const std::uint32_t cxy = c32 / sx;
    const int cx = static_cast<int>(c32 - cxy * sx), cy = static_cast<int>(cxy % sy), cz = static_cast<int>(cxy / sy);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = cx + dx, y = cy + dy, z = cz + dz;
          if (x < 0 || y < 0 || z < 0 || x >= sh[0] || y >= sh[1] || z >= sh[2]) continue;
          const std::int64_t key = x + std::int64_t(sh[0]) * (y + std::int64_t(sh[1]) * z);
          if (key <= c) continue;  // each pair once
          const std::int64_t found = find(key);
          if (found < 0) continue;
          const std::size_t b = static_cast<std::size_t>(found);
          const Eigen::Vector3d d = Eigen::Vector3d(&s.position[3 * a]) - Eigen::Vector3d(&s.position[3 * b]);
          // gap = |d| - ra - rb improves on best only if |d| < best + ra + rb: the square root is
          // taken for those pairs alone (on a filled lattice every pair but the first is skipped).
          const double rr = s.radius[a] + s.radius[b], lim = best + rr;
          const double d2 = d.squaredNorm();
          if (lim > 0.0 && d2 < lim * lim) best = std::min(best, std::sqrt(d2) - rr);
        }
  }
  return best;
}

std::string audit_text(const Audit& a) {
  std::ostringstream o;
  o.precision(6);
  o << "hand-off audit (method " << a.method << ")\n"
    << "  particles in file " << a.input.count << ", handed off " << a.before.count << ", dropped " << a.dropped.count
    << "; occupied MPM cells " << a.occupied_mpm_cells << "; spheres " << a.after.count << " (cell " << a.sphere_cell
    << " m)\n";
  if (a.outflow_particles > 0)
    o << "  outflow: " << a.outflow_particles << " particles that left the grid -> " << a.outflow_spheres
      << " spheres outside it (the rest merged into edge spheres)\n";
  o
    << std::scientific << "  mass       before " << a.before.mass << " kg, after " << a.after.mass
    << " kg, rel. diff " << a.mass_error_relative() << "\n"
    << "  momentum   before " << a.before.momentum.transpose() << " kg m/s, |diff|/(M v_rms) "
    << a.momentum_error_relative() << "\n"
    << "  ang. mom.  before " << a.before.angular_momentum.transpose() << ", after "
    << a.after.angular_momentum.transpose() << " kg m^2/s, rel. diff " << a.angular_momentum_error_relative() << "\n"
    << "  kinetic    before " << a.before.kinetic() << " J, after " << a.after.kinetic() << " J (rot. "
    << a.after.kinetic_rotational << " J), loss " << a.kinetic_loss() << " J = " << 100.0 * a.kinetic_loss_relative()
    << " %\n"
    << "  centre of mass moved by " << (a.after.centre_of_mass - a.before.centre_of_mass).norm() << " m\n"
    << "  dropped mass " << a.dropped.mass << " kg, momentum " << a.dropped.momentum.transpose() << " kg m/s\n"
    << "  closest sphere pair: gap " << a.min_gap << " m, max overlap " << a.max_overlap << " m\n";
  if (!a.note.empty()) o << "  note: " << a.note << "\n";
  return o.str();
}

std::string audit_json(const Audit& a) {
  std::ostringstream o;
  o << "{\n  \"method\": \"" << a.method << "\",\n  \"input\": " << inv_json(a.input) << ",\n  \"before\": "
    << inv_json(a.before) << ",\n  \"after\": " << inv_json(a.after) << ",\n  \"dropped\": " << inv_json(a.dropped)
    << ",\n  \"occupied_mpm_cells\": " << a.occupied_mpm_cells << ",\n  \"sphere_cell_size\": " << num(a.sphere_cell)
    << ",\n  \"outflow_particles\": " << a.outflow_particles << ",\n  \"outflow_spheres\": " << a.outflow_spheres
    << ",\n  \"mass_rel_diff\": " << num(a.mass_error_relative())
    << ",\n  \"momentum_abs_diff\": " << vec(a.after.momentum - a.before.momentum)
    << ",\n  \"momentum_rel_diff\": " << num(a.momentum_error_relative())
    << ",\n  \"angular_momentum_abs_diff\": " << vec(a.after.angular_momentum - a.before.angular_momentum)
    << ",\n  \"angular_momentum_rel_diff\": " << num(a.angular_momentum_error_relative())
    << ",\n  \"kinetic_abs_loss\": " << num(a.kinetic_loss())
    << ",\n  \"kinetic_rel_loss\": " << num(a.kinetic_loss_relative())
    << ",\n  \"centre_of_mass_shift\": " << num((a.after.centre_of_mass - a.before.centre_of_mass).norm())
    << ",\n  \"min_gap\": " << num(a.min_gap) << ",\n  \"max_overlap\": " << num(a.max_overlap)
    << ",\n  \"exact\": " << (a.exact ? "true" : "false") << ",\n  \"note\": \"" << a.note << "\"\n}\n";
  return o.str();
}

void write_audit_h5(long long file, const Audit& a) {
  namespace h5 = common::h5;
  h5::Handle g = h5::create_group(static_cast<hid_t>(file), "audit");
  h5::write_attr(g, "method", a.method);
  inv_h5(g, "input_", a.input);
  inv_h5(g, "before_", a.before);
  inv_h5(g, "after_", a.after);
  inv_h5(g, "dropped_", a.dropped);
  h5::write_attr(g, "occupied_mpm_cells", static_cast<std::int64_t>(a.occupied_mpm_cells));
  h5::write_attr(g, "sphere_cell_size", a.sphere_cell);
  h5::write_attr(g, "outflow_particles", static_cast<std::int64_t>(a.outflow_particles));
  h5::write_attr(g, "outflow_spheres", static_cast<std::int64_t>(a.outflow_spheres));
  h5::write_attr(g, "mass_rel_diff", a.mass_error_relative());
  h5::write_attr(g, "momentum_rel_diff", a.momentum_error_relative());
  h5::write_attr(g, "angular_momentum_rel_diff", a.angular_momentum_error_relative());
  h5::write_attr(g, "kinetic_abs_loss", a.kinetic_loss());
  h5::write_attr(g, "kinetic_rel_loss", a.kinetic_loss_relative());
  h5::write_attr(g, "min_gap", a.min_gap);
  h5::write_attr(g, "max_overlap", a.max_overlap);
  h5::write_attr(g, "exact", static_cast<std::int64_t>(a.exact));
  h5::write_attr(g, "note", a.note);
  h5::write_attr(g, "units", std::string("SI: kg, m, s, J; relative diffs dimensionless"));
}

}  // namespace handoff
