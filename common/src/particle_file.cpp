/// @file particle_file.cpp
/// Implementation of common/particle_file.hpp (the header states the contract, and for physics the equations and sources).
#include "common/particle_file.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>

#include "common/atomic_file.hpp"
#include "item_file.hpp"

namespace common {

namespace detail {
std::vector<Field> read_fields(hid_t f, hid_t g, const std::string& group, const std::string& file,
                               std::size_t n, const std::vector<std::string>& skip, const h5::RowRange* range) {
  std::vector<Field> out;
  std::vector<std::string> names;
  auto collect = [](hid_t, const char* name, const H5L_info_t*, void* op) -> herr_t {
    static_cast<std::vector<std::string>*>(op)->push_back(name);
    return 0;
  };
  H5Literate(g, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect, &names);
  for (const auto& nm : names) {
    if (std::find(skip.begin(), skip.end(), nm) != skip.end()) continue;
    const std::string full = group + "/" + nm;
    H5O_info_t info;
    if (H5Oget_info_by_name2(g, nm.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0 || info.type != H5O_TYPE_DATASET)
      throw InputError(file, full, "not a dataset: " + group + " holds only datasets");
    h5::Handle ds(H5Dopen2(g, nm.c_str(), H5P_DEFAULT));
    if (!ds.valid()) throw InputError(file, full, "cannot open dataset (corrupt file?)");
    h5::Handle type(H5Dget_type(ds));
    if (!(H5Tget_class(type) == H5T_FLOAT && H5Tget_size(type) == 8))
      throw InputError(file, full, "wrong dtype: extra datasets (fields) must be float64");
    const auto d = h5::shape(f, full, file);
    const std::size_t ncomp = d.size() == 2 && d[1] >= 2 ? d[1] : 1;  // (n, 1), (n, 0): refused below
    Field fl;
    fl.name = nm;
    fl.ncomp = ncomp;
    fl.values = range ? h5::read_doubles(f, full, static_cast<long long>(n), ncomp, file, *range)
                      : h5::read_doubles(f, full, static_cast<long long>(n), ncomp, file);
    fl.unit = h5::unit_of(g, nm);
    check_values(file, full, fl.values, ncomp, false, range ? range->offset : 0);
    out.push_back(std::move(fl));
  }
  return out;
}
}  // namespace detail

const Field* ParticleSnapshot::field(const std::string& name) const {
  for (const auto& f : fields)
    if (f.name == name) return &f;
  return nullptr;
}

bool write_particle_content(long long file, const ParticleSnapshot& s, const Provenance& prov,
                            const h5::RowBlock& block) {
  using namespace detail;
  const hid_t f = static_cast<hid_t>(file);
  const std::size_t n = s.count();
  check_size("position", s.position.size(), n, 3);
  check_size("velocity", s.velocity.size(), n, 3);
  check_size("mass", s.mass.size(), n, 1);
  check_size("volume", s.volume.size(), n, 1);
  check_size("size", s.size.size(), n, 3);
  check_size("material", s.material.size(), n, 1);
  write_header(f, kParticleFormat, kParticleFormatVersion, s.time, s.step);
  {
    h5::Handle g = h5::create_group(f, "grid");
    h5::write_attr(g, "origin", std::vector<double>(s.grid.origin.data(), s.grid.origin.data() + 3));
    h5::write_attr(g, "cell_size", std::vector<double>(s.grid.cell_size.data(), s.grid.cell_size.data() + 3));
    h5::write_attr(g, "shape", std::vector<std::int64_t>{s.grid.shape[0], s.grid.shape[1], s.grid.shape[2]});
    h5::write_attr(g, "unit", std::string("m"));
  }
  bool ok = true;
  {
    h5::Handle g = h5::create_group(f, "particles");
    ok = h5::write_dataset_rows(g, "id", s.id.data(), n, 1, "1", block) && ok;
    ok = h5::write_dataset_rows(g, "position", s.position.data(), n, 3, "m", block) && ok;
    ok = h5::write_dataset_rows(g, "velocity", s.velocity.data(), n, 3, "m/s", block) && ok;
    ok = h5::write_dataset_rows(g, "mass", s.mass.data(), n, 1, "kg", block) && ok;
    ok = h5::write_dataset_rows(g, "volume", s.volume.data(), n, 1, "m^3", block) && ok;
    ok = h5::write_dataset_rows(g, "size", s.size.data(), n, 3, "m", block) && ok;
    ok = h5::write_dataset_rows(g, "material", s.material.data(), n, 1, "1", block) && ok;
    ok = write_fields(g, s.fields, n, block) && ok;
  }
  h5::write_provenance(f, prov);
  return ok;
}

void write_particle_xdmf(const std::string& path, const ParticleSnapshot& s, std::size_t n) {
  using namespace detail;
  XdmfGrid grid{"particles", s.time, n, basename(path), "/particles/position", {}, {}, 0};
  grid.attributes = {{"id", "/particles/id", 1, "UInt", 8},
                     {"velocity", "/particles/velocity", 3, "Float", 8},
                     {"mass", "/particles/mass", 1, "Float", 8},
                     {"volume", "/particles/volume", 1, "Float", 8},
                     {"size", "/particles/size", 3, "Float", 8},
                     {"material", "/particles/material", 1, "Int", 4}};
  for (auto& a : field_attributes("/particles", s.fields)) grid.attributes.push_back(a);
  write_xdmf(xdmf_path_for(path), {grid});
}

void write_particle_snapshot(const std::string& path, const ParticleSnapshot& s,
                             const Provenance& prov, const H5Hook& extra) {
  {
    AtomicPath out(path);
    {
      h5::Handle f = h5::create_file(out.temp_path());
      if (!write_particle_content(f, s, prov, h5::RowBlock{0, s.count(), H5P_DEFAULT}))
        throw IoError("HDF5: writing " + path + " failed (disk full or file not writable?)");
      if (extra) extra(f);
      h5::save_file(f, out.temp_path(), path);
    }
    out.commit();
  }
  write_particle_xdmf(path, s, s.count());
}

ParticleSnapshot read_particle_snapshot(const std::string& path, const H5Hook& extra) {
  using namespace detail;
  h5::Handle f = h5::open_file_read(path);
  ParticleSnapshot s;
  read_header(f, path, kParticleFormat, kParticleFormatVersion, s.time, s.step);
  {
    h5::Handle g = h5::open_group(f, "grid", path);
    const auto o = h5::read_attr_doubles(g, "origin", path);
    const auto h = h5::read_attr_doubles(g, "cell_size", path);
    const auto sh = h5::read_attr_ints(g, "shape", path);
    if (o.size() != 3 || h.size() != 3 || sh.size() != 3)
      throw InputError(path, "/grid", "origin, cell_size and shape must have 3 entries each");
    for (int d = 0; d < 3; ++d) {
      if (!std::isfinite(o[d])) throw InputError(path, "/grid/origin", "non-finite value");
      if (!(h[d] > 0.0) || !std::isfinite(h[d])) throw InputError(path, "/grid/cell_size", "must be finite and > 0");
      if (sh[d] < 2) throw InputError(path, "/grid/shape", "node counts must be >= 2");
      s.grid.origin[d] = o[d];
      s.grid.cell_size[d] = h[d];
      s.grid.shape[d] = static_cast<int>(sh[d]);
    }
  }
  h5::Handle g = h5::open_group(f, "particles", path);
  s.id = h5::read_u64(f, "/particles/id", -1, 1, path);
  check_unique_ids(path, "/particles/id", s.id);
  const auto n = static_cast<long long>(s.id.size());
  s.position = h5::read_doubles(f, "/particles/position", n, 3, path);
  s.velocity = h5::read_doubles(f, "/particles/velocity", n, 3, path);
  s.mass = h5::read_doubles(f, "/particles/mass", n, 1, path);
  s.volume = h5::read_doubles(f, "/particles/volume", n, 1, path);
  s.size = h5::read_doubles(f, "/particles/size", n, 3, path);
  s.material = h5::read_i32(f, "/particles/material", n, 1, path);
  check_values(path, "/particles/position", s.position, 3, false);
  check_values(path, "/particles/velocity", s.velocity, 3, false);
  check_values(path, "/particles/mass", s.mass, 1, true);
  check_values(path, "/particles/volume", s.volume, 1, true);
  check_values(path, "/particles/size", s.size, 3, true);
  s.fields = read_fields(f, g, "/particles", path, s.id.size(),
                         {"id", "position", "velocity", "mass", "volume", "size", "material"});
  if (extra) extra(f);
  return s;
}

}  // namespace common
