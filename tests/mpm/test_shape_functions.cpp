/// @file test_shape_functions.cpp
/// Unit tests of the uGIMP / linear shape functions (mpm/include/mpm/shape_functions.hpp).
#include <gtest/gtest.h>

#include <random>

#include "mpm/shape_functions.hpp"

using namespace mpmfrag;

namespace {
common::GridInfo test_grid() {
  common::GridInfo g;
  g.origin = Eigen::Vector3d(-1.3, 0.7, 2.05);  // shifted origin (cb-geo/MPM-Geomechanics bug class)
  g.cell_size = Eigen::Vector3d(0.1, 0.25, 0.05);
  g.shape = Eigen::Vector3i(30, 20, 40);
  return g;
}
}  // namespace

TEST(ShapeFunctions, UgimpMatchesFormulaAtPoints) {
  const double h = 2.0, lp = 0.5;
  // a < lp: 1 - (d^2 + lp^2)/(2 h lp) = 1 - (0.09+0.25)/2 = 0.83
  EXPECT_NEAR(ugimp_weight_1d(0.3, h, lp), 0.83, 1e-15);
  EXPECT_NEAR(ugimp_gradient_1d(0.3, h, lp), -0.3, 1e-15);
  // lp <= a <= h - lp: 1 - a/h
  EXPECT_NEAR(ugimp_weight_1d(-1.2, h, lp), 0.4, 1e-15);
  EXPECT_NEAR(ugimp_gradient_1d(-1.2, h, lp), 0.5, 1e-15);
  // h - lp < a < h + lp: (h + lp - a)^2/(4 h lp) = (0.5)^2/4 = 0.0625
  EXPECT_NEAR(ugimp_weight_1d(2.0, h, lp), 0.0625, 1e-15);
  EXPECT_NEAR(ugimp_gradient_1d(2.0, h, lp), -0.25, 1e-15);
  EXPECT_NEAR(ugimp_gradient_1d(-2.0, h, lp), 0.25, 1e-15);
  EXPECT_EQ(ugimp_weight_1d(2.5, h, lp), 0.0);
  EXPECT_EQ(ugimp_weight_1d(-3.0, h, lp), 0.0);
  EXPECT_EQ(ugimp_gradient_1d(2.6, h, lp), 0.0);
  // linear
  EXPECT_NEAR(linear_weight_1d(0.5, h), 0.75, 1e-15);
  EXPECT_NEAR(linear_gradient_1d(0.5, h), -0.5, 1e-15);
  EXPECT_NEAR(linear_gradient_1d(-0.5, h), 0.5, 1e-15);
}

TEST(ShapeFunctions, UgimpContinuousAcrossBranches) {
  const double h = 1.0;
  for (double lp : {0.5, 0.25, 1.0 / 6.0}) {
    for (double b : {lp, h - lp, h + lp}) {
      for (double sgn : {-1.0, 1.0}) {
        const double x = sgn * b, e = 1e-10;
        EXPECT_NEAR(ugimp_weight_1d(x - e, h, lp), ugimp_weight_1d(x + e, h, lp), 1e-9);
        EXPECT_NEAR(ugimp_gradient_1d(x - e, h, lp), ugimp_gradient_1d(x + e, h, lp), 1e-8);
      }
    }
  }
}

TEST(ShapeFunctions, GradientIsDerivativeOfWeight) {
  const double h = 0.3;
  for (double lp : {0.15, 0.075}) {
    for (double d = -0.49; d < 0.49; d += 0.0137) {
      const double e = 1e-7;
      const double fd = (ugimp_weight_1d(d + e, h, lp) - ugimp_weight_1d(d - e, h, lp)) / (2 * e);
      EXPECT_NEAR(ugimp_gradient_1d(d, h, lp), fd, 1e-6) << "d=" << d << " lp=" << lp;
    }
  }
}

TEST(ShapeFunctions, PartitionOfUnityCompletenessGradientSum3D) {
  const common::GridInfo g = test_grid();
  std::mt19937_64 rng(42);
  for (ShapeKind kind : {ShapeKind::ugimp, ShapeKind::linear}) {
    for (int ppc : {1, 2, 3}) {
      const Eigen::Vector3d lp = default_half_width(g, ppc);
      for (int t = 0; t < 500; ++t) {
        Eigen::Vector3d x;
        for (int d = 0; d < 3; ++d) {
          std::uniform_real_distribution<double> U(g.origin[d] + 2 * g.cell_size[d],
                                                   g.origin[d] + (g.shape[d] - 3) * g.cell_size[d]);
          x[d] = U(rng);
        }
        const ParticleStencil st = compute_stencil(kind, g, x, lp);
        ASSERT_TRUE(stencil_inside(g, st));
        EXPECT_EQ(st.size(), kind == ShapeKind::ugimp ? 27 : 8);
        double sw = 0;
        Eigen::Vector3d sx = Eigen::Vector3d::Zero(), sg = Eigen::Vector3d::Zero();
        Eigen::Matrix3d sxg = Eigen::Matrix3d::Zero();
        for_each_node(st, [&](int i, int j, int k, double w, const Eigen::Vector3d& gr) {
          const Eigen::Vector3d xi = node_position(g, i, j, k);
          sw += w;
          sx += w * xi;
          sg += gr;
          sxg += xi * gr.transpose();
        });
        EXPECT_NEAR(sw, 1.0, 1e-13);
        EXPECT_NEAR((sx - x).norm(), 0.0, 1e-12);
        EXPECT_NEAR(sg.norm(), 0.0, 1e-10);
        // Gradient completeness: sum_i x_i (x) grad S_i = I (a rigid linear field is reproduced).
        EXPECT_NEAR((sxg - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-10);
      }
    }
  }
}

TEST(ShapeFunctions, TensorProductAndNodeSelection) {
  common::GridInfo g;
  g.origin = Eigen::Vector3d(0, 0, 0);
  g.cell_size = Eigen::Vector3d(1, 1, 1);
  g.shape = Eigen::Vector3i(10, 10, 10);
  const Eigen::Vector3d lp(0.25, 0.25, 0.25);
  // x = 4.2 -> f = 0.2 <= 0.5 -> nodes 3,4,5; x = 4.7 -> nodes 4,5,6.
  const auto st = compute_stencil(ShapeKind::ugimp, g, Eigen::Vector3d(4.2, 4.7, 4.5), lp);
  EXPECT_EQ(st.axis[0].first, 3);
  EXPECT_EQ(st.axis[1].first, 4);
  EXPECT_EQ(st.axis[2].first, 3);
  const auto nodes = stencil_nodes(ShapeKind::ugimp, g, Eigen::Vector3d(4.2, 4.7, 4.5), lp);
  double sum = 0;
  for (const auto& n : nodes) {
    const Eigen::Vector3d d = Eigen::Vector3d(4.2, 4.7, 4.5) - node_position(g, n.ijk[0], n.ijk[1], n.ijk[2]);
    const double w = ugimp_weight_1d(d[0], 1, 0.25) * ugimp_weight_1d(d[1], 1, 0.25) *
                     ugimp_weight_1d(d[2], 1, 0.25);
    EXPECT_NEAR(n.weight, w, 1e-15);
    EXPECT_NEAR(n.grad[1], ugimp_weight_1d(d[0], 1, 0.25) * ugimp_gradient_1d(d[1], 1, 0.25) *
                               ugimp_weight_1d(d[2], 1, 0.25), 1e-15);
    sum += n.weight;
  }
  EXPECT_NEAR(sum, 1.0, 1e-14);
  EXPECT_EQ(node_index(g, 1, 2, 3), 1u + 10u * (2u + 10u * 3u));
  // A particle whose support reaches node -1 is reported as outside.
  EXPECT_FALSE(stencil_inside(g, compute_stencil(ShapeKind::ugimp, g, Eigen::Vector3d(0.3, 5, 5), lp)));
  EXPECT_EQ(parse_shape_kind("linear"), ShapeKind::linear);
  EXPECT_THROW(parse_shape_kind("bspline"), std::invalid_argument);
}

// The branch-free weights-only evaluator (used by the hand-off) against axis_weights: same node
// choice, same weights to round-off, partition of unity, on random positions and half-widths and on
// the branch boundaries (f = 1/2, particles on nodes, l = 1/2, |d| = l, h - l, h + l).
TEST(ShapeFunctions, WeightsOnlyMatchAxisWeights) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> ux(-3.0, 5.0), ul(0.01, 0.5);
  const double origin = -1.3, h = 0.1;
  std::vector<std::pair<double, double>> cases;  // (x, l = lp/h)
  for (int t = 0; t < 20000; ++t) cases.emplace_back(ux(rng), ul(rng));
  for (double l : {0.5, 0.25, 0.125, 1.0 / 6.0}) {
    for (int node = 10; node < 12; ++node)
      for (double off : {0.0, 0.5, l, 1.0 - l, -l, -(1.0 - l), 0.5 - l, 0.5 + l, 1e-13, -1e-13})
        cases.emplace_back(origin + (node + off) * h, l);
  }
  double worst = 0.0, worst_sum = 0.0;
  for (const auto& [x, l] : cases) {
    const AxisWeights ref = axis_weights(ShapeKind::ugimp, x, origin, h, l * h);
    const AxisWeightsOnly fast = axis_weights_only<ShapeKind::ugimp>(x, origin, 1.0 / h, l);
    // Node choice may differ only where f is within round-off of 1/2 (both choices then carry a
    // zero weight on the extra node); compare node by node.
    double sum = 0.0;
    for (int s = 0; s < 3; ++s) {
      sum += fast.w[s];
      const int node = fast.first + s;
      const int r = node - ref.first;
      const double wr = (r >= 0 && r < 3) ? ref.w[r] : 0.0;
      worst = std::max(worst, std::fabs(fast.w[s] - wr));
      ASSERT_GE(fast.w[s], 0.0) << "x=" << x << " l=" << l;
    }
    worst_sum = std::max(worst_sum, std::fabs(sum - 1.0));
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(worst_sum, 1e-14);
  // Linear.
  for (int t = 0; t < 2000; ++t) {
    const double x = ux(rng);
    const AxisWeights ref = axis_weights(ShapeKind::linear, x, origin, h, 0.0);
    const AxisWeightsOnly fast = axis_weights_only<ShapeKind::linear>(x, origin, 1.0 / h, 0.0);
    ASSERT_EQ(fast.first, ref.first);
    EXPECT_NEAR(fast.w[0], ref.w[0], 1e-12);
    EXPECT_NEAR(fast.w[1], ref.w[1], 1e-12);
    EXPECT_EQ(fast.w[2], 0.0);
  }
}
