#pragma once
// Per-contact blocks of the rigidity matrix G ([AR] eq. 10-11) and of the stiffness matrix
// K = K(1) + K(2) ([AR] eq. 18 and App. B), for one contact between grains i (first) and j.
// MPI-free: the PETSc assembler (rigidity/) adds these blocks at global indices, and the
// serial tests check them against closed forms and finite differences. docs/stiffness.md.
//
// Local unknowns of one contact, in this order (m = 2 g + dim entries, g = grain dofs):
//   x = (u_i, rho_i, u_j, rho_j, e)
// u: periodic displacement ũ (m); rho = theta * ell, the rotation times a fixed length ell
// (m), present only with friction (frictionless grains carry no torque: [AR] eq. 20 drops
// rotations); e_alpha = eps_alpha * L_alpha, the diagonal strain ([AR]: eps_alpha = -dL/L,
// positive in compression) times the cell length (m). With `shear_strains` the shear strains
// follow in Voigt order (analysis/elastic_tensor.h): e_I = gamma_I sqrt(L_a L_b), gamma_I =
// 2 eps_ab the engineering shear strain, again positive when it shortens the branch vectors
// (eps.r enters the approach delta_u). Every unknown is a length, so every block is in N/m
// and the conjugate loads are forces: F_u, torque/ell, Omega Sigma_I / s_I (s_I the scale).
//
// Sign conventions ([AR] eq. 10 with the dynamics' branch vectors, docs/contact-law.md):
// delta_u = ũ_i + θ_i x b_i - ũ_j - θ_j x b_j + eps.r_ij is the approach of i's contact point
// to j's; the contact force F = N n + T acts on j (from i); loads F_ext = ᵀG f.
//
// [GRC] App. A adds two kinds of rows. Rolling resistance: dim - 1 rows per contact, the
// rolling part of ρ_i - ρ_j = ell (θ_i - θ_j): the row itself in 2D, its components on a
// tangent basis (t1, t2) of n in 3D, where pivoting (about n) is free as in the contact law
// (docs/contact-law.md step 8). Conjugate to Γ^r / ell (Γ^r the rolling moment on j, eq. 9),
// stiffness K_r / ell². In 3D Γ^r turns with the contact like T, which K(2) carries.
// Distant attractions: the normal row only, whatever the friction, with the negative
// stiffness dN^a/dh = -F0/D0. With cohesion N is the static normal force N^e + N^a
// (N^a = -F0 in contact), the force the geometry turns in K(2).
#include <Eigen/Core>
#include <cmath>

#include "granpack/analysis/elastic_tensor.h"
#include "granpack/contact/contact_law.h"
#include "granpack/core/vec.h"

namespace granpack {

/// Everything the blocks need about one contact.
template <int dim> struct RigidityContact {
  PairGeometry<dim> geometry; ///< from r_ij and the radii (make_pair_geometry)
  double normal_force = 0;    ///< static N = N^e + N^a (> 0: repulsive); N^e without cohesion
  Vec<dim> tangential_force = Vec<dim>::Zero();     ///< T, on j, global frame (0 if frictionless)
  RotVec<dim> rolling_moment = RotVec<dim>::Zero(); ///< Γ^r on j, elastic: -K_r δθ (RR)
  bool distant = false;                             ///< cohesive pair across a gap: one normal row
  ContactStiffness stiffness; ///< from ContactLaw::stiffness(): the dynamics' law
};

/// Unknown layout and scales of one problem.
template <int dim> struct RigidityLayout {
  bool rotations = true;            ///< false: frictionless, translations only
  bool rolling = false;             ///< rolling-resistance rows ([GRC] eq. 21; with rotations)
  double ell = 1;                   ///< rotation length scale (m): rho = theta * ell
  Vec<dim> cell = Vec<dim>::Ones(); ///< L_alpha: e_alpha = eps_alpha L_alpha
  /// Strain unknowns: the dim diagonal ones of [AR] eq. (9) (false), or all voigt_size<dim>
  /// of a periodic cell, diagonal first (true: the elastic tensor).
  bool shear_strains = false;

  int grain_dofs() const { return rotations ? dim + rot_dim<dim> : dim; }
  int strains() const { return shear_strains ? voigt_size<dim> : dim; }
  /// s_I with e_I = gamma_I s_I: L_a on the diagonal, sqrt(L_a L_b) for the shear (a, b).
  double strain_scale(int i) const {
    const auto [a, b] = voigt_pair<dim>(i);
    return a == b ? cell[a] : std::sqrt(cell[a] * cell[b]);
  }
  int local_size() const { return 2 * grain_dofs() + strains(); }
  /// Rolling rows of a contact: the rotations normal to n, 1 in 2D, 2 in 3D (pivoting free).
  static constexpr int rolling_rows = dim - 1;
  /// Rows of G per contact: dim with friction (normal and tangential) plus dim - 1 with
  /// rolling resistance, 1 without friction; a distant pair has its normal row only.
  int rows_per_contact(bool distant = false) const {
    if (!rotations || distant)
      return 1;
    return dim + (rolling ? rolling_rows : 0);
  }
};

using DynMatrix = Eigen::MatrixXd;
using DynVector = Eigen::VectorXd;

/// The dim x m map from the local unknowns x to the relative displacement delta_u (global
/// frame), eq. (10).
template <int dim>
DynMatrix relative_displacement_map(const RigidityContact<dim>& c, const RigidityLayout<dim>& l);

/// G rows of the contact ([AR] eq. 11): delta_u itself with friction (dim rows, global
/// frame), its normal part n . delta_u without or across a gap (1 row); with rolling
/// resistance the rows tᵀ(ρ_i - ρ_j) follow (rolling_basis).
template <int dim>
DynMatrix rigidity_rows(const RigidityContact<dim>& c, const RigidityLayout<dim>& l);

/// The rot_dim x (dim - 1) basis t of the rolling rotations: 1 in 2D (the rotation about z),
/// two unit vectors normal to n and to each other in 3D (chosen from n alone, so that every
/// rank builds the same rows). t tᵀ is the projection that removes pivoting.
template <int dim> Eigen::Matrix<double, rot_dim<dim>, dim - 1> rolling_basis(const Vec<dim>& n);

/// The contact's force in G's row space: F = N n + T with friction (then Γ^r / ell with
/// rolling resistance), N without or across a gap.
template <int dim>
DynVector contact_force_vector(const RigidityContact<dim>& c, const RigidityLayout<dim>& l);

/// The contact's constitutive stiffness in G's row space (eq. 12-13, global frame):
/// k_n n nᵀ + k_t (1 - n nᵀ) with friction (then K_r / ell²), k_n without or across a gap
/// (-F0/D0 < 0 there). Elastic values throughout: [AR] uses the elastic 𝒦 of eq. (13) even on
/// sliding contacts, [GRC] App. A the elastic K_T and K_r.
template <int dim>
DynMatrix contact_stiffness(const RigidityContact<dim>& c, const RigidityLayout<dim>& l);

/// m x m constitutive block ᵀG 𝒦 G, eq. (18). Symmetric positive semi-definite.
template <int dim>
DynMatrix constitutive_block(const RigidityContact<dim>& c, const RigidityLayout<dim>& l);

/// m x m geometric block K(2): the change of the loads ᵀG f at fixed contact-law response
/// when the geometry moves (rotation of n and of T, App. B eq. B1-B5; moving branch vectors
/// and r_ij in the moments and in Omega Sigma). Not symmetric with friction. Derivation in
/// docs/stiffness.md. The 2D rolling moment is a scalar that no geometry change turns: it
/// adds nothing there; in 3D Γ^r turns with the contact like T: ΔΓ^r = -n (Γ^r.Δn) + ½ s n x Γ^r
/// on ρ_i / ell, its opposite on ρ_j (a couple: no force, no stress).
template <int dim>
DynMatrix geometric_block(const RigidityContact<dim>& c, const RigidityLayout<dim>& l);

/// Generalised loads of the contact on the local unknowns, (ᵀG f) restricted to the
/// contact: (F, b_i x F / ell, -F, -b_j x F / ell, F_alpha r_alpha / L_alpha, then with shear
/// strains (F_a r_b + F_b r_a) / (2 s_I)): the strain entries sum to Omega sigma_I / s_I.
template <int dim>
DynVector contact_loads(const RigidityContact<dim>& c, const RigidityLayout<dim>& l);

/// The free rolling of a divalent grain ([AR] fig. 14, App. E): rotation about the line
/// through its two contact points p1, p2 (branch vectors from its centre), the centre moving
/// by theta x (0 - p1). Returns the grain's g = 6 scaled dofs (u, rho), unit norm; both
/// contact points stay still, so with the neighbours at rest the mode is an exact null
/// vector of G. 3D with rotations only.
Eigen::Matrix<double, 6, 1> divalent_rolling_mode(const Vec<3>& p1, const Vec<3>& p2, double ell);

} // namespace granpack
