#!/usr/bin/python3
"""Paired differences between two ensembles of the same seeds (a controlled experiment against
its base: the same melted gases or packings, one deck parameter changed).

Usage:
  paired_ensembles.py BASE.json:STEM OTHER.json:STEM KEY...
e.g.
  paired_ensembles.py docs/data/ensembles/experiments/D_QS_rerun/ensemble.json:D \
      docs/data/ensembles/experiments/D_no_walton/ensemble.json:D z_star M1 H_over_Nf

For each KEY (an analysis scalar of ensemble.json, e.g. z_star, phi, x0, x2, Z_2, M1, M2,
H_over_Nf) over the seeds both ensembles have: each seed's difference OTHER - BASE, their mean
and its standard error (sample sd / sqrt(K), ddof = 1).
"""
import argparse

import numpy as np

import granpack_io as gio


def per_seed(spec, key):
    """{seed: value of KEY} of the ensemble FILE:STEM; a clear error if any part is missing."""
    if ":" not in spec:
        gio.fail("paired_ensembles.py", f"{spec}: expected FILE:STEM, e.g. out/D/ensemble.json:D")
    path, stem = spec.rsplit(":", 1)
    try:
        e = gio.read_ensemble(path)
    except gio.GranpackFileError as err:
        gio.fail("paired_ensembles.py", str(err))
    block = e.get("analysis", {}).get(stem)
    if block is None:
        gio.fail("paired_ensembles.py", f"{path}: no configuration \"{stem}\" in \"analysis\" "
                 f"(it has: {', '.join(sorted(e.get('analysis', {})))})")
    entry = block.get("/" + key)
    if entry is None:
        gio.fail("paired_ensembles.py", f"{path}:{stem}: no scalar \"{key}\"")
    return dict(zip(e["seeds"], entry["values"]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("base", metavar="BASE.json:STEM")
    ap.add_argument("other", metavar="OTHER.json:STEM")
    ap.add_argument("keys", nargs="+", metavar="KEY")
    args = ap.parse_args()
    for key in args.keys:
        a, b = per_seed(args.base, key), per_seed(args.other, key)
        seeds = sorted(set(a) & set(b))
        d = np.array([b[k] - a[k] for k in seeds])
        se = d.std(ddof=1) / np.sqrt(len(d)) if len(d) > 1 else float("nan")
        print(f"{key}: seeds {seeds}: {' '.join(f'{x:+.4g}' for x in d)}; "
              f"mean {d.mean():+.4g} +- {se:.2g} (standard error)")


if __name__ == "__main__":
    main()
