#!/usr/bin/python3
"""I(k) of pooled ensembles beside [GRC]'s fitted curves, each divided by its value at k = 1/a
(issue 27; docs/reproduction-2d.md, "The blob size against geometric aggregation").

Dividing by I(1/a) compares the shapes only: how much the density fluctuations grow from the
grain scale to the cell's, which is what the blob size xi of eq. (28) measures. [GRC]'s curves
are eq. (28) with their table VII's d_F and xi (Cst = 0), drawn over the k range of a
1400-disk cell at Phi = 0.36 (k a from 2 pi / 55 to 2 pi).

  /usr/bin/python3 jobs/tools/plot_ik_yardstick.py OUT.png LABEL=FILE.json[:STAGE] ...

FILE.json is `granpack ensemble`'s ensemble.json (its `density_pooled`; STAGE picks one of its
configurations, default the first; a file named otherwise is read as one when STAGE is given)
or one configuration's `granpack analyze --json` file (its `density`).
"""
import argparse

import numpy as np

import granpack_io as gio
from plot_analysis import eq28_over_a2  # [GRC] eq. (28), as granpack evaluates it

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PROG = "plot_ik_yardstick.py"
# [GRC] table VII: (d_F, xi/a).
GRC = {"[GRC] no RR, P* = 0": (1.925, 8.29), "[GRC] RR, P* = 0": (1.53, 9.3),
       "[GRC] RR, P* = 0.01": (1.51, 5.06)}


def pooled(spec):
    label, _, rest = spec.rpartition("=")  # labels may hold "=", paths do not
    path, _, stage = rest.partition(":")
    if not path:
        gio.fail(PROG, f"'{spec}' is not LABEL=FILE.json[:STAGE]")
    try:
        if stage or path.endswith("ensemble.json"):
            pools = gio.read_ensemble(path).get("density_pooled") or {}
            stage = stage or next(iter(pools), "")
            if stage not in pools:
                gio.fail(PROG, f"{path}: no pooled I(k) of stage '{stage}' "
                         f"(has: {', '.join(pools) or 'none'})")
            ik = pools[stage]["I_k"]
        else:
            density = gio.read_analysis(path).get("density")
            if not density:
                gio.fail(PROG, f"{path}: no density (a 2D analysis has it)")
            ik = density["I_k"]
    except gio.GranpackFileError as e:
        gio.fail(PROG, e)
    k = np.array(ik["k_times_a"])
    y = np.array(ik["I_over_a2"])
    keep = k <= 2 * np.pi
    return label, k[keep], y[keep] / np.interp(1.0, k, y)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("curves", nargs="+", help="LABEL=FILE.json[:STAGE]")
    a = ap.parse_args()
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    for spec in a.curves:
        label, k, y = pooled(spec)
        ax.loglog(k, y, "o-", ms=3, lw=1, label=label)
    k = np.geomspace(2 * np.pi / 55.3, 2 * np.pi, 200)
    for label, (d_f, xi) in GRC.items():
        y = eq28_over_a2(k, d_f, xi, 0.0, 1.0)  # Cst = 0; the amplitude cancels below
        ax.loglog(k, y / eq28_over_a2([1.0], d_f, xi, 0.0, 1.0)[0], "--", lw=1.5,
                  label=f"{label} (eq. 28)")
    ax.set_xlabel("k a")
    ax.set_ylabel("I(k) / I(1/a)")
    ax.set_title("Density fluctuations from the grain to the cell scale")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
