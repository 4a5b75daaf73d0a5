// The moduli read off an elastic tensor (analysis/elastic_tensor.h) against closed forms: an
// isotropic medium (lambda, mu) in 2D and 3D gives B and mu for every average, a cubic crystal
// Hill's Voigt and Reuss shear moduli, an indefinite tensor no Reuss average; and the Voigt
// order and stress conversion.
#include <gtest/gtest.h>

#include <cmath>

#include "granpack/analysis/elastic_tensor.h"

using namespace granpack;

namespace {

/// c of an isotropic medium: lambda + 2 mu on the diagonal block's diagonal, lambda off it,
/// mu on the shear diagonal (engineering shear strains).
template <int dim> VoigtMatrix<dim> isotropic(double lambda, double mu) {
  VoigtMatrix<dim> c = VoigtMatrix<dim>::Zero();
  c.template topLeftCorner<dim, dim>().setConstant(lambda);
  for (int i = 0; i < voigt_size<dim>; ++i)
    c(i, i) = i < dim ? lambda + 2 * mu : mu;
  return c;
}

template <int dim> void check_isotropic() {
  const double lambda = 3e7, mu = 1.1e7;
  const ElasticSummary<dim> s = summarize_elastic_tensor<dim>(isotropic<dim>(lambda, mu));
  const double b = lambda + 2 * mu / dim;
  EXPECT_NEAR(s.bulk_voigt, b, 1e-9 * b);
  EXPECT_NEAR(s.bulk_reuss, b, 1e-9 * b);
  for (double g : {s.shear_voigt, s.shear_reuss, s.shear_diag, s.shear_voigt_diag})
    EXPECT_NEAR(g, mu, 1e-9 * mu);
  EXPECT_TRUE(s.positive_definite);
  EXPECT_EQ(s.symmetry_deviation, 0.0);
  EXPECT_NEAR(s.eigenvalues[0], mu, 1e-9 * mu); // modes 2 mu (diagonal shear), mu (shear)
}

} // namespace

TEST(ElasticTensorSummary, IsotropicMedium3D) {
  check_isotropic<3>();
}
TEST(ElasticTensorSummary, IsotropicMedium2D) {
  check_isotropic<2>();
}

TEST(ElasticTensorSummary, CubicCrystalHillAverages) {
  const double c11 = 5.0, c12 = 2.0, c44 = 1.0;
  VoigtMatrix<3> c = isotropic<3>(c12, 0.5 * (c11 - c12));
  for (int i = 3; i < 6; ++i)
    c(i, i) = c44;
  const ElasticSummary<3> s = summarize_elastic_tensor<3>(c);
  EXPECT_NEAR(s.bulk_voigt, (c11 + 2 * c12) / 3, 1e-12);
  EXPECT_NEAR(s.bulk_reuss, (c11 + 2 * c12) / 3, 1e-12); // cubic: B_R = B_V
  EXPECT_NEAR(s.shear_voigt, (c11 - c12 + 3 * c44) / 5, 1e-12);
  EXPECT_NEAR(s.shear_reuss, 5 * (c11 - c12) * c44 / (4 * c44 + 3 * (c11 - c12)), 1e-12);
  EXPECT_NEAR(s.shear_diag, (c11 - c12) / 2, 1e-12);
  EXPECT_NEAR(s.shear_voigt_diag, c44, 1e-12);
}

TEST(ElasticTensorSummary, AsymmetryAndIndefiniteness) {
  VoigtMatrix<2> c = isotropic<2>(1.0, 1.0);
  c(0, 1) += 0.3; // a pre-stress-like asymmetry: the summary uses the symmetric part
  const ElasticSummary<2> s = summarize_elastic_tensor<2>(c);
  EXPECT_NEAR(s.symmetry_deviation, 0.3 / 3.0, 1e-12);
  EXPECT_NEAR(s.bulk_voigt, (3 + 3 + 1 + 1.3) / 4.0, 1e-12);
  c(2, 2) = -0.1; // a shear mechanism's negative stiffness
  const ElasticSummary<2> bad = summarize_elastic_tensor<2>(c);
  EXPECT_FALSE(bad.positive_definite);
  EXPECT_TRUE(std::isnan(bad.bulk_reuss));
  EXPECT_TRUE(std::isnan(bad.shear_reuss));
}

TEST(ElasticTensorSummary, VoigtOrderAndStress) {
  EXPECT_STREQ(voigt_name<3>(3), "yz");
  EXPECT_STREQ(voigt_name<3>(5), "xy");
  EXPECT_STREQ(voigt_name<2>(2), "xy");
  EXPECT_EQ((voigt_pair<3>(4)), (std::array<int, 2>{0, 2}));
  Tensor<3> sigma;
  sigma << 1, 6, 5, 6, 2, 4, 5, 4, 3;
  const VoigtVec<3> v = stress_to_voigt<3>(sigma);
  EXPECT_EQ(v, (VoigtVec<3>() << 1, 2, 3, 4, 5, 6).finished());
}
