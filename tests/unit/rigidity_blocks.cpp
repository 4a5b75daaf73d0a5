// Per-contact blocks of G and K = K(1) + K(2) (analysis/rigidity_blocks.h): the stiffness
// blocks are the exact derivative of the contact's generalised loads ᵀG f with respect to
// the unknowns, the loads following the dynamics' contact law (Hertz normal force, elastic
// tangential increment, transport of T by the contact's rotation, mid-overlap branch
// vectors). Checked by central differences in 2D and 3D, with and without friction, and in
// 2D with [GRC]'s parts: cohesion (N = N^e - F0 in contact), rolling resistance (the moment
// -K_r δθ) and a distant pair (normal row only, N^a = -F0 (1 - g/D0)); the divalent rolling
// mode is checked to be null.
#include <gtest/gtest.h>

#include "granpack/analysis/rigidity_blocks.h"
#include "granpack/contact/contact_law_params.h"

using namespace granpack;

namespace {

/// Which contact: [GRC]'s parts are 2D (rolling rows) or any dimension (cohesion).
struct Case {
  bool friction = true;
  bool cohesion = false; ///< F0 = 50 N (half the Hertz force here), D0 = 1e-5 m
  bool rolling = false;  ///< K_r = 1e-3 N m, reference moment 2e-6 N m
  bool distant = false;  ///< the pair 0.4 D0 apart instead of overlapping by h
  bool shear = true;     ///< all strain unknowns (the elastic tensor), not only the diagonal
};

template <int dim> struct Fixture {
  ContactLaw<dim> law;
  RigidityLayout<dim> layout;
  RigidityContact<dim> c;
  double r_i = 0.5e-3, r_j = 0.4e-3;
  Vec<dim> r;
  Case kind;

  explicit Fixture(bool friction) : Fixture(Case{friction}) {}
  explicit Fixture(const Case& k) : kind(k) {
    ContactLawParams p;
    p.young_modulus = 70e9;
    p.poisson_ratio = 0.3;
    p.friction = k.friction ? 0.3 : 0.0;
    if (k.cohesion)
      p.cohesion_force = 50.0, p.cohesion_range = 1e-5;
    if (k.rolling)
      p.rolling_stiffness = 1e-3, p.rolling_friction = 1e-5;
    law = make_contact_law<dim>(p);
    layout.rotations = k.friction;
    layout.rolling = k.rolling;
    layout.ell = 0.5e-3;
    layout.shear_strains = k.shear;
    for (int a = 0; a < dim; ++a)
      layout.cell[a] = 0.01 + 0.001 * a;
    Vec<dim> dir;
    if constexpr (dim == 3)
      dir = Vec<3>(0.3, -0.5, 0.8);
    else
      dir = Vec<2>(0.6, -0.35);
    const double h = k.distant ? -0.4e-5 : 2e-5; // h/R ~ 4e-2: K(2) is a few per cent of K(1)
    r = dir.normalized() * (r_i + r_j - h);
    c = at(r, Vec<dim>::Zero(), RotVec<dim>::Zero(), RotVec<dim>::Zero(),
           DynVector::Zero(layout.local_size()));
  }

  /// The contact after the motion x from the reference state (first order in x exact).
  RigidityContact<dim> at(const Vec<dim>& r_new, const Vec<dim>& w, const RotVec<dim>& th_i,
                          const RotVec<dim>& th_j, const DynVector& x) const {
    RigidityContact<dim> out;
    out.geometry = make_pair_geometry<dim>(r_i, r_j, 1.0, 1.0, r_new);
    ContactState<dim> st;
    out.stiffness = law.stiffness(out.geometry, st);
    if (kind.distant) { // N^a only, whatever the friction
      out.distant = true;
      out.normal_force = law.cohesion->force(out.geometry.overlap);
      return out;
    }
    const NormalResponse nr =
        normal_response(law.normal, out.geometry.overlap, out.geometry.effective_radius);
    out.normal_force = nr.force + (law.cohesion ? law.cohesion->force(out.geometry.overlap) : 0.0);
    if (!layout.rotations)
      return out;
    // Rolling: Γ^r on j = Γ0 - K_r (θ_j - θ_i) (eq. 9 with the sign of rolling_resistance.h).
    // In 3D (below) Γ0 is transported and the increment loses its pivoting part.
    if (layout.rolling && dim == 2)
      out.rolling_moment = RotVec<dim>::Constant(2e-6) - law.rolling->k_r * (th_j - th_i);
    if (layout.rolling && dim == 3)
      out.rolling_moment = reference_rolling_moment(out.geometry.normal);
    if (x.isZero(0)) { // the reference tangential force: 0.2 N along a tangent
      Vec<dim> t = Vec<dim>::Zero();
      t[0] = 1.0;
      const Vec<dim>& n = out.geometry.normal;
      t -= t.dot(n) * n;
      out.tangential_force = 0.2 * nr.force * t.normalized();
      return out;
    }
    // Transport of the reference T by the contact's rotation (App. B), then the elastic
    // increment k_t (delta u)_T (eq. 3), as ContactLaw::force does over one step.
    const PairGeometry<dim>& g0 = c.geometry;
    const RotVec<dim> theta = contact_rotation<dim>(g0, w, th_i, th_j, 1.0);
    const Vec<dim>& n1 = out.geometry.normal;
    Vec<dim> t = transport_tangential<dim>(c.tangential_force, theta, n1);
    const Vec<dim> du = relative_displacement_map(c, layout) * x;
    t += c.stiffness.k_t * (du - du.dot(n1) * n1);
    out.tangential_force = t;
    // 3D rolling, as ContactLaw::force (step 8): the stored δθ = -Γ0 / K_r turns with the
    // contact like T, then gains (θ_j - θ_i) without its pivoting part about the new n.
    if constexpr (dim == 3) {
      if (layout.rolling) {
        const RotVec<3> d_theta = (th_j - th_i) - n1.dot(th_j - th_i) * n1;
        out.rolling_moment =
            transport_tangential<3>(c.rolling_moment, theta, n1) - law.rolling->k_r * d_theta;
      }
    }
    return out;
  }

  /// Γ0 (3D): 2e-4 N m along a tangent other than T's, below μ_r N^e = 1e-3 N m. Large
  /// enough that its turning (K(2): ~Γ0 / (r ell) ~ 400 N/m) is far above the tolerance
  /// 1e-6 k_n ~ 5 N/m: a wrong 3D rolling term in K(2) fails.
  static RotVec<dim> reference_rolling_moment(const Vec<dim>& n) {
    RotVec<dim> t = RotVec<dim>::Zero();
    if constexpr (dim == 3) {
      t = Vec<3>(0.0, 1.0, 0.0);
      t -= t.dot(n) * n;
      t = 2e-4 * t.normalized();
    }
    return t;
  }

  /// Generalised loads ᵀG f of the contact after the motion x.
  DynVector loads(const DynVector& x) const {
    const int g = layout.grain_dofs();
    Vec<dim> u_i = x.template segment<dim>(0), u_j = x.template segment<dim>(g);
    RotVec<dim> th_i = RotVec<dim>::Zero(), th_j = RotVec<dim>::Zero();
    if (layout.rotations) {
      th_i = x.template segment<rot_dim<dim>>(dim) / layout.ell;
      th_j = x.template segment<rot_dim<dim>>(g + dim) / layout.ell;
    }
    const Vec<dim> w = u_j - u_i - strain(x.tail(layout.strains())) * r;
    return contact_loads(at(r + w, w, th_i, th_j, x), layout);
  }

  /// The symmetric strain tensor of the scaled unknowns, written out here rather than taken
  /// from the kernels: diagonal e_a / L_a, shear gamma = e / sqrt(L_a L_b), eps_ab = gamma / 2.
  Tensor<dim> strain(const DynVector& e) const {
    Tensor<dim> eps = Tensor<dim>::Zero();
    for (int a = 0; a < dim; ++a)
      eps(a, a) = e[a] / layout.cell[a];
    if (layout.shear_strains) {
      int k = dim;
      for (const auto& [a, b] : shear_pairs()) {
        eps(a, b) = eps(b, a) = 0.5 * e[k++] / std::sqrt(layout.cell[a] * layout.cell[b]);
      }
    }
    return eps;
  }
  /// Voigt order of the shear strains: yz, xz, xy in 3D, xy in 2D.
  static std::vector<std::pair<int, int>> shear_pairs() {
    if constexpr (dim == 3)
      return {{1, 2}, {0, 2}, {0, 1}};
    else
      return {{0, 1}};
  }
};

template <int dim> void check_derivative(const Case& kind) {
  const bool friction = kind.friction;
  Fixture<dim> f(kind);
  const int m = f.layout.local_size();
  const DynMatrix k1 = constitutive_block(f.c, f.layout);
  const DynMatrix k = k1 + geometric_block(f.c, f.layout);
  DynMatrix fd(m, m);
  const double step = 1e-10;
  for (int col = 0; col < m; ++col) {
    DynVector x = DynVector::Zero(m);
    x[col] = step;
    fd.col(col) = (f.loads(x) - f.loads(-x)) / (2 * step);
  }
  const double scale = k1.cwiseAbs().maxCoeff();
  EXPECT_LT((fd - k).cwiseAbs().maxCoeff(), 1e-6 * scale) << "finite differences\n"
                                                          << fd << "\nK\n"
                                                          << k;
  // The geometric part is resolved: without it the difference is much larger.
  EXPECT_GT((fd - k1).cwiseAbs().maxCoeff(), 1e-3 * scale);
  // The same block by block for the strain rows and columns, whose entries are smaller than
  // the grains' by r / L: each is checked against its own scale, and K(2) must be resolved in
  // each (above 1e-3 of it), so that a wrong or missing K(2) term in a shear row or column
  // fails here.
  const int ns = f.layout.strains(), two_g = m - ns;
  const auto check_block = [&](const char* what, int r0, int nr, int c0, int nc) {
    const DynMatrix b1 = k1.block(r0, c0, nr, nc), bk = k.block(r0, c0, nr, nc),
                    bf = fd.block(r0, c0, nr, nc);
    const double s = std::max(b1.cwiseAbs().maxCoeff(), bk.cwiseAbs().maxCoeff());
    EXPECT_LT((bf - bk).cwiseAbs().maxCoeff(), 1e-6 * s) << what << "\nFD\n" << bf << "\nK\n" << bk;
    EXPECT_GT((bf - b1).cwiseAbs().maxCoeff(), 1e-3 * s) << what << ": K(2) not resolved";
  };
  check_block("strain rows, grain columns", two_g, ns, 0, two_g);
  check_block("grain rows, strain columns", 0, two_g, two_g, ns);
  check_block("strain-strain block", two_g, ns, two_g, ns);
  if (kind.shear) { // the shear rows and columns alone
    check_block("shear rows", two_g + dim, ns - dim, 0, m);
    check_block("shear columns", 0, m, two_g + dim, ns - dim);
  }
  EXPECT_LT((k1 - k1.transpose()).cwiseAbs().maxCoeff(), 1e-12 * scale);
  if (!friction) {
    // Central forces: the grain block of K(2) is symmetric (-N/r (1 - n nᵀ) couplings). The
    // strain rows are not: Omega Sigma is a load, not the derivative of a potential in e.
    const DynMatrix k2 = (k - k1).topLeftCorner(two_g, two_g);
    EXPECT_LT((k2 - k2.transpose()).cwiseAbs().maxCoeff(), 1e-9 * scale);
  }
}

} // namespace

TEST(RigidityBlocks, Derivative3DFriction) {
  check_derivative<3>(Case{true});
}
TEST(RigidityBlocks, Derivative3DFrictionless) {
  check_derivative<3>(Case{false});
}
TEST(RigidityBlocks, Derivative2DFriction) {
  check_derivative<2>(Case{true});
}
TEST(RigidityBlocks, Derivative2DFrictionless) {
  check_derivative<2>(Case{false});
}
TEST(RigidityBlocks, Derivative3DFrictionDiagonalStrainsOnly) {
  check_derivative<3>(Case{true, false, false, false, false}); // [AR]'s dim strain unknowns
}
TEST(RigidityBlocks, Derivative2DFrictionlessDiagonalStrainsOnly) {
  check_derivative<2>(Case{false, false, false, false, false});
}
TEST(RigidityBlocks, Derivative2DCohesiveRolling) {
  check_derivative<2>(Case{true, true, true, false});
}
TEST(RigidityBlocks, Derivative2DCohesiveFrictionless) {
  check_derivative<2>(Case{false, true, false, false});
}
TEST(RigidityBlocks, Derivative2DDistantPair) {
  check_derivative<2>(Case{true, true, true, true});
}
TEST(RigidityBlocks, Derivative3DRolling) {
  check_derivative<3>(Case{true, false, true, false});
}
TEST(RigidityBlocks, Derivative3DCohesiveRolling) {
  check_derivative<3>(Case{true, true, true, false});
}
TEST(RigidityBlocks, Derivative3DCohesiveRollingDiagonalStrainsOnly) {
  check_derivative<3>(Case{true, true, true, false, false});
}
TEST(RigidityBlocks, Derivative3DCohesiveFrictionless) {
  check_derivative<3>(Case{false, true, false, false});
}
TEST(RigidityBlocks, Derivative3DDistantPairRolling) {
  check_derivative<3>(Case{true, true, true, true}); // RR law, but a gap: the normal row only
}
TEST(RigidityBlocks, Derivative3DDistantPair) {
  check_derivative<3>(Case{true, true, false, true});
}

TEST(RigidityBlocks, CohesiveRowsAndForces) {
  // In contact with rolling resistance: 3 rows (δu, then ρ_i - ρ_j), f = (N n + T, Γ / ell)
  // with N = N^e - F0, and the rolling stiffness K_r / ell² on the last row.
  Fixture<2> f(Case{true, true, true, false});
  const DynMatrix rows = rigidity_rows(f.c, f.layout);
  ASSERT_EQ(rows.rows(), 3);
  EXPECT_EQ(rows(2, 2), 1.0);  // ρ_i
  EXPECT_EQ(rows(2, 5), -1.0); // ρ_j
  EXPECT_EQ(rows.row(2).cwiseAbs().sum(), 2.0);
  const NormalResponse nr =
      normal_response(f.law.normal, f.c.geometry.overlap, f.c.geometry.effective_radius);
  EXPECT_NEAR(f.c.normal_force, nr.force - 50.0, 1e-12 * nr.force);
  const DynVector force = contact_force_vector(f.c, f.layout);
  EXPECT_NEAR(force[2], 2e-6 / f.layout.ell, 1e-18);
  EXPECT_NEAR(contact_stiffness(f.c, f.layout)(2, 2), 1e-3 / (f.layout.ell * f.layout.ell), 1e-9);
  // A distant pair: one normal row and the stiffness -F0/D0, whatever the friction.
  Fixture<2> d(Case{true, true, true, true});
  EXPECT_TRUE(d.c.stiffness.distant);
  EXPECT_EQ(rigidity_rows(d.c, d.layout).rows(), 1);
  EXPECT_EQ(d.layout.rows_per_contact(true), 1);
  EXPECT_NEAR(contact_stiffness(d.c, d.layout)(0, 0), -50.0 / 1e-5, 1e-6);
  EXPECT_NEAR(contact_force_vector(d.c, d.layout)[0], -50.0 * (1 - 0.4), 1e-9);
}

TEST(RigidityBlocks, LoadsAreTransposedRigidityTimesForces) {
  Fixture<3> f(true);
  const DynVector loads = contact_loads(f.c, f.layout);
  const Vec<3> force = f.c.normal_force * f.c.geometry.normal + f.c.tangential_force;
  // F on u_i, -F on u_j, b x F / ell on the rotations, F_a r_a / L_a on the strains.
  EXPECT_LT((loads.segment<3>(0) - force).norm(), 1e-12 * force.norm());
  EXPECT_LT((loads.segment<3>(6) + force).norm(), 1e-12 * force.norm());
  EXPECT_LT((loads.segment<3>(3) - f.c.geometry.branch_i().cross(force) / f.layout.ell).norm(),
            1e-12 * force.norm());
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(loads[12 + a], force[a] * f.r[a] / f.layout.cell[a], 1e-12 * force.norm());
  // Shear strains (yz, xz, xy): the symmetrised force moment (F_a r_b + F_b r_a) / 2 over
  // sqrt(L_a L_b), which sums to Omega sigma_ab / sqrt(L_a L_b) over the contacts.
  ASSERT_EQ(loads.size(), 18);
  int k = 15;
  for (const auto& [a, b] : Fixture<3>::shear_pairs()) {
    const double expected = 0.5 * (force[a] * f.r[b] + force[b] * f.r[a]) /
                            std::sqrt(f.layout.cell[a] * f.layout.cell[b]);
    EXPECT_NEAR(loads[k++], expected, 1e-12 * force.norm()) << a << b;
  }
}

TEST(RigidityBlocks, DivalentRollingModeIsNull) {
  // Grain i (first of both contacts) touches j and k; rolling about the line through its two
  // contact points leaves both contacts without relative displacement.
  RigidityLayout<3> l;
  l.ell = 0.5e-3;
  const double radius = 0.5e-3, h = 1e-6;
  RigidityContact<3> a, b;
  a.geometry = make_pair_geometry<3>(radius, radius, 1, 1,
                                     Vec<3>(0.2, 0.9, 0.1).normalized() * (2 * radius - h));
  b.geometry = make_pair_geometry<3>(radius, radius, 1, 1,
                                     Vec<3>(-0.7, 0.2, -0.4).normalized() * (2 * radius - 2 * h));
  const auto v = divalent_rolling_mode(a.geometry.branch_i(), b.geometry.branch_i(), l.ell);
  DynVector x = DynVector::Zero(l.local_size());
  x.head<6>() = v;
  EXPECT_LT((rigidity_rows(a, l) * x).norm(), 1e-15);
  EXPECT_LT((rigidity_rows(b, l) * x).norm(), 1e-15);
  EXPECT_NEAR(v.norm(), 1.0, 1e-14);
  // A plain rotation about the same axis through the centre is not a mechanism.
  DynVector y = DynVector::Zero(l.local_size());
  y.segment<3>(3) = v.tail<3>();
  EXPECT_GT((rigidity_rows(a, l) * y).norm(), 1e-3);
}

TEST(RigidityBlocks, RollingRows3DLeavePivotingFree) {
  // 3 + 2 rows: δu, then the rolling components of ρ_i - ρ_j on an orthonormal tangent basis;
  // a pivoting of either grain about n moves no rolling row, a rolling rotation does.
  Fixture<3> f(Case{true, true, true, false});
  const Vec<3>& n = f.c.geometry.normal;
  const DynMatrix rows = rigidity_rows(f.c, f.layout);
  ASSERT_EQ(rows.rows(), 5);
  ASSERT_EQ(f.layout.rows_per_contact(), 5);
  const auto t = rolling_basis<3>(n);
  EXPECT_NEAR((t.transpose() * t - Eigen::Matrix2d::Identity()).cwiseAbs().maxCoeff(), 0, 1e-15);
  EXPECT_NEAR((t.transpose() * n).cwiseAbs().maxCoeff(), 0, 1e-15);
  for (int grain = 0; grain < 2; ++grain) {
    DynVector x = DynVector::Zero(f.layout.local_size());
    x.segment<3>(3 + 6 * grain) = n;
    EXPECT_NEAR(rows.bottomRows(2).operator*(x).norm(), 0, 1e-15);
    x.segment<3>(3 + 6 * grain) = t.col(0);
    EXPECT_NEAR(rows.bottomRows(2).operator*(x).norm(), 1, 1e-15);
  }
  // f: Γ0's components / ell; 𝒦: K_r / ell² on both rolling rows.
  const DynVector force = contact_force_vector(f.c, f.layout);
  EXPECT_NEAR((t * force.tail(2) * f.layout.ell - f.c.rolling_moment).norm(), 0, 1e-18);
  const DynMatrix k = contact_stiffness(f.c, f.layout);
  EXPECT_NEAR(k(3, 3), 1e-3 / (f.layout.ell * f.layout.ell), 1e-9);
  EXPECT_NEAR(k(4, 4), 1e-3 / (f.layout.ell * f.layout.ell), 1e-9);
  EXPECT_EQ(k(3, 4), 0.0);
}
