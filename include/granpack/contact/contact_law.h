#pragma once
// The contact law: independent sub-models (normal elasticity, normal damping, tangential
// elasticity, Coulomb friction, and optionally [GRC]'s cohesion and rolling resistance)
// composed into one small value type with force() and stiffness(). Header-only: force() is
// the hot loop. Conventions and formulas: docs/contact-law.md.
#include <optional>

#include "granpack/contact/cohesion.h"
#include "granpack/contact/normal_damping.h"
#include "granpack/contact/normal_elasticity.h"
#include "granpack/contact/pair_geometry.h"
#include "granpack/contact/rolling_resistance.h"
#include "granpack/contact/tangential.h"
#include "granpack/core/contact_store.h"
#include "granpack/core/vec.h"

namespace granpack {

/// Velocities of the two grains. v_i, v_j must include the affine part of the cell
/// deformation (the caller adds it); ω about z (1 component) in 2D, 3 components in 3D.
template <int dim> struct ContactKinematics {
  Vec<dim> v_i = Vec<dim>::Zero(), v_j = Vec<dim>::Zero();
  RotVec<dim> w_i = RotVec<dim>::Zero(), w_j = RotVec<dim>::Zero();
};

/// Result of one evaluation.
template <int dim> struct ContactForces {
  bool active = false;                    ///< false: no interaction, state was reset
  Vec<dim> force_on_j = Vec<dim>::Zero(); ///< N n + T, transmitted from i to j; on i: -it
  RotVec<dim> torque_i = RotVec<dim>::Zero();
  RotVec<dim> torque_j = RotVec<dim>::Zero();
  double normal_elastic = 0;              ///< N^e (Coulomb, rattlers)
  double normal_attractive = 0;           ///< N^a <= 0 (cohesion, [GRC] eq. 4-5)
  double normal_total = 0;                ///< N = N^e + N^v + N^a
  Vec<dim> tangential = Vec<dim>::Zero(); ///< T (on j)
};

/// Local constitutive stiffness at the current state (rigidity assembles G^T 𝒦 G).
struct ContactStiffness {
  double k_n = 0;               ///< dN/dh of the static force N^e + N^a (-F0/D0 across a gap)
  double k_t = 0;               ///< dT/du_T (elastic; 0 for a distant interaction)
  double k_r = 0;               ///< rolling stiffness K_r (0 without rolling resistance or contact)
  bool sliding = false;         ///< last update was on the Coulomb cone
  bool rolling_plastic = false; ///< last update was on the rolling threshold
  bool distant = false;         ///< cohesive interaction across a gap: normal force only
};

template <int dim> struct ContactLaw {
  NormalElasticity normal = HertzNormal{};
  NormalDamping damping{};
  TangentialElasticity tangential{};
  CoulombFriction friction{};
  std::optional<Cohesion> cohesion;         ///< [GRC] eq. 4-5
  std::optional<RollingResistance> rolling; ///< [GRC] eq. 9-10

  /// Largest gap (-h) at which a pair interacts: 0 without cohesion, D0 with it.
  double interaction_range() const { return cohesion ? cohesion->d0 : 0.0; }
  /// True when the pair interacts at this geometry.
  bool interacts(const PairGeometry<dim>& g) const {
    return g.overlap > 0 || (cohesion && -g.overlap < cohesion->d0);
  }

  /// Static attractive normal force N^a at overlap h (0 without cohesion).
  double attraction(double h) const { return cohesion ? cohesion->force(h) : 0.0; }

  /// One update of the contact over a time step dt: reads and updates `state`
  /// (normal_force = N^e, tangential_force = T, rolling = δθ, kSliding, kRollingPlastic,
  /// kDistant, age + 1). When the pair does not interact, returns active = false with zero
  /// forces and resets state.
  // Always inlined into the force loop (GCC otherwise keeps it out of line for its size):
  // the geometry, kinematics and result then stay in registers instead of going through
  // memory for every pair (docs/performance.md).
  [[gnu::always_inline]] ContactForces<dim> force(const PairGeometry<dim>& g,
                                                  const ContactKinematics<dim>& kin,
                                                  ContactState<dim>& state, double dt) const {
    ContactForces<dim> out;
    if (!(g.overlap > 0)) {
      if (!(cohesion && -g.overlap < cohesion->d0)) {
        state = ContactState<dim>{};
        return out;
      }
      // Distant interaction ([GRC] eq. 4): attraction along n only; the tangential and
      // rolling histories of a contact that opened are forgotten.
      out.active = true;
      out.normal_attractive = cohesion->force(g.overlap);
      out.normal_total = out.normal_attractive;
      out.force_on_j = out.normal_total * g.normal;
      const std::int64_t age = state.age;
      state = ContactState<dim>{};
      state.flags = kDistant;
      state.age = age + 1;
      return out;
    }
    out.active = true;
    const Vec<dim>& n = g.normal;
    const Vec<dim> b_i = g.branch_i(), b_j = g.branch_j();

    // Relative velocity of j's contact point with respect to i's.
    const Vec<dim> v_ij = kin.v_j - kin.v_i;
    const Vec<dim> dv = v_ij + spin_velocity<dim>(kin.w_j, b_j) - spin_velocity<dim>(kin.w_i, b_i);
    const double dv_n = n.dot(dv);
    const double h_dot = -dv_n;
    const Vec<dim> dv_t = dv - dv_n * n;

    // Normal elasticity and damping.
    const NormalResponse nr = normal_response(normal, g.overlap, g.effective_radius);
    const double n_visc = damping.coefficient(g.effective_mass, nr.stiffness) * h_dot;

    // Tangential: transport (App. B), Walton (App. A), increment (eq. 3), Coulomb.
    Vec<dim> t = transport_tangential<dim>(state.tangential_force,
                                           contact_rotation<dim>(g, v_ij, kin.w_i, kin.w_j, dt), n);
    // (skipped for a zero T, e.g. without friction: the ratio may cost a cube root)
    if (tangential.walton_rescaling && tangential.proportional_to_normal() &&
        nr.force < state.normal_force && state.tangential_force.squaredNorm() > 0)
      t *= normal_stiffness_ratio(normal, nr.force, state.normal_force);
    const double k_t = tangential.stiffness(nr.stiffness);
    t -= (k_t * dt) * dv_t;
    state.flags &= ~static_cast<std::uint32_t>(kSliding | kDistant);
    if (!friction.unlimited()) {
      const double limit = coulomb_limit(friction.mu, nr.force);
      const double t2 = t.squaredNorm();
      if (beyond_coulomb(t2, limit)) {
        t = limit > 0 ? Vec<dim>(t * coulomb_scale(limit, t2)) : Vec<dim>::Zero();
        state.flags |= kSliding;
      }
    }

    out.normal_elastic = nr.force;
    out.normal_attractive = cohesion ? -cohesion->f0 : 0.0;
    out.normal_total =
        applied_elastic_viscous_force(nr.force + n_visc, damping.tension) + out.normal_attractive;
    out.tangential = t;
    out.force_on_j = out.normal_total * n + t;
    out.torque_j = moment<dim>(b_j, out.force_on_j);
    out.torque_i = moment<dim>(b_i, Vec<dim>(-out.force_on_j));

    if (rolling) {
      // Relative rotation of j with respect to i over the step; in 3D its pivoting part
      // (about n) is free, and the stored δθ turns with the contact like T.
      RotVec<dim> d_theta = (kin.w_j - kin.w_i) * dt;
      if constexpr (dim == 3) {
        d_theta -= n.dot(d_theta) * n;
        state.rolling = transport_tangential<dim>(
            state.rolling, contact_rotation<dim>(g, v_ij, kin.w_i, kin.w_j, dt), n);
      }
      state.flags &= ~static_cast<std::uint32_t>(kRollingPlastic);
      if (rolling->update<dim>(state.rolling, d_theta, nr.force))
        state.flags |= kRollingPlastic;
      // Elastic-plastic moment on j, plus the optional viscous part (not in [GRC]).
      RotVec<dim> gamma = -rolling->k_r * state.rolling;
      if (rolling->damping > 0)
        gamma -= rolling->viscosity(g.effective_mass, g.effective_radius) * (d_theta / dt);
      out.torque_j += gamma;
      out.torque_i -= gamma;
    }

    state.normal_force = nr.force;
    state.tangential_force = t;
    ++state.age;
    return out;
  }

  /// Local stiffness at the current geometry and state.
  ContactStiffness stiffness(const PairGeometry<dim>& g, const ContactState<dim>& state) const {
    ContactStiffness k;
    k.sliding = (state.flags & kSliding) != 0;
    k.rolling_plastic = (state.flags & kRollingPlastic) != 0;
    if (!(g.overlap > 0)) {
      k.distant = cohesion && -g.overlap < cohesion->d0;
      k.k_n = cohesion ? cohesion->stiffness(g.overlap) : 0.0;
      return k;
    }
    k.k_n = normal_response(normal, g.overlap, g.effective_radius).stiffness;
    k.k_t = tangential.stiffness(k.k_n);
    k.k_r = rolling ? rolling->k_r : 0.0;
    return k;
  }
};

} // namespace granpack
