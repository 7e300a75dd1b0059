/// @file grid.hpp
/// The uniform background grid of the MPM stage (GridInfo) and its construction from a domain
/// box (make_grid). Shared by the solver, the shape functions and the particle snapshot file
/// (particle_file.hpp stores it as the /grid group), without pulling in the file interface.
#pragma once
#include <Eigen/Core>

namespace common {

/// Uniform background grid: node (i,j,k) sits at origin + (i,j,k) * cell_size,
/// 0 <= i < shape[0] etc.
struct GridInfo {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d cell_size = Eigen::Vector3d::Ones();
  Eigen::Vector3i shape = Eigen::Vector3i::Ones();
};

}  // namespace common
