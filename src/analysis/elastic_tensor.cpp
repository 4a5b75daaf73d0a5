#include "granpack/analysis/elastic_tensor.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>

namespace granpack {

template <int dim> const char* voigt_name(int i) {
  if constexpr (dim == 2) {
    static const char* names[] = {"xx", "yy", "xy"};
    return names[i];
  } else {
    static const char* names[] = {"xx", "yy", "zz", "yz", "xz", "xy"};
    return names[i];
  }
}

template <int dim> VoigtVec<dim> stress_to_voigt(const Tensor<dim>& sigma) {
  VoigtVec<dim> v;
  for (int i = 0; i < voigt_size<dim>; ++i) {
    const auto [a, b] = voigt_pair<dim>(i);
    v[i] = 0.5 * (sigma(a, b) + sigma(b, a));
  }
  return v;
}

namespace {

/// (sum over the diagonal block, its trace, sum of the shear diagonal) of a Voigt matrix:
/// the sums the isotropic averages are made of.
template <int dim> std::array<double, 3> projections(const VoigtMatrix<dim>& m) {
  const Tensor<dim> d = m.template topLeftCorner<dim, dim>();
  return {d.sum(), d.trace(), m.diagonal().template tail<voigt_size<dim> - dim>().sum()};
}

} // namespace

template <int dim> ElasticSummary<dim> summarize_elastic_tensor(const VoigtMatrix<dim>& c) {
  constexpr int nv = voigt_size<dim>, ns = nv - dim;
  ElasticSummary<dim> s;
  const double top = c.cwiseAbs().maxCoeff();
  s.symmetry_deviation = top > 0 ? (c - c.transpose()).cwiseAbs().maxCoeff() / top : 0.0;
  const VoigtMatrix<dim> sym = 0.5 * (c + c.transpose());
  s.eigenvalues = Eigen::SelfAdjointEigenSolver<VoigtMatrix<dim>>(sym).eigenvalues();
  s.positive_definite = s.eigenvalues[0] > 0;

  // Voigt: the isotropic part of c (3D: Hill 1952, G_V = (T - O/2 + 3 S) / 15; 2D: the
  // average of the two deviatoric modes, (T - O)/4 and S) with T the trace of the diagonal
  // block, O the sum of its off-diagonal entries and S the shear diagonal.
  const auto [p, t, sh] = projections<dim>(sym);
  const double off = p - t; // sum of c_ab, a != b
  s.bulk_voigt = p / (dim * dim);
  s.shear_voigt = dim == 3 ? (t - off / 2 + 3 * sh) / 15 : (t - off + 4 * sh) / 8;
  s.shear_diag = 0.5 * (t / dim - off / (dim * (dim - 1)));
  s.shear_voigt_diag = sh / ns;

  // Reuss: the same projections of the compliance c^-1.
  if (s.positive_definite) {
    const VoigtMatrix<dim> comp = sym.inverse();
    const auto [cp, ct, csh] = projections<dim>(comp);
    const double coff = cp - ct;
    s.bulk_reuss = 1.0 / cp;
    s.shear_reuss = dim == 3 ? 15.0 / (4 * ct - 2 * coff + 3 * csh) : 2.0 / (ct - coff + csh);
  } else {
    s.bulk_reuss = s.shear_reuss = std::numeric_limits<double>::quiet_NaN();
  }
  return s;
}

#define GRANPACK_INSTANTIATE(d)                                                                    \
  template const char* voigt_name<d>(int);                                                         \
  template VoigtVec<d> stress_to_voigt<d>(const Tensor<d>&);                                       \
  template ElasticSummary<d> summarize_elastic_tensor<d>(const VoigtMatrix<d>&);
GRANPACK_INSTANTIATE(2)
GRANPACK_INSTANTIATE(3)
#undef GRANPACK_INSTANTIATE

} // namespace granpack
