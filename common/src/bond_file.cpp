/// @file bond_file.cpp
/// Writer and validating reader of the `/bonds` group of sphere files (bond_file.hpp).
#include "common/bond_file.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>
#include <utility>

#include "common/bond_columns.hpp"
#include "common/status.hpp"

namespace common {

void BondTable::add(std::uint64_t a, std::uint64_t b, double kn_, double ks_, double sc, double tc, double rb,
                    double L0) {
  push_bond_columns(*this, a, b, kn_, ks_, sc, tc, rb, L0);
}

namespace {
std::unordered_map<std::uint64_t, std::uint64_t> row_of(const std::vector<std::uint64_t>& ids) {
  std::unordered_map<std::uint64_t, std::uint64_t> m;
  m.reserve(2 * ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) m.emplace(ids[i], i);
  return m;
}
std::string num(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}
}  // namespace

void write_bonds(hid_t file, const BondTable& b, const std::vector<std::uint64_t>& sphere_ids) {
  const std::size_t B = b.size();
  const auto bad = [](const std::string& what) { throw InputError("", "/bonds", what); };
  if (b.id_b.size() != B) bad("id_a and id_b differ in length");
  BondTable::zip_columns([&](const BondColumn& c, const std::vector<double>& v) {
    if (v.size() != B) bad(std::string(c.name) + " has " + std::to_string(v.size()) + " rows, expected " + std::to_string(B));
  }, b);
  if (!b.broken.empty() && b.broken.size() != B) bad("broken has the wrong length");
  const auto rows = row_of(sphere_ids);
  std::vector<std::uint64_t> index(2 * B);
  for (std::size_t k = 0; k < B; ++k) {
    const auto a = rows.find(b.id_a[k]), c = rows.find(b.id_b[k]);
    if (a == rows.end() || c == rows.end())
      bad("bond " + std::to_string(k) + " names a sphere id that is not in /spheres/id");
    index[2 * k] = a->second;
    index[2 * k + 1] = c->second;
  }
  if (!write_bond_rows(file, b, index, h5::RowBlock{0, B, H5P_DEFAULT}, !b.broken.empty()))
    throw IoError("HDF5: writing /bonds failed (disk full or file not writable?)");
}

bool write_bond_rows(hid_t file, const BondTable& b, const std::vector<std::uint64_t>& index, const h5::RowBlock& rows,
                     bool broken) {
  const std::size_t B = b.size();
  h5::Handle g = h5::create_group(file, "bonds");
  h5::write_attr(g, "description",
                 std::string("parallel bonds between the spheres id_a and id_b (common/bond_file.hpp); "
                             "sphere_index: their rows in /spheres (XDMF Polyline connectivity)"));
  bool ok = h5::write_dataset_rows(g, "id_a", b.id_a.data(), B, 1, "1", rows);
  ok = h5::write_dataset_rows(g, "id_b", b.id_b.data(), B, 1, "1", rows) && ok;
  ok = h5::write_dataset_rows(g, "sphere_index", index.data(), B, 2, "1", rows) && ok;
  BondTable::zip_columns([&](const BondColumn& c, const std::vector<double>& v) {
    ok = h5::write_dataset_rows(g, c.name, v.data(), B, 1, c.unit, rows) && ok;
  }, b);
  if (broken) ok = h5::write_dataset_rows(g, "broken", b.broken.data(), B, 1, "1", rows) && ok;
  return ok;
}

BondTable read_bonds(hid_t file, const std::string& path, const std::vector<std::uint64_t>& sphere_ids) {
  BondTable b;
  if (!h5::exists(file, "bonds")) return b;
  b.id_a = h5::read_u64(file, "/bonds/id_a", -1, 1, path);
  const long long B = static_cast<long long>(b.id_a.size());
  b.id_b = h5::read_u64(file, "/bonds/id_b", B, 1, path);
  const std::vector<std::uint64_t> index = h5::read_u64(file, "/bonds/sphere_index", B, 2, path);
  BondTable::zip_columns([&](const BondColumn& c, std::vector<double>& v) {
    const std::string ds = std::string("/bonds/") + c.name;
    v = h5::read_doubles(file, ds, B, 1, path);
    const std::string range = std::string(c.lo_open ? "(" : "[") + num(c.lo) + ", " + num(c.hi) + "] " + c.unit;
    for (std::size_t k = 0; k < v.size(); ++k) {
      const bool ok = std::isfinite(v[k]) && (c.lo_open ? v[k] > c.lo : v[k] >= c.lo) && v[k] <= c.hi;
      if (!ok)
        throw InputError(path, ds, "value " + num(v[k]) + " at row " + std::to_string(k) + " outside the valid range " + range);
    }
  }, b);
  if (h5::exists(file, "/bonds/broken")) {
    b.broken = h5::read_doubles(file, "/bonds/broken", B, 1, path);
    for (std::size_t k = 0; k < b.broken.size(); ++k)
      if (b.broken[k] != 0.0 && b.broken[k] != 1.0)
        throw InputError(path, "/bonds/broken", "value " + num(b.broken[k]) + " at row " + std::to_string(k) +
                                                    " (must be 0 = intact or 1 = broken)");
  }
  const auto rows = row_of(sphere_ids);
  std::vector<std::pair<std::uint64_t, std::uint64_t>> pairs(b.size());
  for (std::size_t k = 0; k < b.size(); ++k) {
    for (int e = 0; e < 2; ++e) {
      const std::uint64_t id = e == 0 ? b.id_a[k] : b.id_b[k];
      const auto r = rows.find(id);
      const std::string ds = e == 0 ? "/bonds/id_a" : "/bonds/id_b";
      if (r == rows.end())
        throw InputError(path, ds, "id " + std::to_string(id) + " at row " + std::to_string(k) +
                                       " is not a sphere of /spheres/id (bonds must join spheres of the file)");
      if (index[2 * k + e] != r->second)
        throw InputError(path, "/bonds/sphere_index", "row " + std::to_string(k) + " gives sphere row " +
                                                          std::to_string(index[2 * k + e]) + " but id " + std::to_string(id) +
                                                          " is at row " + std::to_string(r->second));
    }
    if (b.id_a[k] == b.id_b[k])
      throw InputError(path, "/bonds/id_b", "row " + std::to_string(k) + " bonds sphere " + std::to_string(b.id_a[k]) +
                                                " to itself");
    pairs[k] = {std::min(b.id_a[k], b.id_b[k]), std::max(b.id_a[k], b.id_b[k])};
  }
  std::vector<std::size_t> order(pairs.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return pairs[x] < pairs[y] || (pairs[x] == pairs[y] && x < y); });
  for (std::size_t k = 1; k < order.size(); ++k)
    if (pairs[order[k]] == pairs[order[k - 1]])
      throw InputError(path, "/bonds/id_a", "spheres " + std::to_string(pairs[order[k]].first) + " and " +
                                                std::to_string(pairs[order[k]].second) + " are bonded twice (rows " +
                                                std::to_string(order[k - 1]) + " and " + std::to_string(order[k]) + ")");
  return b;
}

}  // namespace common
