#include "granpack/analysis/rigidity_blocks.h"

#include <Eigen/Geometry>

#include "granpack/core/error.h"

namespace granpack {

namespace {

/// Column offsets of the local unknowns x = (u_i, rho_i, u_j, rho_j, e).
template <int dim> struct Offsets {
  int ui, ri, uj, rj, e;
  explicit Offsets(const RigidityLayout<dim>& l) {
    const int g = l.grain_dofs();
    ui = 0, ri = dim, uj = g, rj = g + dim, e = 2 * g;
  }
};

/// The dim x rot_dim matrix X with X theta = theta x b (b fixed).
template <int dim> Eigen::Matrix<double, dim, rot_dim<dim>> spin_matrix(const Vec<dim>& b) {
  Eigen::Matrix<double, dim, rot_dim<dim>> x;
  if constexpr (dim == 3) {
    // theta x b = -b x theta
    x << 0, b[2], -b[1], -b[2], 0, b[0], b[1], -b[0], 0;
  } else {
    x << -b[1], b[0];
  }
  return x;
}

/// The rot_dim x dim matrix Y with Y a = a x t (t fixed): Δn x T as a map of Δn.
template <int dim> Eigen::Matrix<double, rot_dim<dim>, dim> cross_with(const Vec<dim>& t) {
  Eigen::Matrix<double, rot_dim<dim>, dim> y;
  if constexpr (dim == 3) {
    // a x t = -t x a
    y << 0, t[2], -t[1], -t[2], 0, t[0], t[1], -t[0], 0;
  } else {
    y << t[1], -t[0]; // (a x t)_z = a_x t_y - a_y t_x
  }
  return y;
}

/// E: the dim x strains() map from the strain unknowns to eps.r (r = r_ij): eps_aa r_a /
/// L_a for a diagonal strain, (gamma / 2)(r_b e_a + r_a e_b) / s_I for the shear (a, b).
template <int dim> DynMatrix strain_map(const Vec<dim>& r, const RigidityLayout<dim>& l) {
  DynMatrix e = DynMatrix::Zero(dim, l.strains());
  for (int i = 0; i < l.strains(); ++i) {
    const auto [a, b] = voigt_pair<dim>(i);
    const double s = l.strain_scale(i);
    if (a == b) {
      e(a, i) = r[a] / s;
    } else {
      e(a, i) = 0.5 * r[b] / s;
      e(b, i) = 0.5 * r[a] / s;
    }
  }
  return e;
}

/// W: the real relative displacement w = u_j - u_i (= ũ_j - ũ_i - eps r_ij) of the centres.
template <int dim>
DynMatrix centre_motion_map(const RigidityContact<dim>& c, const RigidityLayout<dim>& l) {
  const Offsets<dim> o(l);
  const Vec<dim> r = c.geometry.distance * c.geometry.normal;
  DynMatrix w = DynMatrix::Zero(dim, l.local_size());
  w.block(0, o.ui, dim, dim) = -Tensor<dim>::Identity();
  w.block(0, o.uj, dim, dim) = Tensor<dim>::Identity();
  w.block(0, o.e, dim, l.strains()) = -strain_map<dim>(r, l);
  return w;
}

} // namespace

template <int dim>
DynMatrix relative_displacement_map(const RigidityContact<dim>& c, const RigidityLayout<dim>& l) {
  const Offsets<dim> o(l);
  const auto& g = c.geometry;
  DynMatrix d = DynMatrix::Zero(dim, l.local_size());
  d.block(0, o.ui, dim, dim) = Tensor<dim>::Identity();
  d.block(0, o.uj, dim, dim) = -Tensor<dim>::Identity();
  if (l.rotations) {
    d.block(0, o.ri, dim, rot_dim<dim>) = spin_matrix<dim>(g.branch_i()) / l.ell;
    d.block(0, o.rj, dim, rot_dim<dim>) = -spin_matrix<dim>(g.branch_j()) / l.ell;
  }
  d.block(0, o.e, dim, l.strains()) = strain_map<dim>(g.distance * g.normal, l);
  return d;
}

namespace {
/// Rolling resistance acts between rotations, which frictionless layouts do not carry.
template <int dim> void check_rolling_layout(const RigidityLayout<dim>& l) {
  GRANPACK_CHECK(!l.rolling || l.rotations,
                 "rigidity: rolling-resistance rows need friction (rotation unknowns)");
}
} // namespace

template <int dim> Eigen::Matrix<double, rot_dim<dim>, dim - 1> rolling_basis(const Vec<dim>& n) {
  Eigen::Matrix<double, rot_dim<dim>, dim - 1> t;
  if constexpr (dim == 3) {
    // The axis least aligned with n gives a well-conditioned first tangent.
    int k = 0;
    n.cwiseAbs().minCoeff(&k);
    const Vec<3> t1 = n.cross(Vec<3>::Unit(k)).normalized();
    t.col(0) = t1;
    t.col(1) = n.cross(t1);
  } else {
    (void)n;
    t(0, 0) = 1.0;
  }
  return t;
}

template <int dim>
DynMatrix rigidity_rows(const RigidityContact<dim>& c, const RigidityLayout<dim>& l) {
  check_rolling_layout(l);
  const DynMatrix d = relative_displacement_map(c, l);
  if (!l.rotations || c.distant)
    return c.geometry.normal.transpose() * d;
  if (!l.rolling)
    return d;
  const Offsets<dim> o(l);
  DynMatrix rows = DynMatrix::Zero(l.rows_per_contact(), l.local_size());
  rows.topRows(dim) = d;
  // tᵀ(ρ_i - ρ_j) = ell tᵀ(θ_i - θ_j): the rolling of i relative to j, pivoting left out.
  const auto t = rolling_basis<dim>(c.geometry.normal);
  rows.block(dim, o.ri, l.rolling_rows, rot_dim<dim>) = t.transpose();
  rows.block(dim, o.rj, l.rolling_rows, rot_dim<dim>) = -t.transpose();
  return rows;
}

template <int dim>
DynVector contact_force_vector(const RigidityContact<dim>& c, const RigidityLayout<dim>& l) {
  if (!l.rotations || c.distant)
    return DynVector::Constant(1, c.normal_force);
  DynVector f = DynVector::Zero(l.rows_per_contact());
  f.head(dim) = c.normal_force * c.geometry.normal + c.tangential_force;
  if (l.rolling)
    f.tail(l.rolling_rows) =
        rolling_basis<dim>(c.geometry.normal).transpose() * c.rolling_moment / l.ell;
  return f;
}

template <int dim>
DynMatrix contact_stiffness(const RigidityContact<dim>& c, const RigidityLayout<dim>& l) {
  if (!l.rotations || c.distant)
    return DynMatrix::Constant(1, 1, c.stiffness.k_n);
  const Vec<dim>& n = c.geometry.normal;
  const Tensor<dim> nn = n * n.transpose();
  DynMatrix k = DynMatrix::Zero(l.rows_per_contact(), l.rows_per_contact());
  k.topLeftCorner(dim, dim) =
      c.stiffness.k_n * nn + c.stiffness.k_t * (Tensor<dim>::Identity() - nn);
  // Γ^r = -K_r δθ with δθ = θ_j - θ_i: d(Γ^r/ell)/d(ρ_i - ρ_j) = K_r / ell².
  // In 3D the same on each rolling row (t orthonormal), and pivoting has no spring.
  if (l.rolling)
    k.bottomRightCorner(l.rolling_rows, l.rolling_rows)
        .diagonal()
        .setConstant(c.stiffness.k_r / (l.ell * l.ell));
  return k;
}

template <int dim>
DynMatrix constitutive_block(const RigidityContact<dim>& c, const RigidityLayout<dim>& l) {
  const DynMatrix g = rigidity_rows(c, l);
  return g.transpose() * contact_stiffness(c, l) * g;
}

template <int dim>
DynVector contact_loads(const RigidityContact<dim>& c, const RigidityLayout<dim>& l) {
  return rigidity_rows(c, l).transpose() * contact_force_vector(c, l);
}

template <int dim>
DynMatrix geometric_block(const RigidityContact<dim>& c, const RigidityLayout<dim>& l) {
  const Offsets<dim> o(l);
  const auto& g = c.geometry;
  const int m = l.local_size();
  const Vec<dim>& n = g.normal;
  const double r = g.distance, nf = c.normal_force;
  const Vec<dim> t = l.rotations && !c.distant ? c.tangential_force : Vec<dim>::Zero();
  const Vec<dim> force = nf * n + t;
  const Tensor<dim> proj = Tensor<dim>::Identity() - n * n.transpose();
  const DynMatrix w = centre_motion_map(c, l); // w = u_j - u_i
  const DynMatrix dn = proj * w / r;           // Δn, eq. (B2)

  // Pivoting rate s = n.(θ_i + θ_j) (eq. B5; 3D only: in 2D pivoting does not exist).
  DynMatrix s = DynMatrix::Zero(1, m);
  if constexpr (dim == 3) {
    if (l.rotations) {
      s.block(0, o.ri, 1, 3) = n.transpose() / l.ell;
      s.block(0, o.rj, 1, 3) = n.transpose() / l.ell;
    }
  }
  const RotVec<dim> n_x_t = moment<dim>(n, t);

  // ΔF = N Δn - n (T.Δn) + ½ s (n x T): eqs. (B1), (B3)-(B5) at fixed contact-law response.
  DynMatrix d_force = nf * dn - n * (t.transpose() * dn);
  if constexpr (dim == 3)
    d_force += 0.5 * Vec<3>(n_x_t) * s;

  DynMatrix k = DynMatrix::Zero(m, m);
  k.block(o.ui, 0, dim, m) = d_force;
  k.block(o.uj, 0, dim, m) = -d_force;
  if (l.rotations) {
    // Moments β n x F on both grains (β = R - h/2, the dynamics' branch lengths); their
    // change: Δβ n x T + β Δn x T + β n x ΔF, with Δβ = -Δh/2 = ½ n.w.
    auto moment_change = [&](double beta) {
      DynMatrix dm = 0.5 * n_x_t * (n.transpose() * w) + beta * cross_with<dim>(t) * dn;
      if constexpr (dim == 3)
        dm -= 0.5 * beta * t * s;
      return DynMatrix(dm / l.ell);
    };
    k.block(o.ri, 0, rot_dim<dim>, m) = moment_change(g.branch_i().norm());
    k.block(o.rj, 0, rot_dim<dim>, m) = moment_change(g.branch_j().norm());
    // The 3D rolling moment turns with the contact as T does (the law transports δθ like T,
    // docs/contact-law.md step 8): ΔΓ^r = -n (Γ^r.Δn) + ½ s (n x Γ^r), a couple +Γ^r on ρ_i's
    // load, -Γ^r on ρ_j's. Force-free: no term in the translations or the strains.
    if constexpr (dim == 3) {
      if (l.rolling && !c.distant) {
        const Vec<3> gamma = c.rolling_moment;
        const DynMatrix d_gamma =
            (-n * (gamma.transpose() * dn) + 0.5 * Vec<3>(n.cross(gamma)) * s) / l.ell;
        k.block(o.ri, 0, 3, m) += d_gamma;
        k.block(o.rj, 0, 3, m) -= d_gamma;
      }
    }
  }
  // Omega Sigma_ab = sum (F_a r_b + F_b r_a) / 2 (the loads E(r)ᵀ F, E linear in r): the
  // change ΔF_a r_b + F_a w_b, symmetrised, r moving with the centres (Δr = w).
  const Vec<dim> rv = r * n;
  for (int i = 0; i < l.strains(); ++i) {
    const auto [a, b] = voigt_pair<dim>(i);
    DynMatrix row = rv[b] * d_force.row(a) + force[a] * w.row(b);
    if (a != b)
      row = 0.5 * (row + rv[a] * d_force.row(b) + force[b] * w.row(a));
    k.row(o.e + i) = row / l.strain_scale(i);
  }
  return k;
}

Eigen::Matrix<double, 6, 1> divalent_rolling_mode(const Vec<3>& p1, const Vec<3>& p2, double ell) {
  const Vec<3> axis = (p2 - p1).normalized();
  Eigen::Matrix<double, 6, 1> v;
  v.head<3>() = p1.cross(axis); // θ x (0 - p1) with θ = axis
  v.tail<3>() = ell * axis;
  return v.normalized();
}

#define GRANPACK_INSTANTIATE(d)                                                                    \
  template DynMatrix relative_displacement_map<d>(const RigidityContact<d>&,                       \
                                                  const RigidityLayout<d>&);                       \
  template DynMatrix rigidity_rows<d>(const RigidityContact<d>&, const RigidityLayout<d>&);        \
  template DynVector contact_force_vector<d>(const RigidityContact<d>&, const RigidityLayout<d>&); \
  template DynMatrix contact_stiffness<d>(const RigidityContact<d>&, const RigidityLayout<d>&);    \
  template DynMatrix constitutive_block<d>(const RigidityContact<d>&, const RigidityLayout<d>&);   \
  template DynVector contact_loads<d>(const RigidityContact<d>&, const RigidityLayout<d>&);        \
  template DynMatrix geometric_block<d>(const RigidityContact<d>&, const RigidityLayout<d>&);      \
  template Eigen::Matrix<double, rot_dim<d>, d - 1> rolling_basis<d>(const Vec<d>&);
GRANPACK_INSTANTIATE(2)
GRANPACK_INSTANTIATE(3)
#undef GRANPACK_INSTANTIATE

} // namespace granpack
