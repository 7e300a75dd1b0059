#include "common/sphere_file.hpp"

#include "common/atomic_file.hpp"
#include "item_file.hpp"

namespace common {

const Field* SphereSet::field(const std::string& name) const {
  for (const auto& f : fields)
    if (f.name == name) return &f;
  return nullptr;
}

void write_sphere_set(const std::string& path, const SphereSet& s, const Provenance& prov,
                      const H5Hook& extra) {
  using namespace detail;
  const std::size_t n = s.count();
  check_size("position", s.position.size(), n, 3);
  check_size("velocity", s.velocity.size(), n, 3);
  check_size("spin", s.spin.size(), n, 3);
  check_size("mass", s.mass.size(), n, 1);
  check_size("radius", s.radius.size(), n, 1);
  {
    AtomicPath out(path);
    {
      h5::Handle f = h5::create_file(out.temp_path());
      write_header(f, kSphereFormat, kSphereFormatVersion, s.time, s.step);
      {
        h5::Handle g = h5::create_group(f, "spheres");
        h5::write_dataset(g, "id", s.id.data(), n, 1, "1");
        h5::write_dataset(g, "position", s.position.data(), n, 3, "m");
        h5::write_dataset(g, "velocity", s.velocity.data(), n, 3, "m/s");
        h5::write_dataset(g, "spin", s.spin.data(), n, 3, "rad/s");
        h5::write_dataset(g, "mass", s.mass.data(), n, 1, "kg");
        h5::write_dataset(g, "radius", s.radius.data(), n, 1, "m");
        write_fields(g, s.fields, n);
      }
      h5::write_provenance(f, prov);
      if (extra) extra(f);
      h5::save_file(f, out.temp_path(), path);
    }
    out.commit();
  }
  XdmfGrid grid{"spheres", s.time, n, basename(path), "/spheres/position", {}};
  grid.attributes = {{"id", "/spheres/id", 1, "UInt", 8},
                     {"velocity", "/spheres/velocity", 3, "Float", 8},
                     {"spin", "/spheres/spin", 3, "Float", 8},
                     {"mass", "/spheres/mass", 1, "Float", 8},
                     {"radius", "/spheres/radius", 1, "Float", 8}};
  for (auto& a : field_attributes("/spheres", s.fields)) grid.attributes.push_back(a);
  write_xdmf(xdmf_path_for(path), {grid});
}

SphereSet read_sphere_set(const std::string& path, const H5Hook& extra) {
  using namespace detail;
  h5::Handle f = h5::open_file_read(path);
  SphereSet s;
  read_header(f, path, kSphereFormat, kSphereFormatVersion, s.time, s.step);
  h5::Handle g = h5::open_group(f, "spheres", path);
  s.id = h5::read_u64(f, "/spheres/id", -1, 1, path);
  check_unique_ids(path, "/spheres/id", s.id);
  const auto n = static_cast<long long>(s.id.size());
  s.position = h5::read_doubles(f, "/spheres/position", n, 3, path);
  s.velocity = h5::read_doubles(f, "/spheres/velocity", n, 3, path);
  s.spin = h5::read_doubles(f, "/spheres/spin", n, 3, path);
  s.mass = h5::read_doubles(f, "/spheres/mass", n, 1, path);
  s.radius = h5::read_doubles(f, "/spheres/radius", n, 1, path);
  check_values(path, "/spheres/position", s.position, 3, false);
  check_values(path, "/spheres/velocity", s.velocity, 3, false);
  check_values(path, "/spheres/spin", s.spin, 3, false);
  check_values(path, "/spheres/mass", s.mass, 1, true);
  check_values(path, "/spheres/radius", s.radius, 1, true);
  s.fields = read_fields(f, g, "/spheres", path, s.id.size(),
                         {"id", "position", "velocity", "spin", "mass", "radius"});
  if (extra) extra(f);
  return s;
}

}  // namespace common
