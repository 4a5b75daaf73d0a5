#!/usr/bin/python3
"""Pictures of 2D granpack packings in the style of [GRC] (Gilabert, Roux & Castellanos 2007).

Usage: /usr/bin/python3 jobs/tools/plot_2d.py OUT_DIR FILE.h5 [FILE2.h5 ...] [--labels A,B,...]
           [--threshold T] [--width normal|total] [--width-force W] [--summary]

For each 2D granpack HDF5 file (configuration or checkpoint) writes into OUT_DIR:
  LABEL_forces.png  the disks and one bar per interaction between the centres, width
                    proportional to |N| (or |F|): red compressive, green tensile, blue
                    distant (cohesive, across a gap), grey unstressed        ([GRC] figs. 2, 11, 12, 19)
  LABEL_NT.png      tangential force T against normal force N of every contact, in units of
                    F0 (cohesive) or <N> (cohesionless), Coulomb lines T = +-mu (N + F0)
                    and, with cohesion, the lines T = +-sqrt(3) N of eq. (20)   ([GRC] fig. 14)
  LABEL_theta.png   histogram of the angle theta between the normal n and the contact force F
                    (0 deg: repulsive, T = 0; 180 deg: tensile, T = 0)          ([GRC] fig. 15)
and, with several files, theta.png overlaying their theta histograms. The written files are
printed on stdout; --summary also prints the number of interactions in each colour class.
Bad input (missing or non-HDF5 file, not granpack, 3D, missing datasets) stops the tool with
exit code 2 and a message naming the file, before anything is written. See docs/plots.md.
"""
import argparse
import io
import math
import re
import sys
from pathlib import Path

import numpy as np
import matplotlib

import granpack_io as gio

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import EllipseCollection, PolyCollection  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch, Rectangle  # noqa: E402

PROG = "plot_2d.py"
CLASSES = ("compressive", "tensile", "distant", "unstressed")
COLOURS = {"compressive": "#d62728", "tensile": "#2ca02c", "distant": "#1f4fd6",
           "unstressed": "#9a9a9a"}
RATTLER_FILL = "#dcdcdc"


def note(msg):
    print(f"{PROG}: {msg}", file=sys.stderr)


def die(msg):
    print(f"{PROG}: error: {msg}", file=sys.stderr)
    sys.exit(2)


# ---------------------------------------------------------------------------------------------
def load(path, label):
    """Read one 2D packing (jobs/tools/granpack_io.py) and compute every interaction's static
    forces (in N)."""
    try:
        pk = gio.read_packing(path)
    except gio.GranpackFileError as e:
        die(str(e))
    if pk.dimension != 2:
        die(f"'{path}' is a {pk.dimension}D packing; {PROG} draws 2D packings only")
    # The contact law in force when the file was written (/parameters; older files replay the
    # stored deck's [material] and `set` stages).
    law = pk.law()
    if not pk.parameters and not law:
        note(f"{path}: no readable deck; assuming no cohesion and an unknown friction coefficient")
    f0, d0 = float(law.get("cohesion_force", 0.0)), float(law.get("cohesion_range", 0.0))
    mu = law.get("friction")
    mu = float(mu) if mu is not None else None
    if mu is None and law:
        note(f"{path}: no friction coefficient in the stored deck; no Coulomb lines")
    nc = pk.nc
    x = np.mod(pk.grains["scaled_position"].astype(float), 1.0) * pk.cell_length
    d = pk.branch                                          # minimum image
    dist = pk.distance
    if nc and not np.all(dist > 0):
        die(f"'{path}': two interacting grains at the same position")
    nrm = pk.normal if nc else np.zeros((0, 2))
    tng = np.stack([-nrm[:, 1], nrm[:, 0]], axis=1)          # n turned by +90 deg
    N = pk.total_normal_force                              # [GRC] eq. 4-5: N^e + N^a, > 0 repulsive
    T = (pk.contacts["tangential_force"][:, :2] * tng).sum(axis=1)  # signed T, positive moment on i
    return dict(path=str(path), label=label, kind=pk.kind, L=pk.cell_length, x=x, R=pk.radius,
                i=pk.i, j=pk.j, d=d, n_hat=nrm, t_hat=tng, Ne=pk.contacts["normal_force"], N=N, T=T,
                flags=pk.contacts["flags"].astype(np.int64), distant=pk.distant, gap=-pk.overlap,
                f0=f0, d0=d0, mu=mu)


def classify(run, threshold):
    """Colour class of every interaction; the force unit; the threshold in N."""
    contact = ~run["distant"]
    if run["f0"] > 0:
        unit, unit_name = run["f0"], "F_0"
    else:
        pos = run["N"][contact]
        unit = float(pos.mean()) if pos.size and pos.mean() > 0 else 0.0
        unit_name = r"\langle N\rangle"
        if unit <= 0:
            note(f"{run['label']}: no contact carries a force; forces are shown in N")
            unit, unit_name = 1.0, "1\\,\\mathrm{N}"
    thr = threshold * unit
    F = np.hypot(run["N"], run["T"])
    cls = np.full(len(F), "tensile", dtype=object)
    cls[run["N"] > 0] = "compressive"
    cls[contact & (F < thr)] = "unstressed"
    cls[run["distant"]] = "distant"
    run.update(unit=unit, unit_name=unit_name, thr=thr, F=F, cls=cls)
    # Grains that interact with nothing above the threshold (fig. 11: filled light grey;
    # without cohesion these are the rattlers of fig. 2a).
    stressed = np.zeros(len(run["R"]), dtype=bool)
    carry = ((cls == "compressive") | (cls == "tensile")
             | ((cls == "distant") & (np.abs(run["N"]) >= thr)))
    stressed[run["i"][carry]] = True
    stressed[run["j"][carry]] = True
    run["idle"] = ~stressed
    run["counts"] = {c: int((cls == c).sum()) for c in CLASSES}


def out_name(label):
    return re.sub(r"[^A-Za-z0-9._=+-]+", "_", label).strip("_") or "packing"


def save(fig, out_dir, name, written, dpi=110):
    """PNG; with Pillow (a dependency of Debian's matplotlib) reduced to a 256-colour palette,
    which keeps a 1400-disk network picture near 200 kB instead of 1 MB."""
    path = out_dir / name
    try:
        from PIL import Image
    except ImportError:
        Image = None
    if Image is None:
        fig.savefig(path, dpi=dpi)
    else:
        buf = io.BytesIO()
        fig.savefig(buf, dpi=dpi, format="png")
        buf.seek(0)
        with Image.open(buf) as im:
            im.convert("RGB").quantize(colors=256, method=Image.Quantize.FASTOCTREE,
                                       dither=Image.Dither.NONE).save(path, optimize=True)
    plt.close(fig)
    written.append(path)


def header(run):
    n = len(run["R"])
    Lx, Ly = run["L"]
    phi = math.pi * float((run["R"] ** 2).sum()) / (Lx * Ly)
    z = 2.0 * len(run["N"]) / n if n else 0.0
    mu = "?" if run["mu"] is None else f"{run['mu']:g}"
    coh = (f"$F_0$ = {run['f0']:.3g} N, $D_0$ = {run['d0']:.3g} m"
           if run["f0"] > 0 else "no cohesion")
    return f"{run['label']}: n = {n}, Φ = {phi:.4f}, z = {z:.3f}, μ = {mu}, {coh}"


# ---------------------------------------------------------------------------------------------
def plot_forces(run, args, out_dir, written):
    L, x, R = run["L"], run["x"], run["R"]
    Lx, Ly = L
    r_mean = float(R.mean()) if len(R) else 0.01 * min(Lx, Ly)
    # Full bar width = r_mean * force / F_w: F_w = max(F0, largest force) by default, so the
    # strongest bar is one mean radius wide and, with cohesion, F0 never thinner ([GRC] sec.
    # IV: forces of order F0 as thick as the radii).
    force = np.abs(run["N"]) if args.width == "normal" else run["F"]
    if args.width_force is not None:
        fw = args.width_force * run["unit"]
    else:
        fw = max(run["f0"], float(force.max()) if force.size else 0.0)
        if fw <= 0:
            fw = 1.0
    half = 0.5 * r_mean * force / fw
    half = np.maximum(half, 0.03 * r_mean)                 # hairlines stay visible

    # Fixed layout (inches): title band, the cell at its aspect ratio, legend band.
    width, top, bottom, side = 8.0, 0.5, 0.75, 0.15
    w_ax = width - 2 * side
    h_ax = min(w_ax * Ly / Lx, 11.0)
    w_ax = h_ax * Lx / Ly
    height = top + h_ax + bottom
    fig = plt.figure(figsize=(width, height))
    ax = fig.add_axes([(width - w_ax) / 2 / width, bottom / height, w_ax / width, h_ax / height])
    ax.set_xlim(0, Lx)
    ax.set_ylim(0, Ly)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])

    # Disks, with their periodic images that reach into the cell.
    offs, rad, idle = [], [], []
    for sx in (-1, 0, 1):
        for sy in (-1, 0, 1):
            p = x + np.array([sx * Lx, sy * Ly])
            keep = ((p[:, 0] + R > 0) & (p[:, 0] - R < Lx) & (p[:, 1] + R > 0) & (p[:, 1] - R < Ly))
            offs.append(p[keep])
            rad.append(R[keep])
            idle.append(run["idle"][keep])
    offs, rad, idle = np.concatenate(offs), np.concatenate(rad), np.concatenate(idle)
    faces = [RATTLER_FILL if k else "none" for k in idle]
    disks = EllipseCollection(2 * rad, 2 * rad, np.zeros(len(rad)), units="xy", offsets=offs,
                              offset_transform=ax.transData, facecolors=faces,
                              edgecolors="0.35", linewidths=0.4, zorder=1)
    ax.add_collection(disks)

    # Bars between centres: from i along the minimum-image vector, and from j backwards when
    # that bar leaves the cell (the two pieces meet across the boundary; the axes clip).
    xi, xj, d = x[run["i"]], x[run["j"]], run["d"]
    u = run["t_hat"] * half[:, None]
    polys, cols = [], []
    order = {"unstressed": 0, "distant": 1, "tensile": 2, "compressive": 3}
    idx = sorted(range(len(d)), key=lambda k: (order[run["cls"][k]], half[k]))
    for k in idx:
        starts = [xi[k]]
        end = xi[k] + d[k]
        if np.any(end < 0) or np.any(end > L):
            starts.append(xj[k] - d[k])
        for a in starts:
            b = a + d[k]
            polys.append([a + u[k], b + u[k], b - u[k], a - u[k]])
            cols.append(COLOURS[run["cls"][k]])
    if polys:
        ax.add_collection(PolyCollection(polys, facecolors=cols, edgecolors=cols,
                                         linewidths=0.15, zorder=2))
    ax.add_patch(Rectangle((0, 0), Lx, Ly, fill=False, lw=0.8, color="k", zorder=3))

    c = run["counts"]
    unit = f"${run['unit_name']}$"
    thr = f"{args.threshold:g} {unit}"
    handles = [
        Line2D([], [], color=COLOURS["compressive"], lw=3, label=f"compressive, N > 0 ({c['compressive']})"),
        Line2D([], [], color=COLOURS["tensile"], lw=3, label=f"tensile, N < 0 ({c['tensile']})"),
        Line2D([], [], color=COLOURS["distant"], lw=3, label=f"distant, gap < $D_0$ ({c['distant']})"),
        Line2D([], [], color=COLOURS["unstressed"], lw=3, label=f"unstressed contact, |F| < {thr} ({c['unstressed']})"),
        Patch(facecolor=RATTLER_FILL, edgecolor="0.35", lw=0.4,
              label=f"grain without stressed interaction ({int(run['idle'].sum())})"),
    ]
    what = "|N|" if args.width == "normal" else "|F|"
    fig.legend(handles=handles, loc="lower center", ncol=2, fontsize=8, frameon=False,
               bbox_to_anchor=(0.5, 0.0), borderaxespad=0.2)
    fig.suptitle(f"{header(run)}\nbar width ∝ {what}: one mean radius = {fw / run['unit']:.3g} {unit}"
                 f" = {fw:.3g} N", fontsize=9, y=1.0 - 0.04 / height)
    save(fig, out_dir, f"{out_name(run['label'])}_forces.png", written, dpi=args.dpi)


def plot_nt(run, args, out_dir, written):
    contact = ~run["distant"]
    u = run["unit"]
    N, T = run["N"][contact] / u, run["T"][contact] / u
    cls = run["cls"][contact]
    fig, ax = plt.subplots(figsize=(6.4, 5.2))
    for c in ("unstressed", "tensile", "compressive"):
        m = cls == c
        if m.any():
            ax.scatter(N[m], T[m], s=5, lw=0, color=COLOURS[c], alpha=0.8,
                       label=f"{c} ({int(m.sum())})", zorder=3)
    f0 = run["f0"] / u
    if N.size:
        lo, hi = min(float(N.min()), -f0), max(float(N.max()), 0.0)
        tmax = max(float(np.abs(T).max()), 1e-12)
    else:
        note(f"{run['label']}: no contacts, N-T plot is empty")
        lo, hi, tmax = -f0 - 0.1, 1.0, 1.0
    span = hi - lo if hi > lo else 1.0
    lo, hi = lo - 0.05 * span, hi + 0.05 * span
    ax.set_xlim(lo, hi)
    ax.set_ylim(-1.15 * tmax, 1.15 * tmax)
    ax.axhline(0, color="k", lw=0.5)
    ax.axvline(0, color="k", lw=0.5)
    mu = run["mu"]
    ratio = None
    if mu is not None and math.isfinite(mu):
        ne = np.linspace(-f0, hi, 2)
        ax.plot(ne, mu * (ne + f0), "k-", lw=1, label=f"Coulomb $T = \\pm\\mu (N + F_0)$, μ = {mu:g}"
                if run["f0"] > 0 else f"Coulomb $T = \\pm\\mu N$, μ = {mu:g}")
        ax.plot(ne, -mu * (ne + f0), "k-", lw=1)
        Nec = run["Ne"][contact]
        with np.errstate(divide="ignore", invalid="ignore"):
            r = np.abs(run["T"][contact]) / (mu * Nec)
        r = r[np.isfinite(r)]
        ratio = float(r.max()) if r.size else None
    elif mu is not None:
        note(f"{run['label']}: μ = inf, no Coulomb lines")
    if run["f0"] > 0:
        ne = np.array([lo, hi])
        ax.plot(ne, math.sqrt(3) * ne, "k--", lw=0.8, label=r"$T = \pm\sqrt{3}\,N$ (eq. 20, $R_1 = R_2 = R$)")
        ax.plot(ne, -math.sqrt(3) * ne, "k--", lw=0.8)
    unit = f"${run['unit_name']}$"
    ax.set_xlabel(f"normal force N / {unit}  (N > 0 repulsive)")
    ax.set_ylabel(f"tangential force T / {unit}")
    extra = f", max |T|/(μ$N^e$) = {ratio:.3f}" if ratio is not None else ""
    ax.set_title(f"{header(run)}\n{int(contact.sum())} contacts (distant pairs left out){extra}",
                 fontsize=8)
    ax.legend(fontsize=7, loc="upper left", markerscale=2)
    fig.tight_layout()
    save(fig, out_dir, f"{out_name(run['label'])}_NT.png", written, dpi=args.dpi)


def thetas(run):
    """theta = angle(n, F) in degrees for the stressed contacts ([GRC] fig. 15)."""
    m = (~run["distant"]) & (run["cls"] != "unstressed")
    return np.degrees(np.arctan2(np.abs(run["T"][m]), run["N"][m]))


def theta_marks(ax, runs):
    if any(r["f0"] > 0 for r in runs):
        for t in (60, 120):
            ax.axvline(t, color="k", ls="--", lw=0.7)
        ax.text(60, 0.98, r" $|T/N| = \sqrt{3}$", transform=ax.get_xaxis_transform(),
                va="top", fontsize=7)
    mus = {r["mu"] for r in runs if r["f0"] == 0 and r["mu"] is not None and math.isfinite(r["mu"])}
    for mu in sorted(mus):
        phi = math.degrees(math.atan(mu))
        ax.axvline(phi, color="0.3", ls=":", lw=0.9)
        ax.text(phi, 0.90, f" Coulomb, μ = {mu:g}", transform=ax.get_xaxis_transform(),
                va="top", fontsize=7)


def plot_theta(run, args, out_dir, written):
    th = thetas(run)
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    bins = np.arange(0, 180 + args.bin, args.bin)
    if th.size:
        ax.hist(th, bins=bins, density=True, color="0.6", edgecolor="k", lw=0.5)
    else:
        note(f"{run['label']}: no stressed contact, theta histogram is empty")
    theta_marks(ax, [run])
    ax.set_xlim(0, 180)
    ax.set_xticks(range(0, 181, 30))
    ax.set_xlabel(r"θ = angle between $\mathbf{n}$ and $\mathbf{F}$ (deg): 0 repulsive, 180 tensile, $T = 0$")
    ax.set_ylabel("probability density (1/deg)")
    ax.set_title(f"{header(run)}\n{th.size} contacts with |F| ≥ {args.threshold:g} "
                 f"${run['unit_name']}$, bins of {args.bin:g}°", fontsize=8)
    fig.tight_layout()
    save(fig, out_dir, f"{out_name(run['label'])}_theta.png", written, dpi=args.dpi)


def plot_theta_all(runs, args, out_dir, written):
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    bins = np.arange(0, 180 + args.bin, args.bin)
    for k, run in enumerate(runs):
        th = thetas(run)
        if not th.size:
            continue
        if k == 0:  # [GRC] fig. 15: one shaded, the others bold lines
            ax.hist(th, bins=bins, density=True, color="0.75", label=f"{run['label']} ({th.size})")
        else:
            ax.hist(th, bins=bins, density=True, histtype="step", lw=1.4, color=f"C{k - 1}"
                    if k > 1 else "k", label=f"{run['label']} ({th.size})")
    theta_marks(ax, runs)
    ax.set_xlim(0, 180)
    ax.set_xticks(range(0, 181, 30))
    ax.set_xlabel(r"θ = angle between $\mathbf{n}$ and $\mathbf{F}$ (deg)")
    ax.set_ylabel("probability density (1/deg)")
    ax.set_title("Contact force orientation (cf. [GRC] fig. 15)", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    save(fig, out_dir, "theta.png", written, dpi=args.dpi)


def main(argv=None):
    ap = argparse.ArgumentParser(
        prog=PROG, description="Force networks, N-T scatter and force-angle histograms of 2D "
        "granpack packings, after [GRC] figs. 2, 11, 14, 15 (docs/plots.md).")
    ap.add_argument("out_dir", metavar="OUT_DIR", help="directory for the PNG files")
    ap.add_argument("inputs", metavar="FILE.h5", nargs="+", help="2D granpack HDF5 files")
    ap.add_argument("--labels", help="comma-separated labels, one per file (default: the file "
                    "stems); also the prefixes of the PNG names")
    ap.add_argument("--threshold", type=float, default=1e-3,
                    help="unstressed below |F| < THRESHOLD x unit, unit = F0 with cohesion, "
                    "<N> without (default 1e-3; [GRC] figs. 11, 12: 1e-4, 1e-2)")
    ap.add_argument("--width", choices=("normal", "total"), default="normal",
                    help="bar width proportional to |N| ([GRC] fig. 2, default) or to the total "
                    "|F| = |N n + T t| (figs. 11, 12, 19)")
    ap.add_argument("--width-force", type=float, metavar="W",
                    help="force (in units of F0 or <N>) drawn as wide as a mean radius; default "
                    "max(F0, largest force). Fix it to compare files on one scale")
    ap.add_argument("--bin", type=float, default=5.0, help="theta bin width in degrees (default 5)")
    ap.add_argument("--dpi", type=float, default=110, help="PNG resolution (default 110)")
    ap.add_argument("--summary", action="store_true",
                    help="also print, per file, the interactions in each colour class")
    args = ap.parse_args(argv)
    if not (args.threshold >= 0 and math.isfinite(args.threshold)):
        die("--threshold must be a finite number >= 0")
    if args.width_force is not None and not (args.width_force > 0 and math.isfinite(args.width_force)):
        die("--width-force must be a finite number > 0")
    if not (0 < args.bin <= 180):
        die("--bin must be in (0, 180]")
    if not (10 <= args.dpi <= 600):
        die("--dpi must be in [10, 600]")

    if args.labels is not None:
        labels = [s.strip() for s in args.labels.split(",")]
        if len(labels) != len(args.inputs):
            die(f"--labels has {len(labels)} labels for {len(args.inputs)} files")
    else:
        labels = [Path(p).stem for p in args.inputs]
        if len(set(labels)) < len(labels):  # same stem in several folders: add the folder
            labels = [f"{Path(p).resolve().parent.name}/{Path(p).stem}" for p in args.inputs]
    if len({out_name(s) for s in labels}) < len(labels):
        die("two files would write the same PNG names; give distinct --labels")
    runs = [load(path, label) for label, path in zip(labels, args.inputs)]
    for run in runs:
        classify(run, args.threshold)

    out_dir = Path(args.out_dir)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        die(f"cannot create '{out_dir}': {e.strerror or e}")

    if args.summary:
        for run in runs:
            c = run["counts"]
            print(f"summary {out_name(run['label'])}: " + " ".join(f"{k}={c[k]}" for k in CLASSES)
                  + f" idle_grains={int(run['idle'].sum())} unit={run['unit']:.17g}"
                  f" threshold={run['thr']:.17g}")

    written, failed = [], []
    jobs = [(plot, run) for run in runs for plot in (plot_forces, plot_nt, plot_theta)]
    for plot, run in jobs:
        try:
            plot(run, args, out_dir, written)
        except Exception as e:  # a figure that fails must not stop the others
            plt.close("all")
            failed.append(plot.__name__)
            note(f"{run['label']}: {plot.__name__} failed: {type(e).__name__}: {e}")
    if len(runs) > 1:
        try:
            plot_theta_all(runs, args, out_dir, written)
        except Exception as e:
            plt.close("all")
            failed.append("plot_theta_all")
            note(f"plot_theta_all failed: {type(e).__name__}: {e}")
    for path in written:
        print(path)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
