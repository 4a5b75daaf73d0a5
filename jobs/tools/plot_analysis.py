#!/usr/bin/python3
"""Figures of [AR] (Agnolin & Roux 2007, paper I) from `granpack analyze --json` output.

Usage: /usr/bin/python3 jobs/tools/plot_analysis.py OUT_DIR A.json [B.json ...] [--labels A,B,...]

Writes into OUT_DIR (created if needed), overlaying all input files:
  pf.png            P(f), f = N/<N>, linear and log-y panels, with the DTS fit  ([AR] figs. 4, 15)
  gr.png            g(r) versus r/a, g_I and g_III                              ([AR] figs. 5, 8)
  zh.png            z(h): linear, h <= 0.1 a, and z(h) - z0 on log-log axes,
                    with the fits of eq. (35) z0 + A h^beta                     ([AR] figs. 6, 9-12)
  coordination.png  x_i, grouped bars per file                                  ([AR] tables I, V)
  ik.png            2D files: I(k) a^-2 versus k a on log-log axes with the standard errors
                    and the fit of [GRC] eq. (28) (solid over the fitted range, dotted beyond),
                    d_F and xi in the legend                                    ([GRC] fig. 23)
The written files are printed on stdout; notes about missing data (older or 2D files) go to
stderr and the figure, or the file's curves, are left out. See docs/plots.md.
"""
import argparse
import math
import sys
from pathlib import Path

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import granpack_io as gio  # noqa: E402

PROG = "plot_analysis.py"
# Fit window of eq. (35) used by `granpack analyze` (docs/analysis.md, z_h_fit_*).
FIT_H_MIN, FIT_H_MAX = 1e-4, 0.04
ZH_LINEAR_H_MAX = 0.1


def note(msg):
    print(f"{PROG}: {msg}", file=sys.stderr)


def die(msg):
    print(f"{PROG}: error: {msg}", file=sys.stderr)
    sys.exit(2)


def dts_fit(f):
    """Donev-Torquato-Stillinger fit quoted in the caption of [AR] fig. 4."""
    return (3.43 * f**2 + 1.45 - 1.18 / (1.0 + 4.71 * f)) * np.exp(-2.25 * f)


def as_array(value):
    """A JSON list of numbers (null -> nan) as a 1D float array, or None."""
    if not isinstance(value, list) or not value:
        return None
    try:
        a = np.array([np.nan if v is None else v for v in value], dtype=float)
    except (TypeError, ValueError):
        return None
    return a if a.ndim == 1 else None


def as_number(value):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value)


def arrays(data, key, fields):
    """data[key][field] for each field as equal-length arrays, or (None, reason)."""
    block = data.get(key)
    if not isinstance(block, dict):
        return None, f"no {key}"
    out = []
    for field in fields:
        a = as_array(block.get(field))
        if a is None:
            return None, f"no {key}.{field}"
        out.append(a)
    return out, None


def fit_params(data, key):
    fit = data.get(key)
    if not isinstance(fit, dict):
        return None
    p = [as_number(fit.get(k)) for k in ("z0", "A", "beta")]
    if any(v is None or not np.isfinite(v) for v in p):
        return None
    return p


def coordination_dict(value):
    """x_i as {i: fraction}; accepts a dict keyed by the string i or a list indexed by i."""
    if isinstance(value, list):
        value = {str(i): v for i, v in enumerate(value)}
    if not isinstance(value, dict) or not value:
        return None
    out = {}
    for k, v in value.items():
        try:
            i = int(k)
        except (TypeError, ValueError):
            return None
        v = as_number(v)
        if v is None:
            return None
        out[i] = v
    return out


def load(path):
    """The analysis as stored (granpack_io.read_analysis, lists kept: as_array checks them)."""
    try:
        return gio.read_analysis(path, arrays=False)
    except gio.GranpackFileError as e:
        die(e)


def save(fig, out_dir, name, written):
    path = out_dir / name
    fig.savefig(path, dpi=120)
    plt.close(fig)
    written.append(path)


# ---------------------------------------------------------------------------------------------
def plot_pf(runs, out_dir, written):
    fig, (ax_lin, ax_log) = plt.subplots(1, 2, figsize=(11, 4.4))
    fmax, drawn = 5.0, 0
    for k, (label, data) in enumerate(runs):
        got, why = arrays(data, "P_f", ("f_edges", "pdf"))
        if got is None:
            note(f"{label}: {why}, left out of pf.png")
            continue
        edges, pdf = got
        if len(edges) != len(pdf) + 1:
            note(f"{label}: P_f.f_edges has {len(edges)} values for {len(pdf)} bins, "
                 "left out of pf.png")
            continue
        f = 0.5 * (edges[1:] + edges[:-1])
        fmax = max(fmax, float(np.nanmax(edges)))
        style = dict(marker="os^Dv<>ph*"[k % 10], ms=4, lw=0.8, color=f"C{k}",
                     label=label, mfc="none")
        ax_lin.plot(f, pdf, **style)
        # log axis: empty bins are left out, breaking the line
        ax_log.plot(f, np.where(pdf > 0, pdf, np.nan), **style)
        drawn += 1
    if not drawn:
        plt.close(fig)
        note("pf.png not written: no input has a usable P_f")
        return
    ff = np.linspace(0.0, fmax, 400)
    for ax in (ax_lin, ax_log):
        ax.plot(ff, dts_fit(ff), "k--", lw=1.2, label="DTS fit")
        ax.set_xlabel(r"$f = N/\langle N\rangle$")
        ax.set_ylabel(r"$P(f)$")
        ax.set_xlim(0, fmax)
        ax.legend(fontsize=8)
    ax_lin.set_ylim(bottom=0)
    ax_log.set_yscale("log")
    ax_lin.set_title("linear scale")
    ax_log.set_title("log scale")
    fig.suptitle(r"Distribution of normal forces $P(f)$ (cf. [AR] figs. 4, 15)")
    fig.tight_layout()
    save(fig, out_dir, "pf.png", written)


def plot_gr(runs, out_dir, written):
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    drawn, top, peaks = 0, 3.0, []
    rmax, rmin = 0.0, np.inf
    for k, (label, data) in enumerate(runs):
        got, why = arrays(data, "g_r", ("r_over_a",))
        if got is None:
            note(f"{label}: {why}, left out of gr.png")
            continue
        r = got[0]
        block = data["g_r"]
        for name, ls, lw in (("g_I", "-", 1.3), ("g_III", "--", 1.0)):
            g = as_array(block.get(name))
            if g is None:
                note(f"{label}: no g_r.{name}, left out of gr.png")
                continue
            if len(g) != len(r):
                note(f"{label}: g_r.{name} and g_r.r_over_a differ in length, left out of gr.png")
                continue
            sub = name.split("_")[1]
            ax.plot(r, g, ls, lw=lw, color=f"C{k}", label=f"{label}: $g^{{{sub}}}(r)$")
            beyond = g[r >= 1.05]
            if beyond.size and np.isfinite(beyond).any():
                top = max(top, 1.4 * float(np.nanmax(beyond)))
            if np.isfinite(g).any():
                i = int(np.nanargmax(g))
                peaks.append((label, sub, float(g[i]), float(r[i])))
            rmax = max(rmax, float(np.nanmax(r)))
            nonzero = r[np.nan_to_num(g) > 0]
            if nonzero.size:
                rmin = min(rmin, float(nonzero.min()))
            drawn += 1
    if not drawn:
        plt.close(fig)
        note("gr.png not written: no input has a usable g_r")
        return
    ax.set_ylim(0, top)
    # the empty core r < a (minus the overlaps) is cut, keeping 0.2 a before the first pair
    ax.set_xlim(max(0.0, np.floor(10.0 * (rmin - 0.2)) / 10.0) if np.isfinite(rmin) else 0.0,
                rmax if rmax > 0 else None)
    ax.axhline(1.0, color="0.6", lw=0.6)
    for x in (np.sqrt(3.0), 2.0):  # the sharp drops discussed in [AR] sec. III D
        ax.axvline(x, color="0.6", lw=0.6, ls=":")
    off = [p for p in peaks if p[2] > top]
    if off:
        text = "contact peak (off scale):\n" + "\n".join(
            f"{lab} $g^{{{sub}}}$ = {h:.3g} at r/a = {x:.3g}" for lab, sub, h, x in off)
        ax.text(0.98, 0.97, text, transform=ax.transAxes, ha="right", va="top", fontsize=8,
                bbox=dict(fc="white", ec="0.7"))
    ax.set_xlabel("$r/a$")
    ax.set_ylabel("$g(r)$")
    ax.legend(fontsize=8, loc="center right")
    ax.set_title(r"Pair correlation $g(r)$ (cf. [AR] figs. 5, 8); dotted: $r = \sqrt{3}\,a,\ 2a$",
                 fontsize=10)
    fig.tight_layout()
    save(fig, out_dir, "gr.png", written)


def plot_zh(runs, out_dir, written):
    fig, (ax_lin, ax_log) = plt.subplots(1, 2, figsize=(12, 4.8))
    drawn, log_points = 0, 0
    for k, (label, data) in enumerate(runs):
        got, why = arrays(data, "z_h", ("h_over_a",))
        if got is None:
            note(f"{label}: {why}, left out of zh.png")
            continue
        h = got[0]
        for name, marker, fit_key in (("z_I", "o", "z_h_fit_I"), ("z_III", "s", "z_h_fit_III")):
            z = as_array(data["z_h"].get(name))
            if z is None:
                note(f"{label}: no z_h.{name}, left out of zh.png")
                continue
            if len(z) != len(h):
                note(f"{label}: z_h.{name} and z_h.h_over_a differ in length, left out of zh.png")
                continue
            sub = name.split("_")[1]
            color = f"C{(2 * k + (sub == 'III')) % 10}"
            fit = fit_params(data, fit_key)
            lin = h <= ZH_LINEAR_H_MAX
            ax_lin.plot(h[lin], z[lin], marker, ms=3.5, mfc="none", color=color,
                        label=f"{label}: $z^{{{sub}}}(h)$")
            # log panel: z(h) - z0, z0 from the eq. (35) fit, else z(h = 0)
            if fit is not None:
                z0, A, beta = fit
                z0_text = "$z_0$ (fit)"
            else:
                at0 = z[h == 0]
                z0 = float(at0[0]) if at0.size else None
                z0_text = "$z(0)$"
                note(f"{label}: no {fit_key}, zh.png shows z_{sub}(h) - z(0) without a fit")
            if z0 is not None:
                dz = z - z0
                pos = (h > 0) & (dz > 0)
                log_points += int(pos.sum())
                ax_log.plot(h[pos], dz[pos], marker, ms=3.5, mfc="none", color=color,
                            label=f"{label}: $z^{{{sub}}}(h)$ − {z0_text}")
            if fit is not None:
                hh = np.geomspace(FIT_H_MIN, FIT_H_MAX, 100)
                text = (f"fit (35): $z_0$={z0:.3f}, A={A:.3g}, β={beta:.3f}")
                ax_lin.plot(np.concatenate([[0.0], hh]), z0 + A * np.concatenate([[0.0], hh])**beta,
                            ":", lw=1.4, color=color, label=text)
                ax_log.plot(hh, A * hh**beta, ":", lw=1.4, color=color, label=text)
            drawn += 1
    if not drawn:
        plt.close(fig)
        note("zh.png not written: no input has a usable z_h")
        return
    ax_lin.set_xlim(0, ZH_LINEAR_H_MAX)
    ax_lin.set_xlabel("$h/a$")
    ax_lin.set_ylabel("$z(h)$")
    ax_lin.set_title("linear scale (cf. [AR] figs. 6a, 9)", fontsize=10)
    if log_points:
        ax_log.set_xscale("log")
        ax_log.set_yscale("log")
    else:
        note("zh.png: no positive z(h) - z0 to draw on log scales")
        ax_log.text(0.5, 0.5, "no positive $z(h) - z_0$", transform=ax_log.transAxes,
                    ha="center")
    ax_log.axvspan(FIT_H_MIN, FIT_H_MAX, color="0.92", zorder=0, label="fit window")
    ax_log.set_xlabel("$h/a$")
    ax_log.set_ylabel("$z(h) - z_0$")
    ax_log.set_title("log scales (cf. [AR] figs. 6b, 10-12)", fontsize=10)
    for ax in (ax_lin, ax_log):
        ax.legend(fontsize=7)
    fig.suptitle(r"Coordination of near neighbours $z(h)$, fits $z_0 + A\,h^\beta$ (eq. 35)")
    fig.tight_layout()
    save(fig, out_dir, "zh.png", written)


COORDINATION_PANELS = (
    ("x_i", "(I) backbone contacts, rattlers in $x_0$ (tables I, V)"),
    ("x_i_all_contacts", "all force-carrying contacts (II after fix_rattlers)"),
    ("x_i_without_rattlers", "(III) backbone, rattlers removed"),
)


def plot_coordination(runs, out_dir, written):
    panels = []
    for key, title in COORDINATION_PANELS:
        rows = []
        for k, (label, data) in enumerate(runs):
            if data.get(key) is None:
                continue
            x = coordination_dict(data[key])
            if x is None:
                note(f"{label}: {key} is not a coordination table, left out of coordination.png")
                continue
            rows.append((k, label, data, x))
        if rows:
            panels.append((key, title, rows))
    if not panels:
        note("coordination.png not written: no input has a usable x_i")
        return
    for key, _ in COORDINATION_PANELS:
        if key not in [p[0] for p in panels]:
            note(f"coordination.png: no input has {key}, panel left out")
    nfiles = len(runs)
    fig, axes = plt.subplots(len(panels), 1, figsize=(max(7.0, 5.0 + 0.6 * nfiles),
                                                      3.2 * len(panels)), squeeze=False)
    for ax, (key, title, rows) in zip(axes[:, 0], panels):
        imax = max(max(x) for _, _, _, x in rows)
        i = np.arange(0, imax + 1)
        width = 0.8 / nfiles
        for k, label, data, x in rows:
            vals = np.array([100.0 * x.get(j, 0.0) for j in i])
            legend = label
            extra = [f"{sym}={data[name]:.4g}" for name, sym in
                     (("phi", "Φ"), ("z", "z"), ("z_star", "z*"))
                     if as_number(data.get(name)) is not None]
            if extra:
                legend += " (" + ", ".join(extra) + ")"
            ax.bar(i - 0.4 + width * (k + 0.5), vals, width, color=f"C{k}", label=legend)
        ax.set_xticks(i)
        ax.set_xlabel("number of contacts $i$")
        ax.set_ylabel("$x_i$ (%)")
        ax.set_title(f"{key}: {title}", fontsize=10)
        ax.legend(fontsize=8)
    fig.suptitle("Coordination distribution $x_i$ (cf. [AR] tables I, V)")
    fig.tight_layout()
    save(fig, out_dir, "coordination.png", written)


def legendre_p(nu, x):
    """P_nu(x) for 0 < x <= 1 by its hypergeometric series in (1 - x)/2, as
    src/analysis/density_correlation.cpp evaluates it."""
    y = 0.5 * (1.0 - x)
    term = total = 1.0
    for n in range(2000):
        term *= (n - nu) * (nu + 1 + n) / float((n + 1) * (n + 1)) * y
        total += term
        if abs(term) < 1e-17 * abs(total):
            break
    return total


def eq28_over_a2(ka, d_f, xi_a, constant_a2, amplitude_reduced):
    """[GRC] eq. (28) in units of a: I/a^2 = Cst/a^2 + A 2 pi Gamma(d_F) s^-d_F P_{d_F-1}(p/s),
    p = a/xi, s = sqrt(p^2 + (k a)^2), A = amplitude a^(d_F - 2) = Phi (l/a)^(2 - d_F)."""
    p = 1.0 / xi_a
    out = []
    for k in ka:
        s = math.hypot(p, k)
        out.append(constant_a2 + amplitude_reduced * 2 * math.pi * math.gamma(d_f) * s ** (-d_f)
                   * legendre_p(d_f - 1.0, p / s))
    return np.array(out)


def plot_ik(runs, out_dir, written):
    fig, ax = plt.subplots(figsize=(6.8, 5.0))
    drawn = 0
    for k, (label, data) in enumerate(runs):
        density = data.get("density")
        if not isinstance(density, dict):
            note(f"{label}: no density (3D or an older file), left out of ik.png")
            continue
        got, why = arrays(density, "I_k", ("k_times_a", "I_over_a2", "I_error_over_a2"))
        if got is None:
            note(f"{label}: {why.replace('no ', 'no density.')}, left out of ik.png")
            continue
        ka, I, err = got
        if not (len(ka) == len(I) == len(err)):
            note(f"{label}: density.I_k arrays differ in length, left out of ik.png")
            continue
        keep = (ka > 0) & (I > 0)
        ax.errorbar(ka[keep], I[keep], yerr=np.minimum(err[keep], 0.999 * I[keep]), fmt="o",
                    ms=3, lw=0.8, color=f"C{k}", label=f"{label}")
        drawn += 1
        fit = density.get("fit_eq28")
        if not isinstance(fit, dict):
            note(f"{label}: no density.fit_eq28, curve only")
            continue
        names = ("d_F", "xi_over_a", "constant_over_a2", "l_over_a")
        d_f, xi_a, c_a2, l_a = (as_number(fit.get(n)) for n in names)
        phi = as_number(data.get("phi"))
        if None in (d_f, xi_a, c_a2, l_a, phi) or xi_a <= 0 or abs(2.0 - d_f) < 1e-9:
            note(f"{label}: density.fit_eq28 incomplete (or d_F = 2), no fit curve")
            continue
        amp = phi * l_a ** (2.0 - d_f)
        rng = as_array(fit.get("k_range_times_a"))
        lo, hi = (float(rng[0]), float(rng[1])) if rng is not None and len(rng) == 2 else \
            (float(ka[keep].min()), float(ka[keep].max()))
        grid = np.geomspace(ka[keep].min(), ka[keep].max(), 200)
        inside = (grid >= lo) & (grid <= hi)
        model = eq28_over_a2(grid, d_f, xi_a, c_a2, amp)
        ok = model > 0
        d_err, xi_err = as_number(fit.get("d_F_error")), as_number(fit.get("xi_error_over_a"))
        regime = fit.get("fractal_regime") is True
        text = (f"eq. (28): $d_F$ = {d_f:.3g}" + (f" ± {d_err:.2g}" if d_err is not None else "")
                + rf", $\xi/a$ = {xi_a:.3g}" + (f" ± {xi_err:.2g}" if xi_err is not None else "")
                + ("" if regime else " (no fractal regime)"))
        ax.plot(grid[inside & ok], model[inside & ok], "-", color=f"C{k}", lw=1.3, label=text)
        ax.plot(grid[~inside & ok], model[~inside & ok], ":", color=f"C{k}", lw=1.0)
    if not drawn:
        plt.close(fig)
        note("ik.png not written: no input has a usable density.I_k")
        return
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("$k a$")
    ax.set_ylabel("$I(k)/a^2$")
    ax.legend(fontsize=7)
    ax.set_title("Density fluctuations $I(k)$ and the fit of eq. (28) (cf. [GRC] fig. 23)",
                 fontsize=10)
    fig.tight_layout()
    save(fig, out_dir, "ik.png", written)


def main(argv=None):
    ap = argparse.ArgumentParser(
        prog=PROG,
        description="Figures of [AR] from `granpack analyze --json` files (docs/plots.md).")
    ap.add_argument("out_dir", metavar="OUT_DIR", help="directory for the PNG files")
    ap.add_argument("inputs", metavar="JSON", nargs="+", help="granpack analyze --json output")
    ap.add_argument("--labels", help="comma-separated legend labels, one per JSON file "
                    "(default: the file stems)")
    args = ap.parse_args(argv)

    if args.labels is not None:
        labels = [s.strip() for s in args.labels.split(",")]
        if len(labels) != len(args.inputs):
            die(f"--labels has {len(labels)} labels for {len(args.inputs)} JSON files")
    else:
        labels = [Path(p).stem for p in args.inputs]
        if len(set(labels)) < len(labels):  # same stem in several folders: add the folder
            labels = [f"{Path(p).resolve().parent.name}/{Path(p).stem}" for p in args.inputs]
    runs = [(label, load(path)) for label, path in zip(labels, args.inputs)]

    out_dir = Path(args.out_dir)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        die(f"cannot create '{out_dir}': {e.strerror or e}")

    written, failed = [], []
    for plot in (plot_pf, plot_gr, plot_zh, plot_coordination, plot_ik):
        try:
            plot(runs, out_dir, written)
        except Exception as e:  # a figure that fails must not stop the others
            plt.close("all")
            failed.append(plot.__name__)
            note(f"{plot.__name__} failed: {type(e).__name__}: {e}")
    for path in written:
        print(path)
    if not written:
        note("no figure written")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
