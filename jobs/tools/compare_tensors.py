#!/usr/bin/env python3
"""Compare the elastic tensors of two `granpack stiffness --json` files (docs/stiffness.md,
"Moduli of large packings"): the reference (e.g. the direct path on A 4000) and another run
(e.g. the Krylov path on A 4000, or on its periodic replica A 32k or A 256k, whose tensor must
be the same). Prints, for c (K(1) + K(2)), c_affine and the K(1) tensor, the largest
|c_IJ - c_ref,IJ| / max |c_ref|; B and G_V of both with their relative difference; and, for a
Krylov run, each matrix's method, iterations, largest true residual and seconds.

  /usr/bin/python3 jobs/tools/compare_tensors.py REFERENCE.json OTHER.json [--tol 1e-6]

Exit status 1 if a tensor differs by more than --tol of max |c| (default 1e-6, issue 28's bar).
"""
import argparse

import numpy as np

import granpack_io as gio

TENSORS = (("c", lambda j: j["elastic_tensor"]["c"]),
           ("c_affine", lambda j: j["elastic_tensor"]["c_affine"]),
           ("K(1) c", lambda j: j["constitutive"]["elastic_tensor"]["c"]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("reference")
    ap.add_argument("other")
    ap.add_argument("--tol", type=float, default=1e-6)
    a = ap.parse_args()
    try:
        ref, got = gio.read_stiffness(a.reference), gio.read_stiffness(a.other)
    except gio.GranpackFileError as e:
        gio.fail("compare_tensors.py", e)
    print(f"reference: n = {ref['n']}, {ref['solver']['path']} path; "
          f"other: n = {got['n']}, {got['solver']['path']} path, moduli_valid {got['moduli_valid']}")
    worst = 0.0
    for name, get in TENSORS:
        c_ref, c = np.array(get(ref)), np.array(get(got))
        dev = np.abs(c - c_ref).max() / np.abs(c_ref).max()
        worst = max(worst, dev)
        print(f"{name}: max |dc| / max |c| = {dev:.3g}")
    for name, get in (("B", lambda j: j["bulk_modulus"]),
                      ("G_V", lambda j: j["elastic_tensor"]["shear_voigt"])):
        r, g = get(ref), get(got)
        print(f"{name}: {r:.8g} and {g:.8g}, relative difference {abs(g - r) / abs(r):.3g}")
    krylov = got["solver"].get("krylov")
    for matrix in ("K1", "K") if krylov else ():
        s = krylov[matrix]
        its = s["iterations"]
        print(f"{matrix}: {s['method']} + {s['preconditioner']}, iterations {min(its)}-{max(its)} "
              f"({len(its)} solves), max true residual {max(s['residuals']):.3g}, setup "
              f"{s['setup_seconds']:.1f} s, solves {s['solve_seconds']:.1f} s")
    return 0 if worst <= a.tol else 1


if __name__ == "__main__":
    raise SystemExit(main())
