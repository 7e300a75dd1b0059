/// @file kernel_loops.hpp
/// The projection's inner loops, written once over a per-particle policy Ops<K> that provides
///   typename Ops<K>::Cache                         per-thread state (cached half-widths),
///   Ops<K>::stencil(x, size, L, cache) -> st      first node and per-axis weights (S(d) of
///                                                  mpmfrag::axis_weights_only),
///   Ops<K>::scatter(st, L, m, v, node)             node (m, p) += S_ip m_p (1, v_p),
///   Ops<K>::gather(st, L, node, vt)                vt = sum_i S_ip v_i.
/// Included, with no include guard and inside an anonymous namespace, by kernels_portable.cpp and
/// kernels_avx2.cpp: the AVX2 file includes it after `#pragma GCC target("avx2")`, so these loops
/// (and the OpenMP regions outlined from them) are compiled for that target there. Every header they
/// need is included by the including file before that pragma.

/// Steps 2 and 3 of project_to_spheres (projection.hpp) for one shape kind.
template <mpmfrag::ShapeKind K, template <mpmfrag::ShapeKind> class Ops>
void run_loops(const handoff::detail::KernelArgs& a) {
  const common::ParticleSnapshot& s = a.s;
  const handoff::detail::Lattice& L = a.L;
  const handoff::detail::CoarseGrid& cg = a.cg;
  const int k = a.k;
  const auto& start = a.start;
  const auto& order = a.order;
  const auto& carry = a.carry;
  const auto& cells = a.cells;
  double* const node = a.node.data();
  handoff::ProjectionResult& r = a.r;
  const std::size_t nn = a.node.size() / 4;
  const std::size_t n = s.count();
  // Software prefetch of the particle data kAhead particles ahead in the sorted order: the cell
  // order reads each particle array as several interleaved streams, too many for the hardware
  // prefetcher once the input is not in the hand-off's order.
  constexpr std::size_t kAhead = 32;
  // 2. P2G, parallel over slabs of sphere-cell z layers, two colours so that no two threads
  //    touch the same node; sums run in sorted order, so results do not depend on threads.
  //    (A uGIMP stencil spans 3 node layers: a slab of ceil(3/k) sphere layers covers them.)
  const int layers_per_slab = (3 + k - 1) / k;
  const std::int64_t layer_cells = std::int64_t(cg.shape[0]) * cg.shape[1];
  const int nslab = (cg.shape[2] + layers_per_slab - 1) / layers_per_slab;
  for (int colour = 0; colour < 2; ++colour) {
#pragma omp parallel for schedule(dynamic, 1)
    for (int sl = colour; sl < nslab; sl += 2) {
      const std::int64_t z0 = std::int64_t(sl) * layers_per_slab;
      const std::int64_t z1 = std::min<std::int64_t>(z0 + layers_per_slab, cg.shape[2]);
      typename Ops<K>::Cache cache(L);
      const std::size_t qe = start[z1 * layer_cells];
      for (std::size_t q = start[z0 * layer_cells]; q < qe; ++q) {
        if (q + kAhead < qe) {
          const std::size_t pa = order[q + kAhead];
          __builtin_prefetch(&s.position[3 * pa]);
          __builtin_prefetch(&s.velocity[3 * pa]);
          __builtin_prefetch(&s.size[L.size_stride * pa]);
          __builtin_prefetch(&s.mass[pa]);
        }
        const std::size_t p = order[q];
        Ops<K>::scatter(Ops<K>::stencil(&s.position[3 * p], &s.size[L.size_stride * p], L, cache), L, s.mass[p],
                        &s.velocity[3 * p], node);
      }
    }
  }
  // Nodal velocities in place.
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(nn); ++i) {
    double* nd = &node[4 * i];
    if (nd[0] > 0.0) {
      const double inv = 1.0 / nd[0];
      nd[1] *= inv;
      nd[2] *= inv;
      nd[3] *= inv;
    }
  }

  // 3. One sphere per occupied cell: G2P at the cell's particles, mass-weighted average.
  common::SphereSet& out = r.spheres;
  const std::size_t ns = cells.size();
  // With k > 1, occupied MPM cells are counted per sphere cell (its k^3 fine cells, marked in a
  // per-thread table that is cleared through the list of marks); with k = 1 they are the spheres.
  std::size_t occupied = 0;
#pragma omp parallel reduction(+ : occupied)
  {
    std::vector<double> fsum(carry.size());
    std::vector<unsigned char> mark(k > 1 ? static_cast<std::size_t>(k) * k * k : 0, 0);
    std::vector<std::size_t> marked;
    typename Ops<K>::Cache cache(L);
#pragma omp for schedule(dynamic, 64)
    for (std::int64_t si = 0; si < static_cast<std::int64_t>(ns); ++si) {
      const std::int64_t c = cells[si];
      const std::int64_t cx = c % cg.shape[0], cy = (c / cg.shape[0]) % cg.shape[1],
                         cz = c / (std::int64_t(cg.shape[0]) * cg.shape[1]);
      const std::int64_t idx[3] = {cx, cy, cz};
      double M = 0.0, P[3] = {0, 0, 0};
      std::fill(fsum.begin(), fsum.end(), 0.0);
      for (std::size_t q = start[c]; q < start[c + 1]; ++q) {
        if (q + kAhead < n) {
          const std::size_t pa = order[q + kAhead];
          __builtin_prefetch(&s.position[3 * pa]);
          __builtin_prefetch(&s.size[L.size_stride * pa]);
          __builtin_prefetch(&s.mass[pa]);
          __builtin_prefetch(&s.id[pa]);
          for (const common::Field* f : carry) __builtin_prefetch(&f->values[pa]);
        }
        const std::size_t p = order[q];
        const double* x = &s.position[3 * p];
        if (k > 1) {
          std::size_t local = 0;
          for (int d = 2; d >= 0; --d) {
            const int fi = std::clamp(common::floor_to_int((x[d] - L.origin[d]) * L.inv_h), 0, s.grid.shape[d] - 2);
            local = local * k + static_cast<std::size_t>(fi - idx[d] * k);
          }
          if (!mark[local]) {
            mark[local] = 1;
            marked.push_back(local);
          }
        }
        double vt[3];
        Ops<K>::gather(Ops<K>::stencil(x, &s.size[L.size_stride * p], L, cache), L, node, vt);
        const double m = s.mass[p];
        M += m;
        for (int d = 0; d < 3; ++d) P[d] += m * vt[d];
        for (std::size_t f = 0; f < carry.size(); ++f) fsum[f] += m * carry[f]->values[p];
        r.map.particle_id[q] = s.id[p];
      }
      occupied += k > 1 ? marked.size() : 1;
      for (std::size_t i : marked) mark[i] = 0;
      marked.clear();
      out.id[si] = static_cast<std::uint64_t>(si);
      out.mass[si] = M;
      for (int d = 0; d < 3; ++d) {
        out.position[3 * si + d] = cg.origin[d] + (idx[d] + 0.5) * cg.edge;
        out.velocity[3 * si + d] = P[d] / M;
      }
      for (std::size_t f = 0; f < carry.size(); ++f) out.fields[f].values[si] = fsum[f] / M;
      r.map.offset[si] = start[c];
    }
  }
  r.occupied_mpm_cells = occupied;
}

/// Both shape kinds.
template <template <mpmfrag::ShapeKind> class Ops>
void run_loops_for(mpmfrag::ShapeKind kind, const handoff::detail::KernelArgs& a) {
  if (kind == mpmfrag::ShapeKind::linear)
    run_loops<mpmfrag::ShapeKind::linear, Ops>(a);
  else
    run_loops<mpmfrag::ShapeKind::ugimp, Ops>(a);
}
