#!/usr/bin/python3
"""Moduli of the [AR] ensembles from `granpack stiffness --json` files (issue 28).

Usage:
  ensemble_moduli.py DIR [--json OUT.json] [--plot G_over_B.png] [--plot-pressure G_of_P.png]
                    [--plot-qs G_of_P_frictional.png]

DIR is what jobs/runs/ar_moduli.sh writes: DIR/ens/<state>/<sample>.json (one state per
directory, its samples the files in it), DIR/single/<stem>.json (docs/data/<stem>.h5: one state
per prefix before "_n4000", e.g. B_n4000_seed1 and B_n4000_seed2 are two samples of "B
(docs/data)") and DIR/fig3/<stem>.json (A at n = 1372 along its pressure steps: one row per
file, ordered by pressure) and DIR/qs/<series>/<stem>.json (a frictional packing along its
quasi-static pressure steps, e.g. D_QS_sample_1: D at 1 kPa and its steps to 100 kPa, one row
per file, ordered by pressure). Any of the four may be absent.

Per state, over its K samples: mean, sample standard deviation (ddof = 1; null for K = 1) and
the values of
  B_V, B_R, G_V, G_R   the isotropic Voigt and Reuss averages of the elastic tensor (Pa)
  G_over_B             G_V / B_V of each sample
  nonaffine_B, nonaffine_G   the fraction of the affine modulus the grains' relaxation removes,
                       1 - B_V / B_V(affine), 1 - G_V / G_V(affine)
  B_affine, G_affine   the affine Voigt moduli (Pa)
  k                    the mechanisms of the backbone (trivial + divalent + others)
  z_star               2 N_c* / n*, the backbone coordination
  P, phi, H_over_Nf    pressure (Pa), solid fraction, degree of hyperstaticity
  B_reduced, G_reduced B_V, G_V / (E~^(2/3) P^(1/3)) (E~ = E / (1 - nu^2), from the file's
                       bulk_modulus_reduced)
  B_over_eq30          B over [AR] eq. (30) with the sample's own z, Phi, Z(5/3)
  c11 c22 c33 c44 c55 c66   the diagonal of the Voigt tensor (Pa; 2D: c11 c22 c66), and
  shear_c44, shear_c11_c12  the two cubic-type shear moduli, mean(c44, c55, c66) and
                       (mean c_aa - mean c_ab) / 2: an isotropic state has c11 = c22 = c33 and
                       c44 = c55 = c66 = (c11 - c12) / 2 within its sample scatter, which the
                       "isotropy" table on stdout shows (issue 28): per state, "isotropy" in
                       the JSON gives for the axial and the shear group the largest |t| of the
                       paired differences between two of its entries over the samples,
                       t = mean(a - b) / (sd(a - b) / sqrt(K)), and the pair that gives it
  Gaff_over_Baff       G_V / B_V of the affine tensor (isotropic contact orientations and
                       r = a give 3 (2 + 3 k_t / k_n) / 10: 0.6 without friction)
The pressure series gets power-law fits (least squares on the logarithms, "fits" in the JSON):
B_V and G_V against P, and G_V / B_V against z* - 6 for frictionless samples (z* > 6); each
frictional series ("qs_series", "qs_fits") B_V and G_V against P. Two or more frictional series
(the same deck, several seeds) are also summarised as an ensemble ("qs_ensemble"): per level
(file name) mean ± sd over the series, and mean ± sd of the series' exponents.
A sample whose moduli are not defined (moduli_valid false, no elastic_tensor) is left out and
listed under "excluded". The table on stdout gives mean ± sd; --json writes every number
(docs/stiffness.md, "Moduli of the [AR] ensembles"). Exit codes: 0, 2 bad input.
"""
import argparse
import itertools
import json
import math
import sys
from pathlib import Path

import numpy as np

import granpack_io as gio

PROG = "ensemble_moduli.py"
QUANTITIES = ("B_V", "B_R", "G_V", "G_R", "G_over_B", "nonaffine_B", "nonaffine_G", "B_affine",
              "G_affine", "k", "z_star", "P", "phi", "H_over_Nf", "B_reduced", "G_reduced",
              "B_over_eq30", "Gaff_over_Baff", "c11", "c22", "c33", "c44", "c55", "c66",
              "shear_c44", "shear_c11_c12")
# The diagonal entries of the Voigt tensor by their place in voigt_order.
DIAGONAL = {"c11": "xx", "c22": "yy", "c33": "zz", "c44": "yz", "c55": "xz", "c66": "xy"}


class InputError(Exception):
    """Bad input: the message names the file and key; exit code 2."""


def sample_values(path):
    """The quantities of one stiffness JSON, or None (with the reason) if it has no moduli."""
    try:
        j = gio.read_stiffness(path)
    except gio.GranpackFileError as e:
        raise InputError(str(e)) from None
    for key in ("backbone_contacts", "backbone_grains", "pressure", "phi", "mechanisms"):
        if key not in j:
            raise InputError(f"{path}: no key '{key}' (not a `granpack stiffness --json` file?)")
    e = j.get("elastic_tensor")
    if not j.get("moduli_valid", False) or not e:
        return None, "moduli not valid (unexpected mechanisms)"
    try:
        bv, gv = float(e["bulk_voigt"]), float(e["shear_voigt"])
        ba, ga = float(e["affine"]["bulk_voigt"]), float(e["affine"]["shear_voigt"])
    except (KeyError, TypeError) as err:
        raise InputError(f"{path}: elastic_tensor lacks {err} (written before the tensor?)") from None
    reuss = [e.get("bulk_reuss"), e.get("shear_reuss")]
    # B / (E~^(2/3) P^(1/3)) is in the file; the same factor reduces G.
    red = j.get("bulk_modulus_reduced")
    scale = red / j["bulk_modulus"] if red is not None and j.get("bulk_modulus") else None
    v = {
        "B_V": bv, "B_R": reuss[0], "G_V": gv, "G_R": reuss[1],
        "G_over_B": gv / bv,
        "nonaffine_B": 1.0 - bv / ba, "nonaffine_G": 1.0 - gv / ga,
        "B_affine": ba, "G_affine": ga,
        "k": j["mechanisms"],
        "z_star": 2.0 * j["backbone_contacts"] / j["backbone_grains"],
        "P": j["pressure"], "phi": j["phi"], "H_over_Nf": j.get("H_over_Nf"),
        "B_reduced": bv * scale if scale else None, "G_reduced": gv * scale if scale else None,
        "B_over_eq30": j.get("bulk_modulus_over_eq30"),
        "Gaff_over_Baff": ga / ba,
        "shear_c44": e.get("shear_c44"), "shear_c11_c12": e.get("shear_c11_c12"),
    }
    order = e.get("voigt_order", []) if "c" in e else []
    for name, comp in DIAGONAL.items():
        v[name] = float(e["c"][order.index(comp)][order.index(comp)]) if comp in order else None
    return v, None


def stats(values):
    """mean, sd (ddof = 1, None for one value), K and the values; None entries are dropped."""
    x = [float(t) for t in values if t is not None]
    if not x:
        return {"K": 0, "mean": None, "sd": None, "values": []}
    a = np.array(x)
    return {"K": len(x), "mean": float(a.mean()),
            "sd": float(a.std(ddof=1)) if len(x) > 1 else None, "values": x}


# The entries an isotropic state has equal: the axial diagonal, and the shear diagonal with the
# cubic-type (c11 - c12) / 2.
ISOTROPY_GROUPS = {"axial": ("c11", "c22", "c33"),
                   "shear": ("c44", "c55", "c66", "shear_c11_c12")}


def isotropy(rows):
    """Per group, the largest |t| over the pairs (a, b) of its entries, t = mean(a - b) /
    (sd(a - b) / sqrt(K)): the paired difference over the samples in units of its standard
    error. An isotropic state gives |t| of order 1; None with fewer than 2 samples, or when an
    entry is missing (2D has no c33, c44, c55)."""
    out = {}
    for group, names in ISOTROPY_GROUPS.items():
        if len(rows) < 2 or any(r.get(n) is None for r in rows for n in names):
            out[group] = None
            continue
        worst = None
        for a, b in itertools.combinations(names, 2):
            d = stats([r[a] - r[b] for r in rows])
            se = d["sd"] / math.sqrt(d["K"])
            t = abs(d["mean"]) / se if se > 0 else math.inf
            if worst is None or t > worst["t"]:
                worst = {"t": t, "pair": [a, b], "mean_difference": d["mean"], "standard_error": se}
        out[group] = worst
    return out


def gather(files):
    """{quantity: stats} over the files, the samples used and the excluded ones."""
    rows, used, excluded = [], [], []
    for f in files:
        v, why = sample_values(f)
        if v is None:
            excluded.append({"file": f.name, "why": why})
        else:
            rows.append(v)
            used.append(f.name)
    out = {q: stats([r[q] for r in rows]) for q in QUANTITIES}
    return {"K": len(rows), "samples": used, "excluded": excluded, "quantities": out,
            "isotropy": isotropy(rows)}


def collect(root):
    """The states under DIR (ens/, single/) and the pressure series (fig3/)."""
    root = Path(root)
    if not root.is_dir():
        raise InputError(f"{root}: not a directory")
    states = {}
    for d in sorted((root / "ens").glob("*")) if (root / "ens").is_dir() else []:
        files = sorted(d.glob("*.json"))
        if d.is_dir() and files:
            states[d.name] = dict(gather(files), source=f"ens/{d.name}")
    singles = {}
    for f in sorted((root / "single").glob("*.json")) if (root / "single").is_dir() else []:
        singles.setdefault(f.stem.split("_n4000")[0], []).append(f)
    for name, files in singles.items():
        states[f"{name} (docs/data)"] = dict(gather(files), source="single")
    series = pressure_rows(sorted((root / "fig3").glob("*.json")) if (root / "fig3").is_dir() else [])
    qs = {}
    for d in sorted((root / "qs").glob("*")) if (root / "qs").is_dir() else []:
        files = sorted(d.glob("*.json"))
        if d.is_dir() and files:
            qs[d.name] = pressure_rows(files)
    if not states and not series and not qs:
        raise InputError(f"{root}: no stiffness JSON under ens/, single/, fig3/ or qs/")
    return states, series, qs


def pressure_rows(files):
    """One row per file (its quantities, or why it is excluded), ordered by pressure."""
    rows = []
    for f in files:
        v, why = sample_values(f)
        rows.append(dict(v, file=f.name) if v else {"file": f.name, "excluded": why})
    rows.sort(key=lambda r: r.get("P", math.inf))
    return rows


def power_fit(x, y):
    """Exponent and prefactor of y = A x^e (least squares on the logarithms), or None."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = (x > 0) & (y > 0)
    if ok.sum() < 2:
        return None
    e, a = np.polyfit(np.log(x[ok]), np.log(y[ok]), 1)
    return {"exponent": float(e), "prefactor": float(math.exp(a)), "points": int(ok.sum())}


def series_fits(series):
    rows = [r for r in series if "excluded" not in r]
    if not rows:
        return {}
    dz = [r["z_star"] - 6 for r in rows]
    return {**qs_fits(rows),
            "G_over_B_vs_zstar_minus_6": power_fit(dz, [r["G_over_B"] for r in rows]),
            "G_over_B_per_zstar_minus_6": stats([r["G_over_B"] / d for r, d in zip(rows, dz)
                                                 if d > 0])}


def qs_fits(rows):
    """B_V and G_V against P along a pressure series (frictional or not)."""
    rows = [r for r in rows if "excluded" not in r]
    p = [r["P"] for r in rows]
    return {"B_V_vs_P": power_fit(p, [r["B_V"] for r in rows]),
            "G_V_vs_P": power_fit(p, [r["G_V"] for r in rows])}


QS_LEVEL_QUANTITIES = ("P", "phi", "z_star", "k", "B_V", "G_V", "G_over_B", "nonaffine_G")


def qs_ensemble(qs):
    """The frictional series as an ensemble: per level (the file name, e.g. QS_2.json, the same
    step of the same deck in every series), mean ± sd over the series of each quantity, and of
    each series' power-law exponents. None with fewer than two series."""
    if len(qs) < 2:
        return None
    levels = {}
    for rows in qs.values():
        for r in rows:
            if "excluded" not in r:
                levels.setdefault(r["file"], []).append(r)
    out = {name: {q: stats([r[q] for r in rows]) for q in QS_LEVEL_QUANTITIES}
           for name, rows in levels.items()}
    order = sorted(out, key=lambda n: out[n]["P"]["mean"])
    fits = [qs_fits(rows) for rows in qs.values()]
    return {"K": len(qs), "series": list(qs), "levels": {n: out[n] for n in order},
            "exponents": {f: stats([x[f]["exponent"] for x in fits if x[f]])
                          for f in ("B_V_vs_P", "G_V_vs_P")}}


def pm(s, scale=1.0, digits=3):
    if s["mean"] is None:
        return "-"
    m = f"{s['mean'] / scale:.{digits}g}"
    return m if s["sd"] is None else f"{m} ± {s['sd'] / scale:.2g}"


def print_fits(fits, out):
    for name, f in fits.items():
        if f and "exponent" in f:
            print(f"fit {name}: exponent {f['exponent']:.3f}, prefactor {f['prefactor']:.4g} "
                  f"({f['points']} points)", file=out)
        elif f:
            print(f"{name}: {pm(f, 1, 3)} (K = {f['K']})", file=out)


def print_table(states, series, qs=None, out=sys.stdout):
    head = ("state", "K", "P (kPa)", "z*", "k", "B_V (MPa)", "B_R", "G_V (MPa)", "G_R", "G/B",
            "1-B/B_aff", "1-G/G_aff")
    print(" | ".join(head), file=out)
    for name, s in states.items():
        q = s["quantities"]
        cells = (name, str(s["K"]), pm(q["P"], 1e3), pm(q["z_star"], 1, 4), pm(q["k"], 1, 4),
                 pm(q["B_V"], 1e6, 4), pm(q["B_R"], 1e6, 4), pm(q["G_V"], 1e6, 4),
                 pm(q["G_R"], 1e6, 4), pm(q["G_over_B"], 1, 3), pm(q["nonaffine_B"], 1, 3),
                 pm(q["nonaffine_G"], 1, 3))
        print(" | ".join(cells), file=out)
        for x in s["excluded"]:
            print(f"  excluded: {x['file']}: {x['why']}", file=out)
    print("\nisotropy (MPa, mean ± sd over the samples)", file=out)
    print("state | K | c11 | c22 | c33 | c44 | c55 | c66 | (c11-c12)/2 | max |t| axial, shear",
          file=out)
    for name, s in states.items():
        q = s["quantities"]
        cells = [name, str(s["K"])] + [pm(q[c], 1e6, 4) for c in
                                       ("c11", "c22", "c33", "c44", "c55", "c66", "shear_c11_c12")]
        iso = s.get("isotropy") or {}
        cells.append(", ".join("-" if iso.get(g) is None else f"{iso[g]['t']:.2f}"
                               for g in ISOTROPY_GROUPS))
        print(" | ".join(cells), file=out)
    if series:
        print("\npressure series (docs/data/fig3, one sample)", file=out)
        print("file | P (kPa) | z* | B_V (MPa) | G_V (MPa) | G_R (MPa) | G/B | 1-G/G_aff", file=out)
        for r in series:
            if "excluded" in r:
                print(f"{r['file']} | excluded: {r['excluded']}", file=out)
                continue
            gr = "-" if r["G_R"] is None else f"{r['G_R'] / 1e6:.4g}"
            print(f"{r['file']} | {r['P'] / 1e3:.4g} | {r['z_star']:.4f} | {r['B_V'] / 1e6:.4g} | "
                  f"{r['G_V'] / 1e6:.4g} | {gr} | {r['G_over_B']:.4g} | {r['nonaffine_G']:.3f}",
                  file=out)
        print_fits(series_fits(series), out)
    for name, rows in (qs or {}).items():
        print(f"\nfrictional pressure series {name}", file=out)
        print("file | P (kPa) | phi | z* | k | B_V (MPa) | G_V (MPa) | G/B | 1-G/G_aff", file=out)
        for r in rows:
            if "excluded" in r:
                print(f"{r['file']} | excluded: {r['excluded']}", file=out)
                continue
            print(f"{r['file']} | {r['P'] / 1e3:.4g} | {r['phi']:.4f} | {r['z_star']:.4f} | "
                  f"{r['k']:.0f} | {r['B_V'] / 1e6:.4g} | {r['G_V'] / 1e6:.4g} | "
                  f"{r['G_over_B']:.4g} | {r['nonaffine_G']:.3f}", file=out)
        print_fits(qs_fits(rows), out)
    ens = qs_ensemble(qs or {})
    if ens:
        print(f"\nfrictional pressure series as an ensemble (K = {ens['K']} series, mean ± sd)",
              file=out)
        print("level | K | P (kPa) | phi | z* | k | B_V (MPa) | G_V (MPa) | G/B | 1-G/G_aff",
              file=out)
        for name, q in ens["levels"].items():
            print(f"{name} | {q['P']['K']} | {pm(q['P'], 1e3, 4)} | {pm(q['phi'], 1, 4)} | "
                  f"{pm(q['z_star'], 1, 4)} | {pm(q['k'], 1, 3)} | {pm(q['B_V'], 1e6, 4)} | "
                  f"{pm(q['G_V'], 1e6, 4)} | {pm(q['G_over_B'], 1, 3)} | "
                  f"{pm(q['nonaffine_G'], 1, 3)}", file=out)
        for f, e in ens["exponents"].items():
            print(f"exponent {f}: {pm(e, 1, 3)} (K = {e['K']})", file=out)


def plot_g_over_b(states, series, path):
    """(a) G/B against z* for every state (mean ± sd); (b) the frictionless samples against
    z* - 6 (log-log) with the fig3 pressure series and the line G/B = c (z* - 6)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(9.0, 3.8), dpi=110)
    for name, s in states.items():
        q = s["quantities"]
        if q["G_over_B"]["mean"] is None:
            continue
        zs, gb = q["z_star"], q["G_over_B"]
        ens = s["source"].startswith("ens")
        ax.errorbar(zs["mean"], gb["mean"], xerr=zs["sd"] or 0, yerr=gb["sd"] or 0,
                    fmt="o" if ens else "s", mfc="C0" if ens else "none",
                    color="C0" if ens else "C7", capsize=3, zorder=3)
        short = name.replace(" (docs/data)", "")
        label = f"{short} {q['P']['mean'] / 1e3:.3g} kPa"
        if ens:
            ax.annotate(label + f" (K={s['K']})", (zs["mean"], gb["mean"]), fontsize=6,
                        xytext=(5, -8), textcoords="offset points")
        elif short not in states:  # one file of a state without a committed ensemble
            ax.annotate(label, (zs["mean"], gb["mean"]), fontsize=6, xytext=(-4, 4),
                        textcoords="offset points", ha="right")
        if zs["mean"] > 6:
            bx.plot(zs["mean"] - 6, gb["mean"], "s", mfc="none", color="C0")
            bx.annotate(label, (zs["mean"] - 6, gb["mean"]), fontsize=6, xytext=(4, 2),
                        textcoords="offset points")
    rows = [r for r in series if "excluded" not in r and r["z_star"] > 6]
    if rows:
        dz = np.array([r["z_star"] - 6 for r in rows])
        gb = np.array([r["G_over_B"] for r in rows])
        bx.plot(dz, gb, "o", color="C1", label="A, n = 1372, 0.1 kPa - 1 MPa")
        c = float(np.mean(gb / dz))
        x = np.array([dz.min() * 0.8, dz.max() * 1.2])
        bx.plot(x, c * x, "--", color="gray", label=f"G/B = {c:.3g} (z* - 6)")
        bx.legend(fontsize=7, loc="upper left")
    ax.set_xlabel("backbone coordination z*")
    ax.set_ylabel("G_V / B_V")
    ax.set_yscale("log")
    ax.grid(alpha=0.3, which="both")
    ax.set_title("(a) states: o ensembles (mean ± sd), □ one file", fontsize=8)
    bx.set_xscale("log")
    bx.set_yscale("log")
    bx.set_xlabel("z* - 6")
    bx.set_ylabel("G_V / B_V")
    bx.grid(alpha=0.3, which="both")
    bx.set_title("(b) frictionless", fontsize=8)
    fig.tight_layout()
    fig.savefig(path)


def plot_pressure(series, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = [r for r in series if "excluded" not in r]
    if not rows:
        raise InputError("--plot-pressure: no pressure series (DIR/fig3/*.json)")
    p = np.array([r["P"] for r in rows])
    fig, ax = plt.subplots(figsize=(5.2, 3.8), dpi=110)
    ax.loglog(p, [r["B_V"] for r in rows], "o-", label="B (Voigt)")
    ax.loglog(p, [r["G_V"] for r in rows], "s-", label="G (Voigt)")
    ax.loglog(p, [r["G_R"] for r in rows], "^--", label="G (Reuss)")
    ax.loglog(p, [r["G_affine"] for r in rows], ":", color="gray", label="G affine")
    ax.set_xlabel("P (Pa)")
    ax.set_ylabel("modulus (Pa)")
    ax.set_title("A, n = 1372, one sample", fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path)


def plot_qs(qs, path):
    """Each frictional series: B and G against P (log-log), and G/B against z*."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    if not qs:
        raise InputError("--plot-qs: no frictional pressure series (DIR/qs/<series>/*.json)")
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(9.0, 3.8), dpi=110)
    ens = qs_ensemble(qs)
    for i, (name, rows) in enumerate(qs.items()):
        rows = [r for r in rows if "excluded" not in r]
        p = np.array([r["P"] for r in rows])
        # Several series: each thin and grey, their mean with error bars below.
        style = dict(color="0.75", lw=0.8, ms=3) if ens else dict(color=f"C{i}")
        ax.loglog(p, [r["B_V"] for r in rows], "o-", label=None if ens else f"B, {name}", **style)
        ax.loglog(p, [r["G_V"] for r in rows], "s--", label=None if ens else f"G, {name}", **style)
        bx.plot([r["z_star"] for r in rows], [r["G_over_B"] for r in rows], "o-",
                label=None if ens else name, **style)
        for r in rows if not ens else []:
            bx.annotate(f"{r['P'] / 1e3:.3g} kPa", (r["z_star"], r["G_over_B"]), fontsize=6,
                        xytext=(4, -8), textcoords="offset points")
    if ens:
        lv = list(ens["levels"].values())
        mean = lambda q: np.array([v[q]["mean"] for v in lv])
        sd = lambda q: np.array([v[q]["sd"] or 0.0 for v in lv])
        for q, mk, lab in (("B_V", "o-", "B"), ("G_V", "s--", "G")):
            ax.errorbar(mean("P"), mean(q), yerr=sd(q), fmt=mk, color="C0" if q == "B_V" else "C1",
                        capsize=3, label=f"{lab}, mean ± sd of {ens['K']} samples")
        bx.errorbar(mean("z_star"), mean("G_over_B"), xerr=sd("z_star"), yerr=sd("G_over_B"),
                    fmt="o-", color="C0", capsize=3, label=f"mean ± sd of {ens['K']} samples")
        for v in lv:
            bx.annotate(f"{v['P']['mean'] / 1e3:.3g} kPa", (v["z_star"]["mean"], v["G_over_B"]["mean"]),
                        fontsize=6, xytext=(4, -8), textcoords="offset points")
    first = [r for r in qs[next(iter(qs))] if "excluded" not in r]
    if len(first) >= 2:  # P^(1/3), the Hertz scaling on a fixed network, through the first B
        p = np.array([r["P"] for r in first])
        ax.loglog(p, first[0]["B_V"] * (p / p[0]) ** (1 / 3), ":", color="gray", label="∝ P^(1/3)")
    ax.set_xlabel("P (Pa)")
    ax.set_ylabel("Voigt modulus (Pa)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    ax.set_title("(a) moduli along the quasi-static steps", fontsize=8)
    bx.set_xlabel("backbone coordination z*")
    bx.set_ylabel("G_V / B_V")
    bx.grid(alpha=0.3)
    bx.legend(fontsize=7)
    bx.set_title("(b) G/B follows z*", fontsize=8)
    fig.tight_layout()
    fig.savefig(path)


def main(argv=None):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir", help="output directory of jobs/runs/ar_moduli.sh")
    ap.add_argument("--json", help="write the summary here (docs/data/ensembles/moduli.json)")
    ap.add_argument("--plot", help="G/B against z* (PNG)")
    ap.add_argument("--plot-pressure", help="B and G against P along the fig3 series (PNG)")
    ap.add_argument("--plot-qs", help="B, G and G/B along the frictional series (PNG)")
    a = ap.parse_args(argv)
    try:
        states, series, qs = collect(a.dir)
        print_table(states, series, qs)
        if a.json:
            doc = {"description": "granpack stiffness moduli per state: mean, sd (ddof=1), K, "
                                  "values (jobs/tools/ensemble_moduli.py; units Pa)",
                   "states": states, "pressure_series": series, "fits": series_fits(series),
                   "qs_series": qs, "qs_fits": {n: qs_fits(r) for n, r in qs.items()},
                   "qs_ensemble": qs_ensemble(qs)}
            Path(a.json).write_text(json.dumps(doc, indent=1) + "\n")
        if a.plot:
            plot_g_over_b(states, series, a.plot)
        if a.plot_pressure:
            plot_pressure(series, a.plot_pressure)
        if a.plot_qs:
            plot_qs(qs, a.plot_qs)
    except InputError as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
