/// @file sphere_file.cpp
/// Writer and reader of `ssdem.spheres` files (sphere_file.hpp); the core arrays come from
/// SphereSet::zip_arrays.
#include "common/sphere_file.hpp"

#include <stdexcept>
#include <type_traits>

#include "common/atomic_file.hpp"
#include "item_file.hpp"

namespace common {

const Field* SphereSet::field(const std::string& name) const {
  for (const auto& f : fields)
    if (f.name == name) return &f;
  return nullptr;
}

bool write_sphere_content(long long file, const SphereSet& s, const Provenance& prov, const h5::RowBlock& block) {
  using namespace detail;
  const hid_t f = static_cast<hid_t>(file);
  const std::size_t n = s.count();
  s.for_each_array([&](const SphereArray& a, const auto& v) { check_size(a.name, v.size(), n, a.width); });
  write_header(f, kSphereFormat, kSphereFormatVersion, s.time, s.step);
  bool ok = true;
  {
    h5::Handle g = h5::create_group(f, "spheres");
    s.for_each_array([&](const SphereArray& a, const auto& v) {
      ok = h5::write_dataset_rows(g, a.name, v.data(), n, a.width, a.unit, block) && ok;
    });
    ok = write_fields(g, s.fields, n, block) && ok;
  }
  if (!s.bonds.empty()) {
    if (block.offset != 0 || block.total != n)
      throw std::logic_error("write_sphere_content: bonds are written only with the whole sphere set");
    write_bonds(f, s.bonds, s.id);
  }
  h5::write_provenance(f, prov);
  return ok;
}

void write_sphere_set(const std::string& path, const SphereSet& s, const Provenance& prov,
                      const H5Hook& extra) {
  const std::size_t n = s.count();
  {
    AtomicPath out(path);
    {
      h5::Handle f = h5::create_file(out.temp_path());
      if (!write_sphere_content(f, s, prov, h5::RowBlock{0, n, H5P_DEFAULT}))
        throw IoError("HDF5: writing " + path + " failed (disk full or file not writable?)");
      if (extra) extra(f);
      h5::save_file(f, out.temp_path(), path);
    }
    out.commit();
  }
  write_sphere_xdmf(path, s, n);
}

void write_sphere_xdmf(const std::string& path, const SphereSet& s, std::size_t n) {
  write_sphere_xdmf(path, s, n, s.bonds.size(), !s.bonds.broken.empty());
}

void write_sphere_xdmf(const std::string& path, const SphereSet& s, std::size_t n, std::size_t bonds, bool broken) {
  using namespace detail;
  XdmfGrid grid{"spheres", s.time, n, basename(path), {}, {}, {}, 0};
  SphereSet::zip_arrays([&](const SphereArray& a) {
    const std::string h5path = std::string("/spheres/") + a.name;
    if (a.geometry)
      grid.position_path = h5path;
    else
      grid.attributes.push_back({a.name, h5path, a.width, a.scalar == SphereScalar::UInt64 ? "UInt" : "Float", 8});
  });
  for (auto& a : field_attributes("/spheres", s.fields)) grid.attributes.push_back(a);
  if (bonds == 0) {
    write_xdmf(xdmf_path_for(path), {grid});
    return;
  }
  // bonds as lines between the sphere positions (bond_file.hpp)
  XdmfGrid lines{"bonds", s.time, n, grid.h5file, grid.position_path, {}, {}, 0};
  lines.connectivity_path = "/bonds/sphere_index";
  lines.elements = bonds;
  BondTable::zip_columns([&](const BondColumn& c, const std::vector<double>&) {
    lines.attributes.push_back({c.name, std::string("/bonds/") + c.name, 1, "Float", 8, "Cell"});
  }, s.bonds);
  if (broken) lines.attributes.push_back({"broken", "/bonds/broken", 1, "Float", 8, "Cell"});
  write_text_atomic(xdmf_path_for(path), xdmf_text_spatial("spheres_and_bonds", {grid, lines}));
}

namespace {
// read_sphere_set, or with `range` the rows of one block (read_sphere_rows).
SphereSet read_spheres(const std::string& path, const H5Hook& extra, const h5::RowRange* range) {
  using namespace detail;
  h5::Handle f = h5::open_file_read(path);
  SphereSet s;
  read_header(f, path, kSphereFormat, kSphereFormatVersion, s.time, s.step);
  h5::Handle g = h5::open_group(f, "spheres", path);
  // The first array (id) sets the count the others must have.
  long long n = -1;
  s.for_each_array([&](const SphereArray& a, auto& v) {
    const std::string p = std::string("/spheres/") + a.name;
    if (n < 0 && range) n = static_cast<long long>(h5::rows(f, p, path));
    if constexpr (std::is_same_v<typename std::decay_t<decltype(v)>::value_type, std::uint64_t>)
      v = range ? h5::read_u64(f, p, n, a.width, path, *range) : h5::read_u64(f, p, n, a.width, path);
    else
      v = range ? h5::read_doubles(f, p, n, a.width, path, *range) : h5::read_doubles(f, p, n, a.width, path);
    if (n < 0) n = static_cast<long long>(v.size() / a.width);
  });
  if (!range) check_unique_ids(path, "/spheres/id", s.id);
  std::vector<std::string> core;
  s.for_each_array([&](const SphereArray& a, const auto& v) {
    core.push_back(a.name);
    if constexpr (std::is_same_v<typename std::decay_t<decltype(v)>::value_type, double>)
      check_values(path, "/spheres/" + core.back(), v, a.width, a.positive, range ? range->offset : 0);
  });
  s.fields = read_fields(f, g, "/spheres", path, static_cast<std::size_t>(n), core, range);
  if (!range) s.bonds = read_bonds(f, path, s.id);
  if (extra) extra(f);
  return s;
}
}  // namespace

SphereSet read_sphere_set(const std::string& path, const H5Hook& extra) { return read_spheres(path, extra, nullptr); }

SphereSet read_sphere_rows(const std::string& path, const h5::RowRange& range, const H5Hook& extra) {
  return read_spheres(path, extra, &range);
}

SphereFileShape sphere_file_shape(const std::string& path) {
  using namespace detail;
  h5::Handle f = h5::open_file_read(path);
  double time = 0;
  std::int64_t step = 0;
  read_header(f, path, kSphereFormat, kSphereFormatVersion, time, step);
  return SphereFileShape{h5::rows(f, "/spheres/id", path), h5::exists(f, "/bonds")};
}

}  // namespace common
