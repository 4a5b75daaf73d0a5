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
import json

import numpy as np


def per_seed(spec, key):
    path, stem = spec.rsplit(":", 1)
    e = json.load(open(path))
    return dict(zip(e["seeds"], e["analysis"][stem]["/" + key]["values"]))


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
