/// @file test_style.cpp
/// The "tonge_ramesh" style through its MaterialBatch interface against the point update it
/// wraps (point_update.hpp): one basalt particle (1 mm^3, El Mir et al. 2019 Table 1 flaws) in
/// uniaxial tension at 1e3 1/s until it fails. Each step the style's damage equals
/// update_point's, bit for bit, from the same state, and its cost field damage_substeps
/// (StateField::work: what the MPI cuts weigh) holds the step's damage sub-step count M of
/// StepDiag: 1 while the flaws do not grow, > 1 while they do.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "mpm/tonge_ramesh/point_update.hpp"
#include "style_batch.hpp"

using namespace mpmfrag;
namespace tr = mpmfrag::tonge_ramesh;

TEST(TongeRameshStyle, DamageSubstepsFieldIsThePointUpdatesSubstepCount) {
  const tr::Params p = tr::basalt_el_mir();
  const tr::Derived d(p);
  const int nb = p.total_bins();
  const auto m = make_tonge_ramesh(p);
  Batch b(1, 1e-9);
  m->initialize(b.b);
  const std::vector<StateField> fields = tonge_ramesh_state_fields();
  const std::size_t fSub = fields.size() - 1, fOmega = 6, fSize = 7, fLen = 8;
  ASSERT_EQ(fields[fSub].name, "damage_substeps");
  ASSERT_EQ(fields[fLen].name, "wing_length");
  EXPECT_EQ(b.state[fSub][0], 1.0);  // StateField::initial
  // the point update's copy of the sampled state
  std::vector<double> om(b.state[fOmega].begin(), b.state[fOmega].begin() + nb);
  std::vector<double> sz(b.state[fSize].begin(), b.state[fSize].begin() + nb);
  std::vector<double> ln(b.state[fLen].begin(), b.state[fLen].begin() + nb);
  tr::PointState st;
  st.D = b.state[0][0];
  st.JGP = b.state[1][0];
  st.Iel = b.state[2][0];
  Eigen::Matrix3d sig = Eigen::Matrix3d::Identity() * b.stress[0];
  const double rate = 1e3, dt = 2e-9;
  int growing = 0, first_growth = -1, max_sub = 0;
  for (int i = 0; i < 4000; ++i) {
    b.advance(rate, dt);
    ASSERT_EQ(m->update(b.b).failed, 0u);
    tr::StepInput in;
    in.L = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(b.L.data());
    in.dt = dt;
    in.Jnp1 = det3(b.F.data());
    in.Jn = jacobian_old(in.Jnp1, b.L.data(), dt);
    st.e = 0.0;
    tr::StepDiag diag;
    ASSERT_EQ(tr::update_point(p, d, in, sig, st, nb, om.data(), sz.data(), ln.data(), &diag), tr::UpdateStatus::ok);
    ASSERT_EQ(b.state[0][0], st.D) << "step " << i;  // the same update from the same state
    ASSERT_EQ(b.state[fSub][0], static_cast<double>(diag.substeps)) << "step " << i;
    if (diag.substeps > 1 && first_growth < 0) first_growth = i;
    growing += diag.substeps > 1;
    max_sub = std::max(max_sub, diag.substeps);
  }
  EXPECT_GT(first_growth, 0) << "the first steps are elastic: one sub-step";
  EXPECT_GT(growing, 0);
  EXPECT_GT(max_sub, 2);
  EXPECT_GE(st.D, p.critical_damage);
  std::printf("damage sub-steps: first > 1 at step %d, %d of 4000 steps, largest %d, final D %.3f\n", first_growth,
              growing, max_sub, st.D);
}
