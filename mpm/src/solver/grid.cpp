/// @file grid.cpp
/// Grid stage of the explicit MPM step (Uintah explicit step, shared/reference/mpm.md §1.2–1.4):
/// the grid of a domain box, nodal velocities, the explicit update and the face conditions.
///
///   grid:  v_i = (mv)_i / m_i  (0 where m_i = 0)
///          v*_i = v_i + dt f_i / m_i + dt g   where m_i > m_min, else v*_i = v_i
///   BCs:   fixed: v = 0 on the face plane and the ghost layers; symmetry: normal component 0 on
///          the plane, mirror image on the ghost layers (Uintah MPMBoundCond)
#include <algorithm>
#include <cmath>

#include "kernels.hpp"

namespace mpmfrag {

common::GridInfo make_grid(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double h, int ghost) {
  common::GridInfo g;
  g.cell_size = Eigen::Vector3d::Constant(h);
  g.origin = lo - Eigen::Vector3d::Constant(ghost * h);
  for (int d = 0; d < 3; ++d) {
    const int cells = std::max(1, static_cast<int>(std::ceil((hi[d] - lo[d]) / h - 1e-9)));
    g.shape[d] = cells + 1 + 2 * ghost;
  }
  return g;
}

// momentum -> velocity, in place (Node::momentum() becomes Node::velocity()).
void Solver::grid_velocity() {
  const std::size_t nn = nodes_.size();
  Node* nodes = nodes_.data();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < nn; ++i) {
    Node& n = nodes[i];
    double* v = n.momentum();  // in: (m v)_i, out: v_i
    if (n.m > 0.0) {
      const double im = 1.0 / n.m;
      v[0] *= im;
      v[1] *= im;
      v[2] *= im;
    } else {
      v[0] = v[1] = v[2] = 0.0;
    }
  }
}

// force -> updated velocity, in place (Node::force() becomes Node::updated_velocity()).
void Solver::grid_integrate(double dt) {
  const std::size_t nn = nodes_.size();
  Node* nodes = nodes_.data();
  const double mmin = m_min_;
  const Eigen::Vector3d g = cfg_.gravity;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < nn; ++i) {
    Node& n = nodes[i];
    const double* v = n.velocity();
    double* f = n.force();  // in: f_i, out: v*_i
    if (n.m > mmin) {
      const double im = dt / n.m;
      f[0] = v[0] + f[0] * im + g[0] * dt;
      f[1] = v[1] + f[1] * im + g[1] * dt;
      f[2] = v[2] + f[2] * im + g[2] * dt;
    } else {
      f[0] = v[0];
      f[1] = v[1];
      f[2] = v[2];
    }
  }
}

void Solver::apply_bc(GridSlot which) {
  // face planes in global node indices; a subdomain applies the layers inside its box (the
  // mirror source of a symmetry layer must then be inside it too: mpm/mpi/orb.hpp)
  const int S[3] = {grid_.shape[0], grid_.shape[1], grid_.shape[2]};
  const int g = cfg_.ghost_layers;
  const Node::Slot3 slot = Node::slot(which);
  const Eigen::Vector3i lo = sub_.lo, ls = sub_.shape;
  auto inside = [&](int d, int i) { return i >= lo[d] && i < lo[d] + ls[d]; };
  auto at = [&](int i, int j, int k) -> double* {
    return nodes_[static_cast<std::size_t>(i - lo[0]) +
                  static_cast<std::size_t>(ls[0]) * (static_cast<std::size_t>(j - lo[1]) + static_cast<std::size_t>(ls[1]) * (k - lo[2]))].*slot;
  };
  for (int d = 0; d < 3; ++d) {
    const int d1 = (d + 1) % 3, d2 = (d + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      const BoundaryType t = cfg_.boundary[2 * d + side];
      if (t == BoundaryType::free) continue;
      const int plane = side == 0 ? g : S[d] - 1 - g;
      const int dir = side == 0 ? -1 : 1;  // outward
#pragma omp parallel for schedule(static)
      for (int a = lo[d1]; a < lo[d1] + ls[d1]; ++a) {
        for (int b = lo[d2]; b < lo[d2] + ls[d2]; ++b) {
          int idx[3];
          idx[d1] = a;
          idx[d2] = b;
          for (int layer = 0; layer <= g; ++layer) {
            idx[d] = plane + dir * layer;
            if (!inside(d, idx[d])) continue;
            double* vv = at(idx[0], idx[1], idx[2]);
            if (t == BoundaryType::fixed) {
              vv[0] = vv[1] = vv[2] = 0.0;
            } else if (layer == 0) {
              vv[d] = 0.0;
            } else {
              int jdx[3] = {idx[0], idx[1], idx[2]};
              jdx[d] = plane - dir * layer;
              const double* src = at(jdx[0], jdx[1], jdx[2]);
              vv[d] = -src[d];
              vv[d1] = src[d1];
              vv[d2] = src[d2];
            }
          }
        }
      }
    }
  }
}

}  // namespace mpmfrag
