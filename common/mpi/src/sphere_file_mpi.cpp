/// @file sphere_file_mpi.cpp
/// Implementation of common/sphere_file_mpi.hpp (the header states the contract).
#include "common/sphere_file_mpi.hpp"

#include <optional>
#include <stdexcept>

#include "common/agreed.hpp"
#include "common/finite.hpp"
#include "common/h5_parallel.hpp"
#include "common/status.hpp"

namespace common::mpi {
namespace {
std::vector<RowKey> keys_of(const std::vector<std::uint64_t>& row) {
  std::vector<RowKey> k(row.size());
  for (std::size_t i = 0; i < row.size(); ++i) k[i] = RowKey{0, row[i]};
  return k;
}
std::string field_list(const std::vector<Field>& fields) {
  std::string s;
  for (const Field& f : fields) s += f.name + ":" + std::to_string(f.ncomp) + ":" + f.unit + ":" + f.description + ";";
  return s;
}
}  // namespace

struct SphereBlock::Checked {
  std::vector<RowKey> keys, split;
};

// Collective, before any row moves: every rank's input is checked and a fault anywhere is a
// logic_error on every rank (a rank that threw alone would leave the others in the alltoallv).
SphereBlock::Checked SphereBlock::check(Comm& comm, const SphereSet& local, const std::vector<std::uint64_t>& row,
                                        const std::vector<Field>& block_fields, const std::string& path) {
  long long total = static_cast<long long>(row.size());
  comm.sum(&total, 1);
  const auto n = static_cast<std::size_t>(total);
  const std::size_t block = dense_first(n, comm.size, comm.rank + 1) - dense_first(n, comm.size, comm.rank);
  bool ok = row.size() == local.count();
  for (const Field& f : block_fields) ok = ok && f.values.size() == block * f.ncomp;
  if (!comm.all(ok))
    throw std::logic_error("write_sphere_set_mpi: a rank's rows or block fields do not match its spheres or its block (" +
                           path + ")");
  // names, widths, units and descriptions are HDF5 metadata: the same on every rank
  const std::string fields = field_list(block_fields) + "|" + field_list(local.fields);
  if (!comm.all(comm.bcast(fields) == fields))
    throw std::logic_error("write_sphere_set_mpi: the ranks' field lists differ (" + path + ")");
  return Checked{keys_of(row), dense_splitters(n, comm.size)};
}

SphereBlock::SphereBlock(Comm& comm, const SphereSet& local, const std::vector<std::uint64_t>& row,
                         const std::vector<Field>& block_fields, const std::string& path)
    : SphereBlock(comm, check(comm, local, row, block_fields, path), local, block_fields) {}

SphereBlock::SphereBlock(Comm& comm, const Checked& c, const SphereSet& local, const std::vector<Field>& block_fields)
    : plan(comm, c.keys, c.split) {
  set.time = local.time;
  set.step = local.step;
  SphereSet::zip_arrays([&](const SphereArray& a, auto& to, const auto& from) { to = plan.move(from, a.width); },
                        set, local);
  set.fields = block_fields;
  for (const Field& f : local.fields)
    set.fields.push_back(Field{f.name, f.unit, f.ncomp, plan.move(f.values, f.ncomp), f.description});
}

std::uintmax_t sphere_file_bytes(const SphereSet& s, std::size_t total) {
  std::uintmax_t row = 0;
  SphereSet::zip_arrays([&](const SphereArray& a) { row += a.bytes(); });
  for (const Field& f : s.fields) row += 8 * f.ncomp;
  return row * total + (std::uintmax_t{1} << 20) + 16384 * (7 + s.fields.size());
}

BondBlock::BondBlock(Comm& comm, const BondRows& local) {
  const BondTable& t = local.table;
  if (!comm.all(local.row.size() == t.size() && local.index.size() == 2 * t.size() && t.id_b.size() == t.size() &&
                t.broken.size() == t.size()))
    throw std::logic_error("BondBlock: a rank's bond rows do not match its bonds");
  long long n = static_cast<long long>(t.size());
  comm.sum(&n, 1);
  total = static_cast<std::size_t>(n);
  const SortedRows plan(comm, keys_of(local.row), dense_splitters(total, comm.size));
  offset = plan.offset();
  table.id_a = plan.move(t.id_a, 1);
  table.id_b = plan.move(t.id_b, 1);
  index = plan.move(local.index, 2);
  BondTable::zip_columns([&](const BondColumn&, std::vector<double>& to, const std::vector<double>& from) {
    to = plan.move(from, 1);
  }, table, t);
  table.broken = plan.move(t.broken, 1);
}

void write_sphere_set_mpi(Comm& comm, const std::string& path, const SphereSet& local,
                          const std::vector<std::uint64_t>& row, const std::vector<Field>& block_fields,
                          const Provenance& prov, const BondRows* bonds) {
  if (!comm.all(local.bonds.empty())) throw std::logic_error("write_sphere_set_mpi: bonds go in `bonds`");
  if (!comm.all(bonds != nullptr) && !comm.all(bonds == nullptr))
    throw std::logic_error("write_sphere_set_mpi: bonds given on some ranks only (" + path + ")");
  const SphereBlock b(comm, local, row, block_fields, path);
  agreed(comm, [&] { check_output_spheres(b.set, path); });  // a NaN on any rank: nothing written
  std::optional<BondBlock> bb;
  if (bonds) bb.emplace(comm, *bonds);
  const std::size_t nb = bb ? bb->total : 0;
  ParallelFile file(comm, path, sphere_file_bytes(b.set, b.plan.total()) + nb * 96);
  bool ok = write_sphere_content(file.id(), b.set, prov, file.rows(b.plan.offset(), b.plan.total()));
  // the broken column on every rank (BondRows carries it), whether or not its block is empty
  if (nb > 0) ok = write_bond_rows(file.id(), bb->table, bb->index, file.rows(bb->offset, nb), true) && ok;
  file.commit(ok);
  agreed(comm, [&] {  // the sidecar: a failure there fails every rank alike
    if (comm.rank == 0) write_sphere_xdmf(path, b.set, b.plan.total(), nb, nb > 0);
  });
}

}  // namespace common::mpi
