#!/usr/bin/python3
"""[AR] fig. 3: the bulk modulus of frictionless packings against the confining pressure, from
`granpack stiffness --json` output on the levels of a `pressure_steps` run.

Usage: /usr/bin/python3 jobs/tools/plot_fig3.py OUT.png LEVEL.json [LEVEL.json ...]

Plots the reduced modulus B / (E~^(2/3) P^(1/3)) (E~ = E / (1 - nu^2)) against P, log axis:
  - B from K = K(1) + K(2) (filled) and from K(1) alone (open), as computed;
  - eq. (30) with each level's own z, Phi and Z(5/3) (line with small markers);
  - eq. (30) frozen at the lowest pressure's z, Phi and Z(5/3) (dashed): what [AR] call "the
    sole knowledge of Phi_0, z ~ 6 at low pressure and Z(5/3)".
It prints the table of the plotted values on stdout. Files whose `bulk_modulus_eq30` is null
(not 3D Hertz monodisperse) or whose moduli are invalid are refused with the file's name.
"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import granpack_io as gio  # noqa: E402


def die(msg):
    print(f"plot_fig3.py: error: {msg}", file=sys.stderr)
    sys.exit(2)


def main():
    ap = argparse.ArgumentParser(prog="plot_fig3.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", help="the figure (.png)")
    ap.add_argument("levels", nargs="+", help="`granpack stiffness --json` files, one per level")
    args = ap.parse_args()
    rows = []
    for path in args.levels:
        try:
            j = gio.read_stiffness(path)
        except gio.GranpackFileError as e:
            die(str(e))
        for key in ("pressure", "bulk_modulus", "bulk_modulus_eq30", "bulk_modulus_reduced"):
            if j.get(key) is None:
                die(f"{path}: '{key}' is missing or null (a valid 3D Hertz stiffness result is needed)")
        scale = j["bulk_modulus_reduced"] / j["bulk_modulus"]  # 1 / (E~^(2/3) P^(1/3))
        rows.append({"file": path, "P": j["pressure"], "B": j["bulk_modulus_reduced"],
                     "B1": j["constitutive"]["bulk_modulus"] * scale, "eq30": j["bulk_modulus_eq30"] * scale,
                     "z": j["z"], "phi": j["phi"], "Z53": j["Z_5_3"]})
    rows.sort(key=lambda r: r["P"])
    low = rows[0]
    # Eq. (30) / (E~^(2/3) P^(1/3)) = (z Phi / 3 pi)^(2/3) / (2 Z(5/3)): frozen at the lowest level.
    frozen = low["eq30"]
    print("P (Pa)        phi      z       Z(5/3)  B/(E^2/3 P^1/3)  B1      eq.30 own  eq.30 frozen  B/eq.30")
    for r in rows:
        print(f"{r['P']:<13.5g} {r['phi']:.5f}  {r['z']:.4f}  {r['Z53']:.4f}  {r['B']:.5f}          "
              f"{r['B1']:.5f}  {r['eq30']:.5f}    {frozen:.5f}       {r['B'] / r['eq30']:.4f}")
    fig, ax = plt.subplots(figsize=(5.5, 4))
    p = [r["P"] for r in rows]
    ax.plot(p, [r["B"] for r in rows], "o", color="C0", label="computed, K(1) + K(2)")
    ax.plot(p, [r["B1"] for r in rows], "o", mfc="none", color="C0", label="computed, K(1) only")
    ax.plot(p, [r["eq30"] for r in rows], "-s", ms=3, color="C1", label="eq. (30), each level's z, Φ, Z(5/3)")
    ax.plot(p, [frozen] * len(p), "--", color="C2", label="eq. (30), lowest level's z, Φ, Z(5/3)")
    ax.set_xscale("log")
    ax.set_xlabel("P (Pa)")
    ax.set_ylabel(r"$B / (\tilde E^{2/3} P^{1/3})$")
    ax.set_title("frictionless glass beads ([AR] fig. 3)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(args.out)


if __name__ == "__main__":
    main()
