#!/usr/bin/python3
"""How much of x0, z* and x2 sits in the weakest contacts: the backbone counts of 3D packings
recomputed with the force-carrying threshold raised from granpack's 1e-4 a^2 P.

Usage:
  contact_threshold_scan.py [--thresholds T1,T2,...] FILE.h5... | --group LABEL FILE.h5... [--group ...]
e.g.
  contact_threshold_scan.py --group C out/ens/C/sample_*/C.h5 --group Z out/ens/Z/sample_*/Z.h5

A contact carries force when its elastic normal force N exceeds T a^2 P (a the diameter, P the
file's measured pressure; granpack analyze uses T = 1e-4, [AR] sec. III B's tolerance). Rattlers
follow [AR] sec. III B as in `granpack analyze` (docs/analysis.md): a grain with fewer than
4 (frictionless) or 2 (frictional) force-carrying contacts with non-rattlers is a rattler,
iterated to a fixed point. For each T: x0 (rattlers / n), z* (2 backbone contacts / non-rattlers)
and x2 (non-rattlers with 2 backbone contacts / n), mean +- sample sd over the files of a label.
At T = 1e-4 the numbers are granpack analyze's (tests/cli/python_reader.sh checks it).
"""
import argparse

import numpy as np

import granpack_io as gio

DEFAULT_THRESHOLDS = (1e-4, 1e-3, 1e-2, 2e-2, 3e-2)


def backbone_counts(packing, threshold):
    """(x0, z*, x2) of a 3D packing with the force-carrying threshold `threshold` a^2 P."""
    if packing.dimension != 3:
        raise gio.GranpackFileError(f"{packing.path}: a 3D packing is needed (dimension "
                                    f"{packing.dimension})")
    n = packing.n
    c = packing.contacts
    force = np.asarray(c["normal_force"], dtype=float)
    scale = float(np.mean(packing.diameter)) ** 2 * float(packing.pressure)
    carrying = force > threshold * scale
    i, j = packing.i[carrying], packing.j[carrying]
    min_contacts = 4 if packing.law()["friction"] == 0 else 2
    rattler = np.zeros(n, dtype=bool)
    while True:
        live = ~(rattler[i] | rattler[j])
        count = np.bincount(i[live], minlength=n) + np.bincount(j[live], minlength=n)
        new = ~rattler & (count < min_contacts)
        if not new.any():
            break
        rattler |= new
    backbone = n - int(rattler.sum())
    z_star = 2.0 * int(live.sum()) / backbone if backbone else float("nan")
    return rattler.mean(), z_star, np.mean(~rattler & (count == 2))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--thresholds", default=",".join(f"{t:g}" for t in DEFAULT_THRESHOLDS),
                    metavar="T1,T2,...", help="in units of a^2 P (default: %(default)s)")
    ap.add_argument("--group", nargs="+", action="append", default=[], metavar="LABEL FILE.h5",
                    help="a label and its configuration files (repeatable)")
    ap.add_argument("files", nargs="*", metavar="FILE.h5", help="files of one unlabelled group")
    args = ap.parse_args()
    groups = [(g[0], g[1:]) for g in args.group] + ([("all", args.files)] if args.files else [])
    if not groups:
        ap.error("no configuration files (FILE.h5... or --group LABEL FILE.h5...)")
    for label, files in groups:
        if not files:
            ap.error(f"--group {label}: no files")
    try:
        thresholds = [float(t) for t in args.thresholds.split(",")]
    except ValueError:
        ap.error(f"--thresholds: comma-separated numbers expected, got {args.thresholds!r}")
    if any(not t > 0 for t in thresholds):
        ap.error(f"--thresholds must all be > 0, got {args.thresholds!r}")
    for label, files in groups:
        try:
            rows = np.array([[backbone_counts(p, t) for t in thresholds]
                             for p in map(gio.read_packing, files)])
        except gio.GranpackFileError as err:
            gio.fail("contact_threshold_scan.py", str(err))
        print(f"{label}: K = {len(files)}")
        for t, col in zip(thresholds, rows.transpose(1, 0, 2)):
            mean = col.mean(axis=0)
            sd = col.std(axis=0, ddof=1) if len(files) > 1 else np.full(3, np.nan)
            print(f"  T = {t:.0e} a^2 P: x0 {100 * mean[0]:.2f} +- {100 * sd[0]:.2f} %, "
                  f"z* {mean[1]:.4f} +- {sd[1]:.4f}, x2 {100 * mean[2]:.2f} +- {100 * sd[2]:.2f} %")


if __name__ == "__main__":
    main()
