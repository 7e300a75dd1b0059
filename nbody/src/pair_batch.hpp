/// @file pair_batch.hpp
/// The sphere-sphere pair loop of ContactSystem::compute, kLanes pairs at a time: the pack's
/// inputs are gathered from the sphere arrays and its history from the structure-of-arrays
/// columns (one row per pair), contact_lanes<Lanes> (contact_law.hpp) evaluates them together,
/// and the results and the history of the lanes in contact are scattered back. Only pairs that
/// overlap or were in contact are packed (ContactSystem::compute_impl tests the overlap first:
/// a listed pair whose gap is still open costs two positions and two radii, as in the one-pair
/// kernel's early exit). A short pack repeats its first pair in the unused lanes and stores
/// nothing from them. Each lane computes
/// exactly what the one-pair kernel computes, so the results (and the run) are bit-identical
/// whatever the lane count or the packing (tests/nbody/test_contact_lanes.cpp).
#pragma once
#include <cstdint>
#include <vector>

#include "ssdem/contact_law.hpp"
#include "ssdem/contacts.hpp"

namespace ssdem::pair_batch {

/// What the loop reads and writes.
struct Arrays {
  const Spheres& sp;
  const std::vector<Vec3>& vpred;
  const std::vector<Vec3>& wpred;
  const std::uint32_t* pi;
  const std::uint32_t* pj;
  ContactHistory& hist;
  PairForces* out;     ///< per pair in contact (or released with an edge force)
  double* D;           ///< per pair: energy dissipated over the pair's step (0 without contact)
  std::uint8_t* edge;  ///< per pair: 1 if its record is a released pair's edge force
};

/// Evaluates the pairs rows[0..n) (n <= kLanes) with steps h[0..n) and edge flags whole[0..n) (0: no
/// edge force, ContactSystem::Subset::whole; whole = nullptr: all 1); calls on_contact(p, overlap /
/// smaller radius) for each pair p in contact. Pairs not in contact get a zero result record
/// (released with edges on: their edge force, and edge = 1), D = the energy their history held
/// if they were in contact (plus the edge dashpot's; 0 otherwise), and keep their history row.
template <unsigned PARTS, class OnContact>
inline void eval_pack(const ContactCoeffs& c, const Arrays& a, const std::uint32_t* rows, const double* h,
                      const std::uint8_t* whole, int n, const OnContact& on_contact) {
  constexpr bool HIST = TableInfo::has_history(PARTS);
  const HistCols& cols = a.hist.cols();
  const Spheres& sp = a.sp;
  std::uint32_t prow[kLanes];
  std::size_t I[kLanes], J[kLanes];
  for (int l = 0; l < kLanes; ++l) {
    prow[l] = rows[l < n ? l : 0];
    I[l] = a.pi[prow[l]];
    J[l] = a.pj[prow[l]];
  }
  // every input built lane by lane in registers, then the one-pair caller's expressions lane-wise
  PairIn<Lanes> in;
  in.rho = v3_from([&](int l) -> const Vec3& { return sp.x[J[l]]; }) - v3_from([&](int l) -> const Vec3& { return sp.x[I[l]]; });
  in.sp = lanes_from([&](int l) { return sp.s[I[l]]; });
  in.sn = lanes_from([&](int l) { return sp.s[J[l]]; });
  const Lanes mi = lanes_from([&](int l) { return sp.m[I[l]]; }), mj = lanes_from([&](int l) { return sp.m[J[l]]; });
  in.mu = mi * mj / (mi + mj);
  in.h = lanes_from([&](int l) { return h[l < n ? l : 0]; });
  if (whole) in.edge = lanes_from([&](int l) { return whole[l < n ? l : 0] ? 1.0 : 0.0; });
  in.vp = v3_from([&](int l) -> const Vec3& { return a.vpred[I[l]]; });
  in.vn = v3_from([&](int l) -> const Vec3& { return a.vpred[J[l]]; });
  in.wp = v3_from([&](int l) -> const Vec3& { return a.wpred[I[l]]; });
  in.wn = v3_from([&](int l) -> const Vec3& { return a.wpred[J[l]]; });
  in.vp_half = v3_from([&](int l) -> const Vec3& { return sp.v[I[l]]; });
  in.vn_half = v3_from([&](int l) -> const Vec3& { return sp.v[J[l]]; });
  in.wp_half = v3_from([&](int l) -> const Vec3& { return sp.w[I[l]]; });
  in.wn_half = v3_from([&](int l) -> const Vec3& { return sp.w[J[l]]; });
  const LaneMask act = mask_from([&](int l) { return a.hist.active[prow[l]] != 0; });
  HistOf<Lanes> hl;
  if constexpr (HIST) {
    for (int i = 0; i < kHistVec; ++i)
      if (vec_column_enabled(i, PARTS)) hl.v[i] = v3_from([&](int l) -> const Vec3& { return cols.v[i][prow[l]]; });
    for (int i = 0; i < kHistScal; ++i)
      if (scal_column_enabled(i, PARTS)) hl.q[i] = lanes_from([&](int l) { return cols.q[i][prow[l]]; });
  }
  PairOut<Lanes> o;
  const LaneMask con = contact_lanes<PARTS, false>(c, in, act, hl, o);
  const Lanes frac = o.overlap / lmin(in.sp, in.sn);
  for (int l = 0; l < n; ++l) {
    const std::uint32_t p = prow[l];
    a.hist.active[p] = con[l] ? 1 : 0;
    a.D[p] = o.diss[l];
    const bool edge = !con[l] && act[l] && c.edges && (!whole || whole[l]);
    a.edge[p] = edge ? 1 : 0;
    if (con[l] || edge) {
      PairForces& r = a.out[p];
      r.F = o.F.at(l);
      r.Tp = o.Tp.at(l);
      r.Tn = o.Tn.at(l);
    } else {
      a.out[p] = PairForces{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    }
    if (con[l]) {
      if constexpr (HIST) store_hist<PARTS>(cols, p, hl, l);
      on_contact(p, frac[l]);
    }
  }
}

}  // namespace ssdem::pair_batch
