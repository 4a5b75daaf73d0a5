#!/usr/bin/python3
"""A time series for ParaView from configuration files already written (docs/visualisation.md):
one XDMF temporal collection whose steps are the XDMF sidecars of the given files, at their
simulated times, e.g. the levels of a `pressure_steps` stage or the files of `write` stages.

  /usr/bin/python3 jobs/tools/xdmf_series.py out/run/series.xdmf out/run/level_*.h5

Each FILE.h5 needs its sidecar FILE.xdmf (granpack writes it); the series references the HDF5
files relative to the series' directory, so keep them together. Files are ordered by their
`time` attribute; two files at the same time are refused (ParaView would show one of them).
Open the series with ParaView's "XDMF Reader" and play it. Bad input: exit 2, naming the file.
"""
import argparse
import os
import re
import xml.etree.ElementTree as ET

import granpack_io as gio

PROG = "xdmf_series.py"


def steps(paths, out_dir):
    """(time, [Grid elements]) of each file, its HDF5 references made relative to out_dir."""
    found = []
    for path in paths:
        try:
            p = gio.read_packing(path)
        except gio.GranpackFileError as e:
            gio.fail(PROG, e)
        sidecar = os.path.splitext(path)[0] + ".xdmf"
        if not os.path.isfile(sidecar):
            gio.fail(PROG, f"{path}: no sidecar {sidecar} (granpack writes it beside the file)")
        try:
            domain = ET.parse(sidecar).getroot().find("Domain")
        except ET.ParseError as e:
            gio.fail(PROG, f"{sidecar}: not XML ({e})")
        grids = [] if domain is None else list(domain.findall("Grid"))
        if not grids:
            gio.fail(PROG, f"{sidecar}: no Grid in its Domain")
        h5 = os.path.relpath(os.path.abspath(path), os.path.abspath(out_dir))
        for item in (e for g in grids for e in g.iter("DataItem")):
            item.text = re.sub(r"^[^:]*\.h5:", h5 + ":", item.text.strip())
        found.append((p.time, path, grids))
    found.sort(key=lambda t: t[0])
    for (t0, a, _), (t1, b, _) in zip(found, found[1:]):
        if t0 == t1:
            gio.fail(PROG, f"{a} and {b} have the same time {t0} s")
    return found


def main():
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("output", help="the series (.xdmf)")
    ap.add_argument("files", nargs="+", help="granpack configurations (.h5) with their sidecars")
    args = ap.parse_args()
    out_dir = os.path.dirname(os.path.abspath(args.output))
    root = ET.Element("Xdmf", Version="3.0")
    series = ET.SubElement(ET.SubElement(root, "Domain"), "Grid", Name="series",
                           GridType="Collection", CollectionType="Temporal")
    found = steps(args.files, out_dir)
    for time, _, grids in found:
        if len(grids) == 1:
            step = grids[0]
        else:
            step = ET.Element("Grid", Name="packing", GridType="Collection",
                              CollectionType="Spatial")
            step.extend(grids)
        for grid in step.iter("Grid"):  # one time per step, on the step itself
            for old in grid.findall("Time"):
                grid.remove(old)
        step.insert(0, ET.Element("Time", Value=repr(time)))
        series.append(step)
    ET.indent(root)
    with open(args.output, "w") as f:
        f.write('<?xml version="1.0" ?>\n' + ET.tostring(root, encoding="unicode") + "\n")
    print(f"{args.output}: {len(found)} steps, t = {found[0][0]:.6g} ... {found[-1][0]:.6g} s")


if __name__ == "__main__":
    main()
