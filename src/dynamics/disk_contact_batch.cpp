#include "granpack/dynamics/disk_contact_batch.h"

#include <algorithm>
#include <cmath>

#include "granpack/core/error.h"
#include "granpack/core/simd_clones.h"

namespace granpack {

std::optional<DiskContactConstants> DiskContactConstants::of(const ContactLaw<2>& law) {
  const auto base = BatchLawConstants::of(law);
  if (!base)
    return std::nullopt;
  DiskContactConstants c{*base};
  if (law.cohesion) {
    c.f0 = law.cohesion->f0;
    c.d0 = law.cohesion->d0;
  }
  if (law.rolling) {
    c.rolling = true;
    c.k_r = law.rolling->k_r;
    c.mu_r = law.rolling->mu_r;
    c.zeta_r = law.rolling->damping;
  }
  return c;
}

namespace {

// The loop body follows ContactLaw<2>::force line by line, calling the same formulas (one
// inline function each in contact/*.h), with fewer divisions; the branches of the scalar law
// become selects (a distant pair computes the contact's formulas too, on a zero overlap, and
// selects the attraction), and the branches the batch does not take (a large angle, a large
// unloading, a pair out of range) set `exact`. Compiled once per instruction set
// (GRANPACK_SIMD_CLONES), as the 3D kernel.

GRANPACK_SIMD_CLONES
void evaluate_lanes(const DiskContactConstants& c, DiskContactBatch& b, std::size_t n,
                    std::size_t n_valid, double dt, DiskContactSums& out) {
  // The law's uniform choices as arithmetic (no control flow in the loop body); without
  // rolling resistance δθ stays 0 (K_r = μ_r = 0 and a zero increment).
  const BatchLawTerms law(c);
  const bool cohesive = c.d0 > 0;
  const double f0 = c.f0, d0 = cohesive ? c.d0 : 1.0; // (1: no 0/0 in the unused select)
  const double n_attractive = cohesive ? -f0 : 0.0;   // N^a in contact
  const double k_r = c.k_r, mu_r = c.mu_r, zeta_r = c.zeta_r;
  const double rolling_dt = c.rolling ? dt : 0.0;
  const double inv_dt = 1.0 / dt;
  const int rolling_mask = c.rolling ? static_cast<int>(kRollingPlastic) : 0;
  // The sums, one variable each so that they vectorise as reductions.
  double v00 = 0, v01 = 0, v10 = 0, v11 = 0, e00 = 0, e01 = 0, e10 = 0, e11 = 0;
  double max_overlap = 0;
  long count = 0;
#pragma omp simd reduction(+ : v00, v01, v10, v11, e00, e01, e10, e11, count)                     \
    reduction(max : max_overlap)
  for (std::size_t l = 0; l < n; ++l) {
    // Geometry (make_pair_geometry).
    const double rx = b.rx[l], ry = b.ry[l];
    const double ri = b.rad_i[l], rj = b.rad_j[l];
    const double d = std::sqrt(rx * rx + ry * ry);
    const double inv_d = 1.0 / d;
    const double nx = rx * inv_d, ny = ry * inv_d;
    const double h = ri + rj - d;
    const double mi = b.mass_i[l], mj = b.mass_j[l];
    const double inv_sums = 1.0 / ((ri + rj) * (mi + mj));
    const double r_eff = ri * rj * (mi + mj) * inv_sums; // R_i R_j / (R_i + R_j)
    const double m_eff = mi * mj * (ri + rj) * inv_sums; // m_i m_j / (m_i + m_j)
    const bool touching = h > 0;
    const double gap = -h;
    const bool distant = !touching & cohesive & (gap < d0); // [GRC] eq. 4 across a gap
    const double hp = touching ? h : 0.0;                   // keeps the other lanes finite

    // Branch vectors to the middle of the overlap: b_i = (R_i - h/2) n, b_j = -(R_j - h/2) n.
    const double ci = contact_arm(ri, h), cj = -contact_arm(rj, h);
    const double bix = ci * nx, biy = ci * ny, bjx = cj * nx, bjy = cj * ny;

    // Relative velocity of j's contact point with respect to i's (ω x b = (-ω b_y, ω b_x)).
    const double vx = b.vx[l], vy = b.vy[l], wi = b.wi[l], wj = b.wj[l];
    const double dvx = (vx + -wj * bjy) - -wi * biy;
    const double dvy = (vy + wj * bjx) - wi * bix;
    const double dv_n = nx * dvx + ny * dvy;
    const double h_dot = -dv_n;
    const double dtx = dvx - dv_n * nx, dty = dvy - dv_n * ny;

    // Normal elasticity and damping.
    const double k_n = hertz_stiffness(law.e_tilde, r_eff, hp) + law.k_lin;
    const double n_el = normal_elastic_force(law.n_factor, k_n, hp);
    const double n_visc = viscous_coefficient(law.two_zeta, m_eff, k_n) * h_dot;

    // Transport of T by the contact's rotation (as transport_tangential, small angles only).
    const double angle = contact_rotation_2d(nx, ny, vx, vy, dt * inv_d);
    const Xy t0{b.tx[l], b.ty[l]};
    const double mag2 = t0.x * t0.x + t0.y * t0.y;
    const double x2 = angle * angle;
    const SmallAngle sa = small_angle_series(x2);
    const Xy r = rotate_onto_tangent_line(t0, sa.cos_x, angle * sa.sin_x_over_x, {nx, ny});
    const double rn2 = r.x * r.x + r.y * r.y;
    // (Divisions outside the selects: a guarded one "could trap" and stops vectorisation.)
    const double restore_any = std::sqrt(mag2 / (rn2 > 0 ? rn2 : 1.0));
    const double restore = rn2 > 0 ? restore_any : 0.0;
    double tx = mag2 == 0 ? t0.x : r.x * restore;
    double ty = mag2 == 0 ? t0.y : r.y * restore;

    // Walton (Hertz only): N^e decreased, T scaled by (N/N_old)^{1/3}.
    const double n_old = b.n_old[l];
    const bool unloading = law.walton & (n_el < n_old);
    const double xw = relative_load_change(n_el, unloading ? n_old : 1.0);
    const double ratio = n_el > 0 ? cbrt_one_plus_series(xw) : 0.0;
    const double scale = unloading ? ratio : 1.0;
    tx *= scale;
    ty *= scale;

    // Elastic increment, then Coulomb on N^e.
    const double kdt = proportional_tangential_stiffness(law.k_t_ratio, k_n) * dt;
    tx -= kdt * dtx;
    ty -= kdt * dty;
    const double limit = coulomb_limit(law.mu, n_el);
    const double t2 = tx * tx + ty * ty;
    const bool slide = beyond_coulomb(t2, limit);
    const double cut_any = coulomb_scale(limit, t2 > 0 ? t2 : 1.0);
    const double cut = limit > 0 ? cut_any : 0.0;
    tx = slide ? tx * cut : tx;
    ty = slide ? ty * cut : ty;

    // Forces and moments of the contact.
    const double n_tot = applied_elastic_viscous_force(n_el + n_visc, law.tension) + n_attractive;
    double fx = n_tot * nx + tx, fy = n_tot * ny + ty;
    double tq_j = bjx * fy - bjy * fx;
    double tq_i = bix * -fy - biy * -fx;

    // Rolling resistance (RollingResistance::update): δθ += (ω_j - ω_i) dt, held on
    // |K_r δθ| <= μ_r N^e; the moment on j is -K_r δθ - η_r (ω_j - ω_i).
    const double d_theta = (wj - wi) * rolling_dt;
    double theta = b.rolling[l] + d_theta;
    const double roll_limit = rolling_limit(mu_r, n_el);
    const double m2 = k_r * k_r * (theta * theta);
    const bool plastic = beyond_rolling_limit(m2, roll_limit);
    const double hold_any = roll_limit / std::sqrt(m2 > 0 ? m2 : 1.0);
    const double hold = roll_limit > 0 ? hold_any : 0.0;
    theta = plastic ? theta * hold : theta;
    const double gamma =
        -k_r * theta - rolling_viscosity(zeta_r, k_r, m_eff, r_eff) * (d_theta * inv_dt);
    tq_j += gamma;
    tq_i -= gamma;

    // Across a gap: the attraction along n only, every history forgotten.
    const double n_gap = attraction_across_gap(f0, d0, gap);
    fx = distant ? n_gap * nx : fx;
    fy = distant ? n_gap * ny : fy;
    tq_i = distant ? 0.0 : tq_i;
    tq_j = distant ? 0.0 : tq_j;
    tx = distant ? 0.0 : tx;
    ty = distant ? 0.0 : ty;
    b.fx[l] = fx;
    b.fy[l] = fy;
    b.ti[l] = tq_i;
    b.tj[l] = tq_j;
    b.tx[l] = tx;
    b.ty[l] = ty;
    b.n_old[l] = distant ? 0.0 : n_el;
    b.rolling[l] = distant ? 0.0 : theta;
    b.flags[l] = distant ? static_cast<int>(kDistant)
                         : (slide ? static_cast<int>(kSliding) : 0) | (plastic ? rolling_mask : 0);
    const bool big_angle = touching & (mag2 != 0) & !(x2 < kSmallAngleSquared);
    const bool big_unload =
        unloading & (mag2 != 0) & (n_el > 0) & !(std::abs(xw) < kSmallLoadChange);
    const bool exact = !(touching | distant) | big_angle | big_unload;
    b.exact[l] = exact ? 1 : 0;

    // This lane's share of the sums: none for padding and flagged lanes.
    const double w = (l < n_valid) & !exact ? 1.0 : 0.0;
    const double wfx = w * fx, wfy = w * fy;
    v00 += wfx * rx;
    v01 += wfx * ry;
    v10 += wfy * rx;
    v11 += wfy * ry;
    const double n_static = distant ? n_gap : n_el + n_attractive; // N^e + N^a
    const double ex = w * (n_static * nx + tx), ey = w * (n_static * ny + ty);
    e00 += ex * rx;
    e01 += ex * ry;
    e10 += ey * rx;
    e11 += ey * ry;
    count += w > 0 ? 1 : 0;
    const double rel = w * hp / (ri < rj ? ri : rj);
    max_overlap = rel > max_overlap ? rel : max_overlap;
  }
  const double v[4] = {v00, v01, v10, v11};
  const double e[4] = {e00, e01, e10, e11};
  for (int k = 0; k < 4; ++k) {
    out.virial[k] = v[k];
    out.virial_elastic[k] = e[k];
  }
  out.max_overlap = max_overlap;
  out.contacts = count;
}

} // namespace

void evaluate(const DiskContactConstants& c, DiskContactBatch& b, std::size_t n, double dt,
              DiskContactSums& sums) {
  evaluate_padded(b, n, sums, [&](std::size_t padded, DiskContactSums& s) {
    evaluate_lanes(c, b, padded, n, dt, s);
  });
}

} // namespace granpack
