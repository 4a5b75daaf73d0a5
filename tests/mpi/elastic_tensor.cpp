// The full elastic tensor of `granpack stiffness` (docs/stiffness.md, "The elastic tensor")
// against the closed forms of two crystals under pressure, derived there:
//  - the Hertz-Mindlin FCC crystal (cubic: c11, c12, c44), jobs/decks/ci/fcc_hertz.toml;
//  - a 2D triangular crystal of frictional disks with linear springs (isotropic: c11 = c22,
//    c66 = (c11 - c12) / 2), at a pressure high enough (h/a ~ 1e-2) that every pre-stress
//    term is far above the tolerance.
// Both are centres of inversion: the response is affine, the non-affine part vanishes. The
// tolerance: 1e-6 of the largest modulus for FCC (the existing bulk-modulus test's; measured
// 1e-11), 1e-4 for the triangle (measured 1e-5: see its deck); a wrong pre-stress term (of
// relative size P/c, 3e-5 for FCC, 1e-2 for the triangle) fails either.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "stiffness_runs.h"

using namespace granpack;

namespace {

/// Expected c_IJ (Voigt) of a crystal with cubic (3D) or hexagonal (2D) symmetry: c11 on the
/// diagonal block's diagonal, c12 off it, c44 on the shear diagonal, zero elsewhere.
Eigen::MatrixXd crystal_tensor(int dim, double c11, double c12, double c44) {
  const int nv = dim * (dim + 1) / 2;
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(nv, nv);
  c.topLeftCorner(dim, dim).setConstant(c12);
  for (int i = 0; i < dim; ++i)
    c(i, i) = c11;
  for (int i = dim; i < nv; ++i)
    c(i, i) = c44;
  return c;
}

/// Every entry of `json_c` (rows of c_IJ) within `tol` x max |c| of `expected`.
void expect_tensor(const std::string& what, const nlohmann::json& json_c,
                   const Eigen::MatrixXd& expected, double tol) {
  const double top = expected.cwiseAbs().maxCoeff();
  double worst = 0;
  for (int i = 0; i < expected.rows(); ++i)
    for (int k = 0; k < expected.cols(); ++k) {
      const double got = json_c[i][k].get<double>();
      EXPECT_NEAR(got, expected(i, k), tol * top) << what << " c(" << i << ", " << k << ")";
      worst = std::max(worst, std::abs(got - expected(i, k)) / top);
    }
  if (test::world_rank() == 0)
    std::printf("[ elastic ] %s: largest deviation from the closed form %.3g of max |c|\n",
                what.c_str(), worst);
}

/// The checks every crystal shares, to `tol` of max |c|: closed forms of c (K(1) + K(2)) and
/// of K(1) alone, the affine response, symmetry, positive definiteness; B from the tensor =
/// the bulk modulus exactly.
void expect_crystal(const std::string& what, const nlohmann::json& j, const Eigen::MatrixXd& c,
                    const Eigen::MatrixXd& c_k1, const Eigen::MatrixXd& c_no_prestress,
                    double tol) {
  ASSERT_TRUE(j["moduli_valid"].get<bool>());
  const auto& e = j["elastic_tensor"];
  expect_tensor(what + ", K(1) + K(2)", e["c"], c, tol);
  expect_tensor(what + ", K(1)", j["constitutive"]["elastic_tensor"]["c"], c_k1, tol);
  // The pre-stress terms are resolved: without them the tensor would fail the tolerance.
  const double top = c.cwiseAbs().maxCoeff();
  EXPECT_GT((c - c_no_prestress).cwiseAbs().maxCoeff(), 10 * tol * top) << what;
  // Centrosymmetric: no non-affine relaxation.
  for (const auto& row : e["c_nonaffine"])
    for (const auto& x : row)
      EXPECT_LT(std::abs(x.get<double>()), tol * top) << what;
  EXPECT_LT(e["symmetry_deviation"].get<double>(), tol) << what;
  EXPECT_TRUE(e["positive_definite"].get<bool>()) << what;
  const double b = j["bulk_modulus"].get<double>();
  EXPECT_NEAR(e["bulk_voigt"].get<double>(), b, 1e-12 * b) << what;
  EXPECT_NEAR(e["shear_c11_c12"].get<double>(), j["shear_modulus_diag"].get<double>(), 1e-12 * b);
}

} // namespace

TEST(ElasticTensor, HertzFccCrystalCubicConstants) {
  const auto j = test::run_stiffness(test::run_ci_deck_file("fcc_hertz", "elastic_fcc"));
  // The crystal as in tests/mpi/stiffness.cpp: r from the cell volume (Omega/n = r^3/sqrt 2),
  // Hertz-Mindlin k_n = E~ sqrt(a h / 4), k_t = (2 - 2 nu)/(2 - nu) k_n, N = (2/3) k_n h.
  const double a = 1e-3, nu = 0.3, e_tilde = 70e9 / (1 - nu * nu);
  const double volume_per_grain = std::pow(j["phi"].get<double>(), -1) * M_PI * a * a * a / 6;
  const double r = std::cbrt(std::sqrt(2.0) * volume_per_grain), h = a - r;
  const double kn = e_tilde * std::sqrt(a * h / 4), kt = (2 - 2 * nu) / (2 - nu) * kn;
  const double p = 2 * std::sqrt(2.0) * (2.0 / 3.0 * kn * h) / (r * r);
  EXPECT_NEAR(j["pressure"].get<double>(), p, 1e-6 * p);
  // docs/stiffness.md: the affine response of the 12 contacts plus the pre-stress terms.
  const double s = std::sqrt(2.0) / r;
  const Eigen::MatrixXd k1 = crystal_tensor(3, s * (kn + kt), s * (kn - kt) / 2, s * (kn + kt) / 2);
  const Eigen::MatrixXd c = crystal_tensor(3, s * (kn + kt) - p / 2, s * (kn - kt) / 2 + 1.25 * p,
                                           s * (kn + kt) / 2 - 0.75 * p);
  expect_crystal("FCC", j, c, k1, k1, 1e-6);
  // Cubic: the Voigt and Reuss bulk moduli coincide, the shear ones are Hill's.
  const auto& e = j["elastic_tensor"];
  const double c11 = c(0, 0), c12 = c(0, 1), c44 = c(3, 3), b = (c11 + 2 * c12) / 3;
  EXPECT_NEAR(e["bulk_reuss"].get<double>(), b, 1e-6 * c11);
  EXPECT_NEAR(e["shear_voigt"].get<double>(), (c11 - c12 + 3 * c44) / 5, 1e-6 * c11);
  EXPECT_NEAR(e["shear_reuss"].get<double>(), 5 * (c11 - c12) * c44 / (4 * c44 + 3 * (c11 - c12)),
              1e-6 * c11);
  EXPECT_NEAR(e["shear_c44"].get<double>(), c44, 1e-6 * c11);
  if (test::world_rank() == 0)
    std::printf("[ elastic ] FCC: c11 %.10g (closed form %.10g), c12 %.10g (%.10g), c44 %.10g "
                "(%.10g) Pa; P = %.6g Pa\n",
                e["c"][0][0].get<double>(), c11, e["c"][0][1].get<double>(), c12,
                e["c"][3][3].get<double>(), c44, p);
}

TEST(ElasticTensor, TriangularCrystal2D) {
  // 128 disks, linear springs K_N = 1e5 N/m, K_T = K_N / 2, mu = 1e-3 (the deck says why),
  // on a triangular lattice compressed to P = 2000 N/m: N = P r / sqrt 3 ~ 1.2 N, h/a ~ 1e-2.
  const auto j = test::run_stiffness(test::run_ci_deck_file("triangular_linear", "elastic_hex"));
  EXPECT_EQ(j["backbone_contacts"], 384);
  // r from the area per disk, (sqrt 3 / 2) r^2; N = K_N (a - r), P = sqrt 3 N / r.
  const double a = 1e-3, kn = 1e5, kt = 0.5e5;
  const double area_per_grain = M_PI * a * a / 4 / j["phi"].get<double>();
  const double r = std::sqrt(2 * area_per_grain / std::sqrt(3.0));
  const double p = std::sqrt(3.0) * kn * (a - r) / r;
  EXPECT_NEAR(j["pressure"].get<double>(), p, 1e-4 * p);
  const double s = std::sqrt(3.0) / 4;
  const Eigen::MatrixXd k1 = crystal_tensor(2, s * (3 * kn + kt), s * (kn - kt), s * (kn + kt));
  const Eigen::MatrixXd c = crystal_tensor(2, s * (3 * kn + kt) - p / 4, s * (kn - kt) + 1.25 * p,
                                           s * (kn + kt) - 0.75 * p);
  expect_crystal("triangular", j, c, k1, k1, 1e-4);
  // Isotropic: c66 = (c11 - c12) / 2, and Voigt = Reuss; B = (sqrt 3 / 2) k_n + P / 2, the
  // derivative of the equation of state.
  const auto& e = j["elastic_tensor"];
  const double g = (c(0, 0) - c(0, 1)) / 2;
  EXPECT_NEAR(c(2, 2), g, 1e-12 * kn);
  for (const char* key : {"shear_voigt", "shear_reuss", "shear_c44", "shear_c11_c12"})
    EXPECT_NEAR(e[key].get<double>(), g, 1e-4 * c(0, 0)) << key;
  const double b = std::sqrt(3.0) / 2 * kn + p / 2;
  for (const char* key : {"bulk_voigt", "bulk_reuss"})
    EXPECT_NEAR(e[key].get<double>(), b, 1e-4 * c(0, 0)) << key;
  if (test::world_rank() == 0)
    std::printf("[ elastic ] triangle: c11 %.10g (closed form %.10g), c12 %.10g (%.10g), c66 "
                "%.10g (%.10g) N/m; P = %.6g N/m\n",
                e["c"][0][0].get<double>(), c(0, 0), e["c"][0][1].get<double>(), c(0, 1),
                e["c"][2][2].get<double>(), c(2, 2), p);
}
