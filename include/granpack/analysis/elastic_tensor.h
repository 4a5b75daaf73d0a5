#pragma once
// The strain unknowns of a periodic cell in Voigt notation, and what is read off an elastic
// tensor c_IJ: symmetry, positive definiteness, bulk and shear moduli (the cubic-type ones and
// the isotropic Voigt and Reuss averages). MPI-free; docs/stiffness.md, "The elastic tensor".
//
// Voigt order: 3D xx, yy, zz, yz, xz, xy; 2D xx, yy, xy: the dim diagonal strains first, so
// that the [AR] diagonal-strain quantities are the leading dim x dim block. Shear strains are
// engineering ones, gamma_I = 2 eps_ab, so that Omega sum_I sigma_I gamma_I is the work and
// c_44 is the shear modulus of an isotropic medium.
#include <array>

#include "granpack/core/vec.h"

namespace granpack {

/// Number of independent strain (or stress) components: 6 in 3D, 3 in 2D.
template <int dim> inline constexpr int voigt_size = dim*(dim + 1) / 2;

template <int dim> using VoigtVec = Eigen::Matrix<double, voigt_size<dim>, 1>;
template <int dim> using VoigtMatrix = Eigen::Matrix<double, voigt_size<dim>, voigt_size<dim>>;

/// The tensor indices (a, b), a <= b, of Voigt index I.
template <int dim> constexpr std::array<int, 2> voigt_pair(int i) {
  if (i < dim)
    return {i, i};
  if constexpr (dim == 2)
    return {0, 1};
  else
    return i == 3   ? std::array<int, 2>{1, 2}
           : i == 4 ? std::array<int, 2>{0, 2}
                    : std::array<int, 2>{0, 1};
}

/// Name of Voigt index I ("xx", ..., "xy").
template <int dim> const char* voigt_name(int i);

/// A symmetric tensor's Voigt components (sigma_I = sigma_ab, no factor 2: a stress).
template <int dim> VoigtVec<dim> stress_to_voigt(const Tensor<dim>& sigma);

/// What `granpack stiffness` reports about one tensor.
template <int dim> struct ElasticSummary {
  double symmetry_deviation = 0; ///< max |c_IJ - c_JI| / max |c_IJ|
  VoigtVec<dim> eigenvalues;     ///< of the symmetric part, ascending
  bool positive_definite = false;
  double bulk_voigt = 0, bulk_reuss = 0;   ///< isotropic averages of c and of c^-1
  double shear_voigt = 0, shear_reuss = 0; ///< idem
  double shear_diag = 0;                   ///< (mean c_aa - mean c_{a!=b}) / 2: "(c11 - c12) / 2"
  double shear_voigt_diag = 0;             ///< mean of the shear diagonal: "c44", c66 in 2D
};

/// Reads the summary off c (Pa in 3D, N/m in 2D). The averages use the symmetric part of c
/// (c differs from its transpose by the pre-stress terms only); bulk_voigt is sum_ab c_ab /
/// dim^2 over the diagonal block, the bulk modulus under isotropic compression.
template <int dim> ElasticSummary<dim> summarize_elastic_tensor(const VoigtMatrix<dim>& c);

} // namespace granpack
