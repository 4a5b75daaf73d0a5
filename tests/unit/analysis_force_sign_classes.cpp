// [GRC] table VI's classes (include/granpack/analysis/force_sign_classes.h): the sign rule at
// the tolerance, and the means of a small hand-made set.
#include <gtest/gtest.h>

#include <cmath>

#include "granpack/analysis/force_sign_classes.h"

namespace granpack {
namespace {

TEST(ForceSignClasses, ToleranceSeparatesTheClasses) {
  EXPECT_EQ(force_sign(2e-4, 1e-4), ForceSign::repulsive);
  EXPECT_EQ(force_sign(-2e-4, 1e-4), ForceSign::attractive);
  EXPECT_EQ(force_sign(1e-4, 1e-4), ForceSign::vanishing); // |N| <= t is vanishing, as z0
  EXPECT_EQ(force_sign(-1e-4, 1e-4), ForceSign::vanishing);
}

TEST(ForceSignClasses, MeansPerClass) {
  ForceSignSums s;
  s.add(1.0, 0.5, 0.01);
  s.add(3.0, 1.5, 0.01);
  s.add(-2.0, 0.0, 0.01);
  const ForceSignMeans r = force_sign_means(s, ForceSign::repulsive);
  EXPECT_EQ(r.count, 2);
  EXPECT_DOUBLE_EQ(r.mean_normal, 2.0);
  EXPECT_DOUBLE_EQ(r.rms_normal, std::sqrt(5.0));
  EXPECT_DOUBLE_EQ(r.mean_tangential, 1.0);
  EXPECT_DOUBLE_EQ(r.rms_tangential, std::sqrt(1.25));
  const ForceSignMeans a = force_sign_means(s, ForceSign::attractive);
  EXPECT_EQ(a.count, 1);
  EXPECT_DOUBLE_EQ(a.mean_normal, 2.0); // |N|: table VI gives N- as a magnitude
  const ForceSignMeans v = force_sign_means(s, ForceSign::vanishing);
  EXPECT_EQ(v.count, 0);
  EXPECT_TRUE(std::isnan(v.mean_normal));
}

} // namespace
} // namespace granpack
