/// @file io_bonds.cpp
/// The bonds of a checkpoint with their state (io_bonds.hpp; layout in ssdem/io.hpp).
#include "io_bonds.hpp"

#include <cstdint>
#include <vector>

#include "vec3_rows.hpp"

namespace ssdem {
using io_rows::flat;
using io_rows::unflat;

bool write_bond_state(hid_t state, const BondSet& b, const common::h5::RowBlock& rows, double released) {
  namespace h5 = common::h5;
  const std::size_t B = b.size();
  h5::Handle bg = h5::create_group(state, "bonds");
  h5::write_attr(bg, "released_energy", released);
  h5::write_attr(bg, "released_base", b.released_base);
  bool ok = true;
  auto col = [&](const char* name, const auto& v, std::size_t w, const char* unit) {
    ok = h5::write_dataset_rows(bg, name, v.data(), B, w, unit, rows) && ok;
  };
  col("id_a", b.id_a, 1, "1");
  col("id_b", b.id_b, 1, "1");
  col("kn", b.kn, 1, "N/m^3");
  col("ks", b.ks, 1, "N/m^3");
  col("sigma_c", b.sigma_c, 1, "Pa");
  col("tau_c", b.tau_c, 1, "Pa");
  col("radius", b.radius, 1, "m");
  col("length0", b.length0, 1, "m");
  col("broken", std::vector<double>(b.broken.begin(), b.broken.end()), 1, "1");
  col("Fs", flat(b.Fs), 3, "N");
  col("Mb", flat(b.Mb), 3, "N m");
  col("n_old", flat(b.n_old), 3, "1");
  col("Mt", b.Mt, 1, "N m");
  col("released", b.released, 1, "J");
  return ok;
}

BondSet read_bond_state(hid_t f, const std::string& path) {
  namespace h5 = common::h5;
  BondSet b;
  const std::string g = "/ssdem_state/bonds/";
  b.id_a = h5::read_u64(f, g + "id_a", -1, 1, path);
  const long long B = static_cast<long long>(b.id_a.size());
  b.id_b = h5::read_u64(f, g + "id_b", B, 1, path);
  b.kn = h5::read_doubles(f, g + "kn", B, 1, path);
  b.ks = h5::read_doubles(f, g + "ks", B, 1, path);
  b.sigma_c = h5::read_doubles(f, g + "sigma_c", B, 1, path);
  b.tau_c = h5::read_doubles(f, g + "tau_c", B, 1, path);
  b.radius = h5::read_doubles(f, g + "radius", B, 1, path);
  b.length0 = h5::read_doubles(f, g + "length0", B, 1, path);
  const auto br = h5::read_doubles(f, g + "broken", B, 1, path);
  b.broken.assign(br.size(), 0);
  for (std::size_t k = 0; k < br.size(); ++k) b.broken[k] = br[k] != 0.0 ? 1 : 0;
  b.Fs = unflat(h5::read_doubles(f, g + "Fs", B, 3, path));
  b.Mb = unflat(h5::read_doubles(f, g + "Mb", B, 3, path));
  b.n_old = unflat(h5::read_doubles(f, g + "n_old", B, 3, path));
  b.Mt = h5::read_doubles(f, g + "Mt", B, 1, path);
  h5::Handle bg = h5::open_group(f, "ssdem_state/bonds", path);
  const double total = h5::read_attr_double(bg, "released_energy", path);
  if (h5::exists(f, g + "released")) {
    b.released = h5::read_doubles(f, g + "released", B, 1, path);
    if (H5Aexists(bg, "released_base") > 0) b.released_base = h5::read_attr_double(bg, "released_base", path);
  } else {  // written before each bond kept its released energy: the total as the base
    b.released.assign(static_cast<std::size_t>(B), 0.0);
    b.released_base = total;
  }
  return b;
}

}  // namespace ssdem
