#include "granpack/dynamics/hertz_mindlin_batch.h"

#include <algorithm>
#include <cmath>

#include "granpack/core/error.h"
#include "granpack/core/simd_clones.h"

namespace granpack {

std::optional<HertzMindlinConstants> HertzMindlinConstants::of(const ContactLaw<3>& law) {
  if (law.cohesion || law.rolling)
    return std::nullopt;
  const auto base = BatchLawConstants::of(law);
  if (!base)
    return std::nullopt;
  return HertzMindlinConstants{*base};
}

namespace {

// The loop body follows ContactLaw<3>::force line by line, calling the same formulas (one
// inline function each in contact/normal_elasticity.h, normal_damping.h, tangential.h,
// pair_geometry.h), with fewer divisions; the branches of the scalar law become selects, and
// the branches the batch does not take (large angles, large unloading, no overlap) set `exact`.
// Compiled once per instruction set (GRANPACK_SIMD_CLONES): the default build stays portable
// (SSE2) and still runs 4- or 8-wide on CPUs with AVX2 or AVX-512.

GRANPACK_SIMD_CLONES
void evaluate_lanes(const HertzMindlinConstants& c, HertzMindlinBatch& b, std::size_t n,
                    std::size_t n_valid, double dt, HertzMindlinSums& out) {
  // The law's uniform choices as arithmetic, so that the loop body has no control flow.
  const BatchLawTerms law(c);
  const double half_dt = 0.5 * dt;
  // The sums, one variable each so that they vectorise as reductions (lane-wise partial
  // sums, combined at the end: a fixed order for a given batch and instruction set).
  double v00 = 0, v01 = 0, v02 = 0, v10 = 0, v11 = 0, v12 = 0, v20 = 0, v21 = 0, v22 = 0;
  double e00 = 0, e01 = 0, e02 = 0, e10 = 0, e11 = 0, e12 = 0, e20 = 0, e21 = 0, e22 = 0;
  double max_overlap = 0;
  long count = 0;
#pragma omp simd reduction(+ : v00, v01, v02, v10, v11, v12, v20, v21, v22, e00, e01, e02, e10, \
                               e11, e12, e20, e21, e22, count) reduction(max : max_overlap)
  for (std::size_t l = 0; l < n; ++l) {
    // Geometry (make_pair_geometry).
    const double rx = b.rx[l], ry = b.ry[l], rz = b.rz[l];
    const double ri = b.rad_i[l], rj = b.rad_j[l];
    const double d = std::sqrt(rx * rx + ry * ry + rz * rz);
    // Divisions and square roots bound this loop: one reciprocal serves n and dt/|r|, one
    // division both effective quantities (results differ from the scalar law's by ~1 ulp).
    const double inv_d = 1.0 / d;
    const double nx = rx * inv_d, ny = ry * inv_d, nz = rz * inv_d;
    const double h = ri + rj - d;
    const double mi = b.mass_i[l], mj = b.mass_j[l];
    const double inv_sums = 1.0 / ((ri + rj) * (mi + mj));
    const double r_eff = ri * rj * (mi + mj) * inv_sums; // R_i R_j / (R_i + R_j)
    const double m_eff = mi * mj * (ri + rj) * inv_sums; // m_i m_j / (m_i + m_j)
    const bool touching = h > 0;
    const double hp = touching ? h : 0.0; // keeps the padding and flagged lanes finite

    // Branch vectors to the middle of the overlap: b_i = (R_i - h/2) n, b_j = -(R_j - h/2) n.
    const double ci = contact_arm(ri, h), cj = -contact_arm(rj, h);
    const double bix = ci * nx, biy = ci * ny, biz = ci * nz;
    const double bjx = cj * nx, bjy = cj * ny, bjz = cj * nz;

    // Relative velocity of j's contact point with respect to i's.
    const double vx = b.vx[l], vy = b.vy[l], vz = b.vz[l];
    const double wix = b.wix[l], wiy = b.wiy[l], wiz = b.wiz[l];
    const double wjx = b.wjx[l], wjy = b.wjy[l], wjz = b.wjz[l];
    const double dvx = vx + (wjy * bjz - wjz * bjy) - (wiy * biz - wiz * biy);
    const double dvy = vy + (wjz * bjx - wjx * bjz) - (wiz * bix - wix * biz);
    const double dvz = vz + (wjx * bjy - wjy * bjx) - (wix * biy - wiy * bix);
    const double dv_n = nx * dvx + ny * dvy + nz * dvz;
    const double h_dot = -dv_n;
    const double dtx = dvx - dv_n * nx, dty = dvy - dv_n * ny, dtz = dvz - dv_n * nz;

    // Normal elasticity and damping.
    const double k_n = hertz_stiffness(law.e_tilde, r_eff, hp) + law.k_lin;
    const double n_el = normal_elastic_force(law.n_factor, k_n, hp);
    const double n_visc = viscous_coefficient(law.two_zeta, m_eff, k_n) * h_dot;

    // Rotation of the contact over the step (contact_rotation_3d): rolling n x dn + pivoting.
    const Xyz normal{nx, ny, nz};
    const Xyz theta = contact_rotation_3d(normal, {vx, vy, vz}, {wix, wiy, wiz}, {wjx, wjy, wjz},
                                          dt * inv_d, half_dt);

    // Transport of T (as transport_tangential, with the small-angle series only).
    const Xyz t0{b.tx[l], b.ty[l], b.tz[l]};
    const double mag2 = squared_norm(t0);
    const double x2 = squared_norm(theta);
    const SmallAngle sa = small_angle_series(x2);
    const Xyz r = rotate_onto_tangent_plane(t0, theta, normal, sa.cos_x, sa.sin_x_over_x,
                                            sa.one_minus_cos_over_x2);
    const double rn2 = squared_norm(r);
    const double restore = rn2 > 0 ? std::sqrt(mag2 / (rn2 > 0 ? rn2 : 1.0)) : 0.0;
    double tx = mag2 == 0 ? t0.x : r.x * restore;
    double ty = mag2 == 0 ? t0.y : r.y * restore;
    double tz = mag2 == 0 ? t0.z : r.z * restore;

    // Walton: N^e decreased, T scaled by K_N(N)/K_N(N_old) = (N/N_old)^{1/3}.
    const double n_old = b.n_old[l];
    const bool unloading = law.walton & (n_el < n_old);
    const double xw = relative_load_change(n_el, unloading ? n_old : 1.0);
    const double ratio = n_el > 0 ? cbrt_one_plus_series(xw) : 0.0;
    const double scale = unloading ? ratio : 1.0;
    tx *= scale;
    ty *= scale;
    tz *= scale;

    // Elastic increment, then Coulomb on N^e.
    const double kdt = proportional_tangential_stiffness(law.k_t_ratio, k_n) * dt;
    tx -= kdt * dtx;
    ty -= kdt * dty;
    tz -= kdt * dtz;
    const double limit = coulomb_limit(law.mu, n_el);
    const double t2 = tx * tx + ty * ty + tz * tz;
    const bool slide = beyond_coulomb(t2, limit);
    const double cut = limit > 0 ? coulomb_scale(limit, t2 > 0 ? t2 : 1.0) : 0.0;
    tx = slide ? tx * cut : tx;
    ty = slide ? ty * cut : ty;
    tz = slide ? tz * cut : tz;

    // Forces and moments.
    const double n_tot = applied_elastic_viscous_force(n_el + n_visc, law.tension) + 0.0;
    const double fx = n_tot * nx + tx, fy = n_tot * ny + ty, fz = n_tot * nz + tz;
    b.fx[l] = fx;
    b.fy[l] = fy;
    b.fz[l] = fz;
    b.tjx[l] = bjy * fz - bjz * fy;
    b.tjy[l] = bjz * fx - bjx * fz;
    b.tjz[l] = bjx * fy - bjy * fx;
    b.tix[l] = biy * (-fz) - biz * (-fy);
    b.tiy[l] = biz * (-fx) - bix * (-fz);
    b.tiz[l] = bix * (-fy) - biy * (-fx);
    b.tx[l] = tx;
    b.ty[l] = ty;
    b.tz[l] = tz;
    b.n_old[l] = n_el;
    b.overlap[l] = h;
    b.sliding[l] = slide ? 1 : 0;
    const bool big_angle = (mag2 != 0) & !(x2 < kSmallAngleSquared);
    // (A zero T needs no rescaling: frictionless packings never leave the path here.)
    const bool big_unload =
        unloading & (mag2 != 0) & (n_el > 0) & !(std::abs(xw) < kSmallLoadChange);
    const bool exact = !touching | big_angle | big_unload;
    b.exact[l] = exact ? 1 : 0;

    // This lane's share of the sums: none for padding and flagged lanes.
    const double w = (l < n_valid) & !exact ? 1.0 : 0.0;
    const double wfx = w * fx, wfy = w * fy, wfz = w * fz;
    v00 += wfx * rx;
    v01 += wfx * ry;
    v02 += wfx * rz;
    v10 += wfy * rx;
    v11 += wfy * ry;
    v12 += wfy * rz;
    v20 += wfz * rx;
    v21 += wfz * ry;
    v22 += wfz * rz;
    const double ex = w * (n_el * nx + tx), ey = w * (n_el * ny + ty), ez = w * (n_el * nz + tz);
    e00 += ex * rx;
    e01 += ex * ry;
    e02 += ex * rz;
    e10 += ey * rx;
    e11 += ey * ry;
    e12 += ey * rz;
    e20 += ez * rx;
    e21 += ez * ry;
    e22 += ez * rz;
    count += w > 0 ? 1 : 0;
    const double rel = w * hp / (ri < rj ? ri : rj);
    max_overlap = rel > max_overlap ? rel : max_overlap;
  }
  const double v[9] = {v00, v01, v02, v10, v11, v12, v20, v21, v22};
  const double e[9] = {e00, e01, e02, e10, e11, e12, e20, e21, e22};
  for (int k = 0; k < 9; ++k) {
    out.virial[k] = v[k];
    out.virial_elastic[k] = e[k];
  }
  out.max_overlap = max_overlap;
  out.contacts = count;
}

} // namespace

void evaluate(const HertzMindlinConstants& c, HertzMindlinBatch& b, std::size_t n, double dt,
              HertzMindlinSums& sums) {
  evaluate_padded(b, n, sums, [&](std::size_t padded, HertzMindlinSums& s) {
    evaluate_lanes(c, b, padded, n, dt, s);
  });
}

} // namespace granpack
