/// @file mpi_test_helpers.hpp
/// Helpers of the MPI tests of mpm-frag (test_mpm_mpi.cpp): rank queries, stepping a serial or a
/// distributed run to a time, and the largest per-array difference between two particle sets
/// matched by particle id (every ParticleSet array and every style state field).
#pragma once
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "mpm/mpi/domain.hpp"

namespace mpmtest {

using namespace mpmfrag;
using mpmfrag::mpi::DomainSolver;

inline int rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
inline int ranks() {
  int r = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &r);
  return r;
}

inline void run_serial(Solver& s, double t) {
  while (s.time() < t * (1 - 1e-12)) s.step(std::min(s.stable_dt(), t - s.time()));
}
inline void run_domain(DomainSolver& s, double t) {
  while (s.time() < t * (1 - 1e-12)) s.step(std::min(s.stable_dt(), t - s.time()));
}

/// Largest difference of array `name` (per component) between two particle sets matched by id,
/// and of every style state field.
struct Diff {
  std::map<std::string, double> max;
  bool same_ids = true;
};
inline Diff compare(const ParticleSet& a, const std::vector<MaterialSlot>& ma, const ParticleSet& b,
             const std::vector<MaterialSlot>& mb) {
  Diff d;
  std::map<std::uint64_t, std::size_t> ib;
  for (std::size_t p = 0; p < b.size(); ++p) ib[b.id[p]] = p;
  if (a.size() != b.size()) d.same_ids = false;
  for (std::size_t p = 0; p < a.size() && d.same_ids; ++p) {
    const auto it = ib.find(a.id[p]);
    if (it == ib.end() || b.material[it->second] != a.material[p]) {
      d.same_ids = false;
      break;
    }
    const std::size_t q = it->second;
    ParticleSet::for_each_array([&](const auto& arr) {
      const auto& va = a.*arr.member;
      const auto& vb = b.*arr.member;
      if (va.empty() || vb.empty()) return;
      const std::size_t w = static_cast<std::size_t>(arr.info.width);
      double& m = d.max[arr.info.name];
      for (std::size_t c = 0; c < w; ++c)
        m = std::max(m, std::fabs(static_cast<double>(va[w * p + c]) - static_cast<double>(vb[w * q + c])));
    });
    const MaterialSlot& sa = ma[a.material[p]];
    const MaterialSlot& sb = mb[b.material[q]];
    for (std::size_t f = 0; f < sa.state.size(); ++f) {
      const std::size_t nc = static_cast<std::size_t>(sa.style->state_fields[f].ncomp);
      double& m = d.max["state:" + sa.style->state_fields[f].name];
      for (std::size_t c = 0; c < nc; ++c)
        m = std::max(m, std::fabs(sa.state[f][nc * (p - sa.begin) + c] - sb.state[f][nc * (q - sb.begin) + c]));
    }
  }
  return d;
}

}  // namespace mpmtest
