#!/usr/bin/python3
"""How much of x0, z* and x2 sits in the weakest contacts: the backbone counts of packings
recounted by `granpack analyze --threshold T` with the force-carrying threshold raised from 1e-4.

Usage:
  contact_threshold_scan.py [--thresholds T1,T2,...] [--granpack EXE] FILE.h5...
  contact_threshold_scan.py ... --group LABEL FILE.h5... [--group LABEL FILE.h5...]
e.g.
  contact_threshold_scan.py --group C out/ens/C/sample_*/C.h5 --group Z out/ens/Z/sample_*/Z.h5

A contact carries force when its elastic normal force N exceeds T a^2 P (a the diameter, P the
file's measured pressure; T = 1e-4 is [AR] sec. III B's tolerance and analyze's default). The
counting is analyze's own (docs/analysis.md: the iterated rattler rule of [AR] sec. III B); this
tool only runs it once per file and threshold and tabulates, for each T, x0 (rattlers / n), z*
(2 backbone contacts / non-rattlers) and x2 (non-rattlers with 2 backbone contacts / n) as
mean +- sample sd over the files of a label.
"""
import argparse
import os
import subprocess
import tempfile

import numpy as np

import granpack_io as gio

DEFAULT_THRESHOLDS = (1e-4, 1e-3, 1e-2, 2e-2, 3e-2)
PROG = "contact_threshold_scan.py"


def default_granpack():
    """$GRANPACK_EXE, else the build directory of this checkout."""
    here = os.path.dirname(os.path.abspath(__file__))
    return os.environ.get("GRANPACK_EXE") or os.path.join(here, "..", "..", "build", "granpack")


def backbone_counts(path, threshold, granpack):
    """(x0, z*, x2) of the packing in `path` as `granpack analyze --threshold` counts them."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "analysis.json")
        run = subprocess.run([granpack, "analyze", path, "--threshold", repr(threshold),
                              "--json", out], capture_output=True, text=True)
        if run.returncode != 0:
            raise gio.GranpackFileError(f"{granpack} analyze {path} --threshold {threshold} "
                                        f"failed (exit {run.returncode}): {run.stderr.strip()}")
        a = gio.read_analysis(out, arrays=False)
    return a["x0"], a["z_star"], a["x2"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--thresholds", default=",".join(f"{t:g}" for t in DEFAULT_THRESHOLDS),
                    metavar="T1,T2,...", help="in units of a^2 P, each in (0, 1] "
                    "(default: %(default)s)")
    ap.add_argument("--granpack", default=default_granpack(), metavar="EXE",
                    help="the granpack executable (default: $GRANPACK_EXE, else build/granpack)")
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
    if any(not 0 < t <= 1 for t in thresholds):
        ap.error(f"--thresholds must all be in (0, 1], got {args.thresholds!r}")
    if not os.access(args.granpack, os.X_OK):
        ap.error(f"--granpack: no executable at {args.granpack} (build first, or pass --granpack)")
    for label, files in groups:
        try:
            rows = np.array([[backbone_counts(f, t, args.granpack) for t in thresholds]
                             for f in files])
        except gio.GranpackFileError as err:
            gio.fail(PROG, str(err))
        print(f"{label}: K = {len(files)}")
        for t, col in zip(thresholds, rows.transpose(1, 0, 2)):
            mean = col.mean(axis=0)
            sd = col.std(axis=0, ddof=1) if len(files) > 1 else np.full(3, np.nan)
            print(f"  T = {t:.0e} a^2 P: x0 {100 * mean[0]:.2f} +- {100 * sd[0]:.2f} %, "
                  f"z* {mean[1]:.4f} +- {sd[1]:.4f}, x2 {100 * mean[2]:.2f} +- {100 * sd[2]:.2f} %")


if __name__ == "__main__":
    main()
