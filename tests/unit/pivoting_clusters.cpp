// Parts of a 3D interaction network hanging from one contact (analysis/pivoting_clusters.h):
// found from the bridges of the graph, and their pivoting is an exact null vector of G with
// rolling-resistance rows.
#include <gtest/gtest.h>

#include "granpack/analysis/pivoting_clusters.h"
#include "granpack/analysis/rigidity_blocks.h"

using namespace granpack;

TEST(PivotingClusters, HangingPartsPivotFreely) {
  // A triangle 0-1-2 (no bridge), 3 hanging from 0, 4 from 3, and a distant pair 1-5 holding
  // 5: two parts, {3, 4} from contact 0-3 and {4} from 3-4; the distant pair hinges nothing.
  const double radius = 0.5e-3, d = 0.99e-3;
  std::vector<Vec<3>> x = {{0, 0, 0},
                           {d, 0, 0},
                           {0.5 * d, 0.5 * std::sqrt(3.0) * d, 0},
                           Vec<3>(-0.3, -0.4, 0.866).normalized() * d,
                           Vec<3>::Zero(),
                           Vec<3>::Zero()};
  x[4] = x[3] + Vec<3>(0.2, -0.9, 0.1).normalized() * d;
  x[5] = x[1] + Vec<3>(0.6, 0.0, 0.8) * (1.005e-3);
  const std::vector<std::pair<int, int>> pairs = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {3, 4}, {1, 5}};
  RigidityLayout<3> l;
  l.rolling = true;
  l.ell = radius;
  std::vector<NetworkEdge> edges;
  std::vector<RigidityContact<3>> contacts;
  for (const auto& [i, j] : pairs) {
    RigidityContact<3> c;
    c.geometry = make_pair_geometry<3>(radius, radius, 1.0, 1.0, x[j] - x[i]);
    c.distant = c.geometry.overlap < 0;
    const Vec<3> r = x[j] - x[i], b = c.geometry.branch_i();
    edges.push_back({i, j, {r[0], r[1], r[2]}, {b[0], b[1], b[2]}, c.distant ? 1 : 0});
    contacts.push_back(c);
  }
  ASSERT_TRUE(contacts.back().distant);
  const auto parts = pivoting_clusters(edges, l.ell);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].grain, 3); // sorted by hinge grain
  EXPECT_EQ(parts[0].neighbour, 0);
  EXPECT_EQ(parts[0].mode.size(), 2u);
  EXPECT_EQ(parts[1].grain, 4);
  EXPECT_EQ(parts[1].neighbour, 3);
  EXPECT_EQ(parts[1].mode.size(), 1u);
  // G on the 6 grains (no strain columns needed: the modes have none).
  const int m = l.local_size();
  for (const auto& part : parts) {
    Eigen::VectorXd v = Eigen::VectorXd::Zero(6 * 6);
    for (const auto& [id, dofs] : part.mode)
      v.segment<6>(6 * id) = dofs;
    EXPECT_NEAR(v.norm(), 1.0, 1e-14);
    double worst = 0;
    for (std::size_t c = 0; c < pairs.size(); ++c) {
      Eigen::VectorXd local = Eigen::VectorXd::Zero(m);
      local.head<6>() = v.segment<6>(6 * pairs[c].first);
      local.segment<6>(6) = v.segment<6>(6 * pairs[c].second);
      worst = std::max(worst, (rigidity_rows(contacts[c], l) * local).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(worst, 1e-15) << "part hanging from " << part.grain;
    // Not a trivial motion: the hinge pivots relative to its neighbour.
    EXPECT_GT(v.segment<3>(6 * part.grain + 3).norm(), 0.1);
  }
}
