/// @file outflow_mpi.cpp
/// Outflow removal on MPI ranks (mpm/mpi/domain.hpp): each rank removes the particles of its
/// box whose stencil leaves the grid (Solver, outflow.cpp: the serial code) and keeps their
/// record; the totals of the removed particles are part of each rank's diagnostics, summed in
/// rank order. The records stay on their ranks: the outflow file and the checkpoints write them
/// collectively (local_outflow, then rows sorted by (removal time, id) across the ranks), so the
/// files do not depend on the rank count or on which rank removed a particle. Every rank's field
/// list is merged in rank order, fields matched by name (a particle from a rank without a field
/// gets the field's initial value, as in Solver::remove_particles):
///   field list of a rank = count | per field: name, unit, description, ncomp, initial
/// gather_outflow puts the whole record on one rank (tests compare the collective files with it):
///   record of a rank = row count | field list | per particle: every non-empty ParticleSet array,
///                      removal time, fields
#include <algorithm>
#include <cstring>
#include <numeric>

#include "mpm/checkpoint.hpp"
#include "mpm/mpi/domain.hpp"

namespace mpmfrag::mpi {

namespace {
void put_string(std::vector<char>& b, const std::string& s) {
  put(b, static_cast<std::uint64_t>(s.size()));
  b.insert(b.end(), s.begin(), s.end());
}
std::string get_string(const std::vector<char>& b, std::size_t& off) {
  const std::size_t n = static_cast<std::size_t>(get<std::uint64_t>(b, off));
  std::string s(b.begin() + static_cast<std::ptrdiff_t>(off), b.begin() + static_cast<std::ptrdiff_t>(off + n));
  off += n;
  return s;
}
void put_fields(std::vector<char>& buf, const SolverResume& r) {
  put(buf, static_cast<std::uint64_t>(r.outflow_fields.size()));
  for (std::size_t f = 0; f < r.outflow_fields.size(); ++f) {
    const common::Field& fl = r.outflow_fields[f];
    put_string(buf, fl.name);
    put_string(buf, fl.unit);
    put_string(buf, fl.description);
    put(buf, static_cast<std::uint64_t>(fl.ncomp));
    put(buf, r.outflow_init[f]);
  }
}
/// Read one rank's field list at `off` and merge it into rec.fields / rec.init (a new field is
/// appended with no values); returns each of the rank's fields' index in the merged list.
std::vector<std::size_t> merge_fields(const std::vector<char>& b, std::size_t& off, OutflowRecord& rec) {
  const std::size_t nf = static_cast<std::size_t>(get<std::uint64_t>(b, off));
  std::vector<std::size_t> at(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    common::Field fl;
    fl.name = get_string(b, off);
    fl.unit = get_string(b, off);
    fl.description = get_string(b, off);
    fl.ncomp = static_cast<std::size_t>(get<std::uint64_t>(b, off));
    const double init = get<double>(b, off);
    const auto it = std::find_if(rec.fields.begin(), rec.fields.end(), [&](const common::Field& g) { return g.name == fl.name; });
    at[f] = static_cast<std::size_t>(it - rec.fields.begin());
    if (it == rec.fields.end()) {
      rec.fields.push_back(std::move(fl));
      rec.init.push_back(init);
    }
  }
  return at;
}
/// The totals of the removed particles: the ranks' partials (pack_totals, rank-major) summed in
/// rank order (the same sum on every run).
Diagnostics sum_rank_totals(const std::vector<double>& rank_totals, int ranks) {
  const std::size_t nt = pack_totals(Diagnostics{}).size();
  Diagnostics t;
  for (int k = 0; k < ranks; ++k) {
    const Diagnostics d = unpack_totals(std::vector<double>(rank_totals.begin() + nt * k, rank_totals.begin() + nt * (k + 1)));
    t.mass += d.mass;
    t.momentum += d.momentum;
    t.angular_momentum += d.angular_momentum;
    t.kinetic += d.kinetic;
    t.internal += d.internal;
    t.removed += d.removed;
    t.removed_mass += d.removed_mass;
    t.work_dev += d.work_dev;
    t.heat_shock += d.heat_shock;
    t.heat_transfer += d.heat_transfer;
    t.elastic += d.elastic;
    t.dissipated += d.dissipated;
  }
  return t;
}
}  // namespace

OutflowRecord DomainSolver::local_outflow() {
  SolverResume r = solver_->resume_state();
  std::vector<char> desc;
  put_fields(desc, r);
  std::vector<int> counts;
  const double before = comm_.bytes_sent;
  const std::vector<char> all = comm_.gather(desc, -1, &counts);  // every rank's list, rank order
  OutflowRecord rec;
  std::size_t off = 0;
  std::vector<std::size_t> at;
  for (int k = 0; k < comm_.size; ++k) {
    std::vector<std::size_t> a = merge_fields(all, off, rec);
    if (k == comm_.rank) at = std::move(a);
  }
  const std::size_t n = r.outflow.size();
  for (std::size_t g = 0; g < rec.fields.size(); ++g) rec.fields[g].values.assign(n * rec.fields[g].ncomp, rec.init[g]);
  for (std::size_t f = 0; f < at.size(); ++f) rec.fields[at[f]].values = std::move(r.outflow_fields[f].values);
  rec.ps = std::move(r.outflow);
  rec.time = std::move(r.outflow_time);
  rec.rank_totals = comm_.gather(pack_totals(r.outflow_totals));
  stats_.migrate_bytes += comm_.bytes_sent - before;
  rec.totals = sum_rank_totals(rec.rank_totals, comm_.size);
  return rec;
}

OutflowRecord DomainSolver::gather_outflow(int root) {
  const SolverResume r = solver_->resume_state();
  const ParticleSet& o = r.outflow;
  std::vector<char> buf;
  put(buf, static_cast<std::uint64_t>(o.size()));
  put_fields(buf, r);
  for (std::size_t p = 0; p < o.size(); ++p) {
    ParticleSet::for_each_array([&](const auto& a) {
      const auto& v = o.*a.member;
      if (v.empty()) return;
      const std::size_t w = static_cast<std::size_t>(a.info.width), at = buf.size();
      using T = typename std::decay_t<decltype(v)>::value_type;
      buf.resize(at + w * sizeof(T));
      std::memcpy(buf.data() + at, v.data() + w * p, w * sizeof(T));
    });
    put(buf, r.outflow_time[p]);
    for (const common::Field& fl : r.outflow_fields)
      for (std::size_t c = 0; c < fl.ncomp; ++c) put(buf, fl.values[fl.ncomp * p + c]);
  }
  const double before = comm_.bytes_sent;
  const std::vector<std::vector<char>> all = comm_.gather_per_rank(buf, root);
  OutflowRecord rec;
  rec.rank_totals = comm_.gather(pack_totals(r.outflow_totals), root);
  stats_.migrate_bytes += comm_.bytes_sent - before;
  if (comm_.rank != root) return rec;
  rec.totals = sum_rank_totals(rec.rank_totals, comm_.size);
  // unpack every rank's record in rank order, fields merged by name
  ParticleSet ps;
  std::vector<double> time;
  std::vector<std::vector<double>> values;  // per merged field: rows in arrival order
  const bool with_q = solver_->config().artificial_viscosity;
  for (const std::vector<char>& b : all) {
    std::size_t off = 0;
    const std::size_t n = static_cast<std::size_t>(get<std::uint64_t>(b, off));
    const std::size_t had = rec.fields.size();
    const std::vector<std::size_t> at = merge_fields(b, off, rec);
    const std::size_t nf = at.size();
    for (std::size_t g = had; g < rec.fields.size(); ++g)  // new: earlier particles get its initial value
      values.emplace_back(time.size() * rec.fields[g].ncomp, rec.init[g]);
    for (std::size_t p = 0; p < n; ++p) {
      ParticleSet::for_each_array([&](const auto& a) {
        if (a.info.optional && !with_q) return;
        auto& v = ps.*a.member;
        using T = typename std::decay_t<decltype(v)>::value_type;
        for (int c = 0; c < a.info.width; ++c) v.push_back(get<T>(b, off));
      });
      time.push_back(get<double>(b, off));
      for (std::size_t g = 0; g < rec.fields.size(); ++g)  // fields this rank lacks: initial value
        values[g].resize(time.size() * rec.fields[g].ncomp, rec.init[g]);
      for (std::size_t f = 0; f < nf; ++f) {
        const std::size_t g = at[f], nc = rec.fields[g].ncomp;
        for (std::size_t c = 0; c < nc; ++c) values[g][nc * (time.size() - 1) + c] = get<double>(b, off);
      }
    }
  }
  // sorted by (removal time, id)
  std::vector<std::size_t> order(time.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return time[a] != time[b] ? time[a] < time[b] : ps.id[a] < ps.id[b];
  });
  rec.ps.resize(order.size(), with_q);
  ParticleSet::for_each_array([&](const auto& a) {
    const auto& src = ps.*a.member;
    auto& dst = rec.ps.*a.member;
    if (src.empty()) return;
    const std::size_t w = static_cast<std::size_t>(a.info.width);
    for (std::size_t i = 0; i < order.size(); ++i) std::copy_n(src.begin() + w * order[i], w, dst.begin() + w * i);
  });
  rec.time.resize(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) rec.time[i] = time[order[i]];
  for (std::size_t g = 0; g < rec.fields.size(); ++g) {
    const std::size_t nc = rec.fields[g].ncomp;
    rec.fields[g].values.resize(order.size() * nc);
    for (std::size_t i = 0; i < order.size(); ++i)
      std::copy_n(values[g].begin() + nc * order[i], nc, rec.fields[g].values.begin() + nc * i);
  }
  return rec;
}

}  // namespace mpmfrag::mpi
