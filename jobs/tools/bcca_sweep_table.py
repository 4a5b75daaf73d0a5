#!/usr/bin/python3
"""The table of jobs/tools/bcca_density_sweep.sh: per solid fraction, the pooled I(k) fit of
eq. (28) (`granpack ensemble`'s density_pooled) and the per-sample C(r) fits of eq. (27) of
the BCCA gels under OUT/phi<PHI>/ (docs/reproduction-2d.md 4.10).

  /usr/bin/python3 jobs/tools/bcca_sweep_table.py OUT --n 1400 --k 6 --phis 0.36 0.26
"""
import argparse

import numpy as np

import granpack_io as gio


def row(out, phi, k):
    pooled = gio.read_ensemble(f"{out}/phi{phi}/ensemble.json")["density_pooled"]["bcca"]
    fit = pooled["fit_eq28"]
    fits = [gio.read_analysis(f"{out}/phi{phi}/sample_{s}/bcca.analysis.json")["density"]
            ["fit_eq27_real_space"] for s in range(1, k + 1)]
    fits = [f for f in fits if f.get("determined")]
    xi = np.array([f["xi_over_a"] for f in fits])
    d_f = np.array([f["d_F"] for f in fits])
    sd = lambda x: np.std(x, ddof=1) if len(x) > 1 else float("nan")  # noqa: E731
    if fit.get("determined"):
        eq28 = (f"{fit['d_F']:.2f} +- {fit['d_F_error']:.2f} | {fit['xi_over_a']:.2f} +- "
                f"{fit['xi_error_over_a']:.2f}")
    else:
        eq28 = "undetermined | "
    regime = "yes" if fit.get("fractal_regime") else f"no ({fit.get('regime_failure')})"
    eq27 = (f"{d_f.mean():.2f} +- {sd(d_f):.2f} | {xi.mean():.2f} +- {sd(xi):.2f} "
            f"({len(fits)} of {k})" if len(fits) else "none determined | ")
    return f"| {phi} | {eq28} | {regime} | {eq27} |"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out", help="the sweep's directory (OUT of bcca_density_sweep.sh)")
    ap.add_argument("--n", type=int, required=True, help="disks per gel")
    ap.add_argument("--k", type=int, required=True, help="samples per solid fraction")
    ap.add_argument("--phis", nargs="+", required=True, help="the solid fractions, as named")
    a = ap.parse_args()
    try:
        rows = [row(a.out, phi, a.k) for phi in a.phis]
    except (gio.GranpackFileError, KeyError) as e:
        gio.fail("bcca_sweep_table.py", e)
    print(f"BCCA, n = {a.n}, K = {a.k} per solid fraction (xi, d_F from eq. 28 on the pooled "
          "I(k); C(r): eq. 27 per sample, mean +- sd of the determined ones)")
    print("| Phi | pooled I(k): d_F | pooled I(k): xi/a | fractal regime | C(r): d_F | C(r): xi/a |")
    print("|---|---|---|---|---|---|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
