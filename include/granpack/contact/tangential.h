#pragma once
// Tangential elasticity, Coulomb friction and objective transport of the tangential force.
//
// T is the tangential part of the force exerted BY i ON j. With dv_t the tangential velocity
// of j's surface relative to i's at the contact point, the elastic increment is
// dT = -K_T dv_t dt ([AR] eq. 3). Coulomb: |T| <= μ N^e ([GRC] eq. 8), N^e elastic only.
// Walton ([AR] App. A): when N^e decreases, T is first scaled by K_T(N_new)/K_T(N_old).
// Transport ([AR] App. B, eqs. B3-B5): T rotates with the contact region by
// Δθ = n x Δn + ½ n·(Δθ_i + Δθ_j) n, Δn = (1 - n⊗n)(v_j - v_i) dt / |r_ij| (B2, velocity form).
#include <cmath>
#include <limits>

#include "granpack/contact/pair_geometry.h"
#include "granpack/core/vec.h"

namespace granpack {

enum class TangentialStiffnessKind {
  kMindlin,  ///< K_T = (2-2ν)/(2-ν) K_N(h)  ([AR] eq. 3)
  kRatio,    ///< K_T = ratio · K_N(h)
  kConstant, ///< K_T constant (linear law)
};

// The formulas of the tangential sub-models, one inline function each: TangentialElasticity,
// ContactLaw::force and the batched kernel (dynamics/hertz_mindlin_batch) all call them.

/// K_T = ratio · K_N for a K_T that follows K_N (Mindlin, [AR] eq. 3: ratio (2-2ν)/(2-ν));
/// 0 out of contact (K_N = 0).
inline double proportional_tangential_stiffness(double ratio, double k_n) {
  return k_n > 0 ? ratio * k_n : 0.0;
}

/// Coulomb's threshold μ N^e on |T| ([GRC] eq. 8; N^e alone, without N^v or N^a).
inline double coulomb_limit(double mu, double normal_elastic) {
  return mu * normal_elastic;
}
/// T beyond the cone: |T|² = t2 > limit² (false for μ = +inf).
inline bool beyond_coulomb(double t2, double limit) {
  return t2 > limit * limit;
}
/// Factor limit/|T| that brings a T beyond the cone (|T|² = t2 > 0) back onto it, for
/// limit > 0; a zero limit (μ = 0 or N^e = 0) zeroes T instead.
inline double coulomb_scale(double limit, double t2) {
  return limit / std::sqrt(t2);
}

/// Tangential stiffness sub-model.
struct TangentialElasticity {
  TangentialStiffnessKind kind = TangentialStiffnessKind::kMindlin;
  double value = 0;             ///< kMindlin, kRatio: K_T/K_N; kConstant: K_T
  bool walton_rescaling = true; ///< [AR] App. A; switch exists for tests and studies only

  /// (2-2ν)/(2-ν) for Poisson ratio ν.
  static double mindlin_ratio(double nu) { return (2.0 - 2.0 * nu) / (2.0 - nu); }
  static TangentialElasticity mindlin(double nu) {
    return {TangentialStiffnessKind::kMindlin, mindlin_ratio(nu), true};
  }
  static TangentialElasticity ratio(double k_t_over_k_n) {
    return {TangentialStiffnessKind::kRatio, k_t_over_k_n, true};
  }
  static TangentialElasticity constant(double k_t) {
    return {TangentialStiffnessKind::kConstant, k_t, true};
  }

  /// True when K_T follows K_N (then Walton rescaling uses K_N(N_new)/K_N(N_old)).
  bool proportional_to_normal() const { return kind != TangentialStiffnessKind::kConstant; }
  /// K_T given the current K_N(h) (0 out of contact).
  double stiffness(double k_n) const {
    if (!(k_n > 0))
      return 0.0;
    return proportional_to_normal() ? proportional_tangential_stiffness(value, k_n) : value;
  }
};

/// Coulomb friction sub-model; μ may be 0 (T = 0) or +infinity (never slides).
struct CoulombFriction {
  double mu = 0;

  static constexpr double unlimited_mu() { return std::numeric_limits<double>::infinity(); }
  bool unlimited() const { return std::isinf(mu); }
};

// The 3D rotation of a contact over a step and the transport of a vector with it, on plain
// components: ContactLaw<3> (through contact_rotation and transport_tangential below) and the
// batched kernel (dynamics/hertz_mindlin_batch, one contact per SIMD lane) call the same code.
// The order of the operations is the one both paths had before they shared it (issue 30): with
// the default flags (no FMA in the scalar law) neither path's results changed by one bit. The
// batch's vectorised loop is scheduled from it: the same formulas written with dot and cross
// helpers ran 1-3 % slower.

/// A 3D vector as three doubles: what a lane of the batched kernel holds.
struct Xyz {
  double x, y, z;
};
inline Xyz xyz(const Vec<3>& v) {
  return {v[0], v[1], v[2]};
}
inline Vec<3> to_vec(const Xyz& v) {
  return Vec<3>(v.x, v.y, v.z);
}
inline double squared_norm(const Xyz& v) {
  return v.x * v.x + v.y * v.y + v.z * v.z;
}

/// 3D rotation vector of the contact region over one step: rolling n x Δn with
/// Δn = (1 - n⊗n) v dt/|r_ij| (v = v_j - v_i), plus pivoting ½ n·(ω_i + ω_j) dt n. The caller
/// gives dt/|r_ij| (the batch multiplies dt by the 1/|r_ij| it has, the scalar law divides)
/// and ½ dt.
inline Xyz contact_rotation_3d(const Xyz& n, const Xyz& v, const Xyz& w_i, const Xyz& w_j,
                               double dt_over_distance, double half_dt) {
  const double vn = n.x * v.x + n.y * v.y + n.z * v.z;
  const double dnx = (v.x - vn * n.x) * dt_over_distance;
  const double dny = (v.y - vn * n.y) * dt_over_distance;
  const double dnz = (v.z - vn * n.z) * dt_over_distance;
  const double pivot =
      half_dt * (n.x * (w_i.x + w_j.x) + n.y * (w_i.y + w_j.y) + n.z * (w_i.z + w_j.z));
  return {(n.y * dnz - n.z * dny) + pivot * n.x, (n.z * dnx - n.x * dnz) + pivot * n.y,
          (n.x * dny - n.y * dnx) + pivot * n.z};
}

/// 2D: the angle (about z) by which the contact region turns over one step, n x Δn with
/// Δn = (1 - n⊗n) v dt/|r_ij| (v = v_j - v_i; no pivoting in 2D). ContactLaw<2> (through
/// contact_rotation below) and the batched 2D kernel (dynamics/disk_contact_batch) call it.
inline double contact_rotation_2d(double nx, double ny, double vx, double vy,
                                  double dt_over_distance) {
  const double vn = nx * vx + ny * vy;
  const double dnx = (vx - vn * nx) * dt_over_distance;
  const double dny = (vy - vn * ny) * dt_over_distance;
  return nx * dny - ny * dnx;
}

/// Rotation vector of the contact region over one step, [AR] eqs. B2, B4, B5 in velocity form:
/// rolling n x Δn with Δn = (1 - n⊗n)(v_j - v_i) dt/|r_ij| (v including the affine part of
/// the cell deformation), plus in 3D pivoting ½ n·(ω_i + ω_j) dt n (contact_rotation_3d). In 2D
/// pivoting does not exist: the rotation (about z) is the rolling part only.
template <int dim>
inline RotVec<dim> contact_rotation(const PairGeometry<dim>& g, const Vec<dim>& v_ij,
                                    const RotVec<dim>& w_i, const RotVec<dim>& w_j, double dt) {
  const Vec<dim>& n = g.normal;
  if constexpr (dim == 3) {
    return to_vec(
        contact_rotation_3d(xyz(n), xyz(v_ij), xyz(w_i), xyz(w_j), dt / g.distance, 0.5 * dt));
  } else {
    (void)w_i;
    (void)w_j;
    RotVec<2> angle;
    angle[0] = contact_rotation_2d(n[0], n[1], v_ij[0], v_ij[1], dt / g.distance);
    return angle;
  }
}

/// cos x, sin(x)/x and (1 - cos x)/x² from x² by their Taylor series to x⁴: for x² below
/// kSmallAngleSquared = 1e-6 (always, for the angles of one MD step: ~1e-7..1e-4 rad) the
/// truncation is < x⁶/720 < 2e-21, far below rounding, and neither the angle's square root
/// nor sin/cos is needed. Shared by the transport of T, the batched contact kernel and the
/// orientation update.
inline constexpr double kSmallAngleSquared = 1e-6;
struct SmallAngle {
  double cos_x, sin_x_over_x, one_minus_cos_over_x2;
};
inline SmallAngle small_angle_series(double x2) {
  return {1.0 - x2 * (1.0 / 2.0 - x2 * (1.0 / 24.0)), 1.0 - x2 * (1.0 / 6.0 - x2 * (1.0 / 120.0)),
          0.5 - x2 * (1.0 / 24.0 - x2 * (1.0 / 720.0))};
}

/// Rotates t by the 3D rotation vector theta (Rodrigues' formula, given cos x, sin(x)/x and
/// (1 - cos x)/x² of its angle x = |theta|), then removes the component along n. The magnitude
/// of t is not restored here: the scalar law and the batched kernel each do it their way.
inline Xyz rotate_onto_tangent_plane(const Xyz& t, const Xyz& theta, const Xyz& n, double cos_x,
                                     double sin_x_over_x, double one_minus_cos_over_x2) {
  const double theta_t = one_minus_cos_over_x2 * (theta.x * t.x + theta.y * t.y + theta.z * t.z);
  const double rx =
      cos_x * t.x + sin_x_over_x * (theta.y * t.z - theta.z * t.y) + theta_t * theta.x;
  const double ry =
      cos_x * t.y + sin_x_over_x * (theta.z * t.x - theta.x * t.z) + theta_t * theta.y;
  const double rz =
      cos_x * t.z + sin_x_over_x * (theta.x * t.y - theta.y * t.x) + theta_t * theta.z;
  const double rn = n.x * rx + n.y * ry + n.z * rz;
  return {rx - rn * n.x, ry - rn * n.y, rz - rn * n.z};
}

/// A 2D vector as two doubles: what a lane of the batched 2D kernel holds.
struct Xy {
  double x, y;
};

/// 2D: rotates t by the angle whose cosine and sine are c and s, then removes the component
/// along n; as rotate_onto_tangent_plane, the magnitude is restored by the caller.
inline Xy rotate_onto_tangent_line(const Xy& t, double c, double s, const Xy& n) {
  const double rx = c * t.x - s * t.y, ry = s * t.x + c * t.y;
  const double rn = n.x * rx + n.y * ry;
  return {rx - rn * n.x, ry - rn * n.y};
}

/// Rotates t by the rotation vector theta (Rodrigues; in 2D an angle about z), then removes
/// any normal component left with respect to n and restores |t|: T stays exactly tangent and
/// its magnitude is not changed by transport.
template <int dim>
inline Vec<dim> transport_tangential(const Vec<dim>& t, const RotVec<dim>& theta,
                                     const Vec<dim>& n) {
  const double magnitude2 = t.squaredNorm();
  if (magnitude2 == 0)
    return t;
  // Below 1e-3 rad, small_angle_series: with std::sincos this function was ~15 % of a
  // dense-packing step (docs/performance.md).
  Vec<dim> r;
  if constexpr (dim == 3) {
    const double x2 = theta.squaredNorm();
    double c, s_over_x, omc_over_x2; // cos x, sin(x)/x, (1 - cos x)/x²
    if (x2 < kSmallAngleSquared) {
      const SmallAngle a = small_angle_series(x2);
      c = a.cos_x;
      s_over_x = a.sin_x_over_x;
      omc_over_x2 = a.one_minus_cos_over_x2;
    } else {
      const double angle = std::sqrt(x2);
      c = std::cos(angle);
      s_over_x = std::sin(angle) / angle;
      omc_over_x2 = (1.0 - c) / x2;
    }
    r = to_vec(rotate_onto_tangent_plane(xyz(t), xyz(theta), xyz(n), c, s_over_x, omc_over_x2));
  } else {
    const double x = theta[0], x2 = x * x;
    double c, s;
    if (x2 < kSmallAngleSquared) {
      const SmallAngle a = small_angle_series(x2);
      c = a.cos_x;
      s = x * a.sin_x_over_x;
    } else {
      c = std::cos(x);
      s = std::sin(x);
    }
    const Xy rt = rotate_onto_tangent_line({t[0], t[1]}, c, s, {n[0], n[1]});
    r = Vec<2>(rt.x, rt.y);
  }
  const double rn2 = r.squaredNorm();
  return rn2 > 0 ? Vec<dim>(r * std::sqrt(magnitude2 / rn2)) : Vec<dim>::Zero();
}

} // namespace granpack
