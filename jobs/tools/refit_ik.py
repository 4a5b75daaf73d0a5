#!/usr/bin/python3
"""Refit [GRC] eq. (28) to an ensemble's pooled I(k) with other fitting choices (issue 27).

Usage:
  refit_ik.py ENSEMBLE.json [--level P0.01] [--check] [--json OUT.json]

Reads `density_pooled[LEVEL].I_k` (k a, I / a^2, the bins' standard errors and wave-vector
counts) of a 2D ensemble summary written by `granpack ensemble` and fits
    I(k) = Cst + A 2 pi Gamma(d_F) s^-d_F P_(d_F - 1)(p / s),  p = 1 / xi,  s = (p^2 + k^2)^(1/2)
(the transform of eq. 27, docs/analysis.md) once per variant:
  granpack       log I, each bin weighted by its count of wave vectors, k <= 2 pi / a: the choice
                 of `granpack analyze` / `ensemble`, refitted independently (scipy instead of
                 Eigen) -- --check requires it to reproduce the summary's fit_eq28 (d_F within
                 2e-3, xi within 1 %), so the other rows differ by the choice alone
  log-unweighted log I, every bin the same weight
  linear         I itself, every bin the same weight
  linear-stderr  I itself, each bin weighted by 1 / its standard error
  k0-count       `granpack` plus a bin at k = 0 with I(0) = Phi^2 A (the cell's mean density, a
                 single "wave vector", so count weight 1), A = L^2 from the first bin 2 pi / L
  k0-unweighted  the same bin, log I unweighted
  kmax=K         `granpack` with the window's upper end at k = K / a (K = 1, 2, 3, 4.19, 12.57)
  fixed-l=0.375  `granpack` with the length l of eq. (27) fixed at the mean radius 0.375 a
                 ([GRC]: "a constant of the order of the average particle radius"), so that
                 the amplitude Phi l^(2 - d_F) is no longer free: three parameters
Every fit also reports l / a = (A / Phi)^(1 / (2 - d_F)), the length its amplitude A implies.
Every variant starts from the same ten points as granpack's fit (xi0 = 0.3, 1, 10 / k_min and
3, 10 / k_max; d0 = 1.5, 1.9) and keeps the lowest cost with 0.5 < d_F < 2.5.
Prints one line per variant: d_F, xi / a, points, rms log residual. --json writes them.
Exit codes: 0; 1 a failed --check; 2 bad input (the file, the key or the level named).
"""
import argparse
import json
import math
import os
import sys

import numpy as np
from scipy.optimize import least_squares
from scipy.special import gamma, hyp2f1

import granpack_io as gio


def blob_intensity(k, d_f, xi, amplitude):
    """Eq. (28) without the constant: the Hankel transform of eq. (27)."""
    p = 1.0 / np.float64(xi)  # xi = 0 (a trial step): NaN, which the residual replaces
    s = np.hypot(p, k)
    nu = d_f - 1.0
    legendre = hyp2f1(-nu, nu + 1.0, 1.0, 0.5 * (1.0 - p / s))
    return amplitude * 2.0 * math.pi * gamma(d_f) * s**(-d_f) * legendre


def fit(k, intensity, weight, log_space, phi, fixed_l=None):
    """Least squares of (Cst / scale, log A, d_F, log xi); None when no start ends in 0.5..2.5.
    With fixed_l, A = phi fixed_l^(2 - d_F) instead of a free parameter."""
    scale = intensity[-1]
    sw = np.sqrt(weight)

    def amplitude(th):
        return phi * fixed_l**(2.0 - th[2]) if fixed_l else np.exp(th[1])

    def residuals(th):
        model = th[0] * scale + blob_intensity(k, th[2], np.exp(th[3]), amplitude(th))
        if log_space:
            with np.errstate(invalid="ignore", divide="ignore"):
                r = np.where(model > 0, np.log(intensity) - np.log(np.abs(model)), 1e3)
        else:
            r = (intensity - model) / scale
        return sw * np.nan_to_num(r, nan=1e3, posinf=1e3, neginf=-1e3)

    best = None
    k1 = k[k > 0][0]  # the starts ignore a k = 0 bin
    for xi0 in (0.3 / k1, 1.0 / k1, 3.0 / k[-1], 10.0 / k[-1], 10.0 / k1):
        for d0 in (1.5, 1.9):
            a0 = intensity[k > 0][0] / blob_intensity(k1, d0, xi0, 1.0)
            th0 = np.array([0.0, math.log(a0), d0, math.log(xi0)])
            try:
                res = least_squares(residuals, th0, method="lm", max_nfev=4000)
            except (ValueError, FloatingPointError):
                continue
            if not (0.5 < res.x[2] < 2.5) or not np.isfinite(res.x[3]):
                continue
            cost = float(np.sum(res.fun**2))
            if best is None or cost < best[0]:
                best = (cost, res.x)
    if best is None:
        return None
    th = best[1]
    model = th[0] * scale + blob_intensity(k, th[2], np.exp(th[3]), amplitude(th))
    with np.errstate(invalid="ignore", divide="ignore"):
        rms = float(np.sqrt(np.mean((np.log(intensity) - np.log(np.abs(model)))**2)))
    l_over_a = (fixed_l if fixed_l else
                float((amplitude(th) / phi)**(1.0 / (2.0 - th[2]))) if th[2] < 2.0 else None)
    return {"d_F": float(th[2]), "xi_over_a": float(math.exp(th[3])),
            "constant_over_a2": float(th[0] * scale), "l_over_a": l_over_a,
            "points": int(len(k)), "rms_log_residual": rms}


def variants(curve, phi, k_lo):
    k = np.asarray(curve["k_times_a"], float)
    intensity = np.asarray(curve["I_over_a2"], float)
    err = np.asarray(curve["I_error_over_a2"], float)
    count = np.asarray(curve["count"], float)
    ok = intensity > 0
    k, intensity, err, count = k[ok], intensity[ok], err[ok], count[ok]
    area = (2.0 * math.pi / k_lo)**2  # the first bin is 2 pi / L
    i0 = phi * phi * area

    def window(kmax):
        m = (k >= k_lo) & (k <= kmax)
        return k[m], intensity[m], err[m], count[m]

    kw, iw, ew, cw = window(2.0 * math.pi)
    k0, i0s = np.concatenate([[0.0], kw]), np.concatenate([[i0], iw])
    out = {
        "granpack": fit(kw, iw, np.maximum(1.0, cw), True, phi),
        "log-unweighted": fit(kw, iw, np.ones_like(kw), True, phi),
        "linear": fit(kw, iw, np.ones_like(kw), False, phi),
        "linear-stderr": fit(kw, iw, (iw[-1] / np.maximum(ew, 1e-300))**2, False, phi),
        "k0-count": fit(k0, i0s, np.concatenate([[1.0], np.maximum(1.0, cw)]), True, phi),
        "k0-unweighted": fit(k0, i0s, np.ones_like(k0), True, phi),
    }
    for kmax in (1.0, 2.0, 3.0, 4.0 * math.pi / 3.0, 4.0 * math.pi):
        kk, ii, _, cc = window(kmax)
        out[f"kmax={kmax:.3g}"] = (fit(kk, ii, np.maximum(1.0, cc), True, phi) if len(kk) >= 6
                                   else None)
    out["fixed-l=0.375"] = fit(kw, iw, np.maximum(1.0, cw), True, phi, fixed_l=0.375)
    return out


def bad_input(message):
    """Bad input: the message on stderr, exit 2 (a failed --check exits 1)."""
    print(f"refit_ik: {message}", file=sys.stderr)
    sys.exit(2)


def main():
    np.seterr(all="ignore")  # trial steps overflow; their residuals are replaced above
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("ensemble", help="ensemble.json of a 2D ensemble (granpack ensemble)")
    ap.add_argument("--level", action="append",
                    help="density_pooled key (default: every level in the file)")
    ap.add_argument("--check", action="store_true",
                    help="fail (exit 1) unless the 'granpack' variant reproduces fit_eq28")
    ap.add_argument("--json", help="write the variants' fits here")
    args = ap.parse_args()
    try:
        summary = gio.read_ensemble(args.ensemble)
    except gio.GranpackFileError as e:
        bad_input(str(e))
    pooled = summary.get("density_pooled")
    if not pooled:
        bad_input(f"{args.ensemble}: no 'density_pooled' (not a 2D ensemble summary)")
    levels = args.level or sorted(pooled)
    results, failed = {}, []
    for level in levels:
        if level not in pooled:
            bad_input(f"{args.ensemble}: no level '{level}' in density_pooled "
                      f"(it has {', '.join(sorted(pooled))})")
        entry = pooled[level]
        ref = entry["fit_eq28"]
        k_lo = ref["k_range_times_a"][0]
        fits = variants(entry["I_k"], entry["phi_of_mesh"], k_lo)
        results[level] = fits
        told = (f"d_F {ref['d_F']:.4f}, xi {ref['xi_over_a']:.4f} a" if ref.get("determined")
                else f"undetermined ({ref.get('reason')})")
        print(f"{args.ensemble} {level} (K = {entry['K']}): granpack's fit {told}")
        print(f"  {'variant':16s} {'d_F':>7s} {'xi/a':>9s} {'l/a':>9s} {'points':>6s} {'rms log':>8s}")
        for name, r in fits.items():
            if r is None:
                print(f"  {name:16s} {'no fit with 0.5 < d_F < 2.5':>43s}")
                continue
            ell = f"{r['l_over_a']:9.3g}" if r["l_over_a"] is not None else f"{'-':>9s}"
            print(f"  {name:16s} {r['d_F']:7.4f} {r['xi_over_a']:9.4g} {ell} {r['points']:6d} "
                  f"{r['rms_log_residual']:8.3f}")
        g = fits["granpack"]
        if args.check and ref.get("determined"):
            if (g is None or abs(g["d_F"] - ref["d_F"]) > 2e-3
                    or abs(g["xi_over_a"] / ref["xi_over_a"] - 1) > 1e-2):
                failed.append(level)
    if args.json:
        with open(args.json + ".tmp", "w") as f:
            json.dump(results, f, indent=1)
        os.replace(args.json + ".tmp", args.json)
    if failed:
        sys.exit(f"refit_ik: the independent fit does not reproduce fit_eq28 at {failed}")


if __name__ == "__main__":
    main()
