"""Opens the modes file of `granpack stiffness --modes K --modes-file MODES.h5` (its XDMF
sidecar) in ParaView (pvbatch), says what it holds, and renders one mode as arrows on the grains
(docs/visualisation.md, docs/stiffness.md "Modes as fields").

  bash jobs/tools/with_xvfb.sh pvbatch jobs/tools/pv_modes.py MODES.xdmf --summary modes.json
  bash jobs/tools/with_xvfb.sh pvbatch jobs/tools/pv_modes.py MODES.xdmf --mode 0 --png mode0.png

--summary writes what ParaView read, as jobs/tools/pv_packing.py does for packings: the grid
"grains" with its points, cells and point arrays (radius, id, backbone, mode_k and, with
friction, mode_k_rotation; name: number of components, range of the first component), and
`magnitude_range`: per displacement array the range of |u| as ParaView computes it. --png draws
the grains as disks (3D: spheres, the middle --slab of the cell along z) coloured by |u| of
--mode, and an arrow on each grain whose |u| is above --above of the largest, scaled so that the
largest arrow is two mean radii long: a mode is a shape, its amplitude is arbitrary (unit norm
over the backbone). Bad input (a missing file, a file without modes, a mode it does not hold):
exit 2 with a message naming it.
"""
import argparse
import json
import os
import re
import sys

# ParaView is imported after the arguments and the file are checked (paraview_api()): a refusal
# then costs no pvbatch start, and plain python3 can give it.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

PROG = "pv_modes.py"


def die(msg):
    print(f"{PROG}: error: {msg}", file=sys.stderr)
    sys.exit(2)


def paraview_api():
    """Imports ParaView's modules (pvbatch only) into this module's namespace."""
    from paraview import servermanager
    from paraview.simple import Calculator, ColorBy, GetColorTransferFunction, Glyph, Show, XDMFReader
    from pv_packing import (arrays, blocks, save_view, show_grains, slab, threshold,
                            white_view)
    globals().update(locals())


def grains(reader):
    """The one grid of a modes file as ParaView fetched it."""
    found = blocks(servermanager.Fetch(reader), "grains")
    return found[0][1] if found else None


def magnitude_range(data, name):
    from vtk.numpy_interface import dataset_adapter as dsa
    import numpy as np
    u = np.asarray(dsa.WrapDataObject(data).PointData[name])
    m = np.linalg.norm(u.reshape(len(u), -1), axis=1)
    return [float(m.min()), float(m.max())]


def summary(data):
    point_arrays = arrays(data.GetPointData())
    modes = sorted(k for k in point_arrays if k.startswith("mode_") and not k.endswith("_rotation"))
    return {"grains": {"points": data.GetNumberOfPoints(), "cells": data.GetNumberOfCells(),
                       "point_arrays": point_arrays, "bounds": list(data.GetBounds())},
            "modes": modes,
            "magnitude_range": {k: magnitude_range(data, k) for k in modes}}


def render(reader, info, mode, png, size, dimension, slab_fraction, above):
    name = f"mode_{mode}"
    view = white_view(size)
    cut = slab_fraction if dimension == 3 else 1.0
    # slab() reads the z range of info["particles"]: the modes file calls its grid "grains".
    shown = slab(reader, {"particles": info["grains"]}, cut)
    umax = max(info["magnitude_range"][name][1], 1e-300)
    lut = GetColorTransferFunction(name)
    lut.ApplyPreset("Blues", True)
    lut.InvertTransferFunction()  # ParaView's "Blues" runs dark to light: at rest = light
    lut.RescaleTransferFunction(0.0, umax)
    r = info["grains"]["point_arrays"]["radius"]["range"]
    # The grains that move, |u| > above * max|u|, coloured by |u| with an arrow each (the
    # largest two mean radii long); in 3D the others are faint, so that the moving ones show
    # through the slab.
    amplitude = Calculator(Input=shown, ResultArrayName="amplitude", Function=f"mag({name})")
    moving = threshold(amplitude, "amplitude", above * umax, umax, points=True)
    for source, opacity in ((shown, 1.0 if dimension == 2 else 0.08), (moving, 1.0)):
        g = show_grains(source, view, dimension)
        ColorBy(g, ("POINTS", name, "Magnitude"))
        g.LookupTable = lut
        g.Opacity = opacity
        if dimension == 2:
            break  # every grain is drawn opaque already
    arrows = Glyph(Input=moving, GlyphType="Arrow", OrientationArray=["POINTS", name],
                   ScaleArray=["POINTS", name], ScaleFactor=(r[0] + r[1]) / umax,
                   GlyphMode="All Points")
    a = Show(arrows, view)
    a.ColorArrayName = [None, ""]
    a.AmbientColor = a.DiffuseColor = [0.85, 0.2, 0.0]
    save_view(view, png, size, dimension, cut, zoom_2d=1.0)


def main():
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("xdmf", help="the XDMF sidecar of a modes file (MODES.xdmf)")
    ap.add_argument("--summary", help="write what ParaView read (JSON) here")
    ap.add_argument("--png", help="render --mode into this PNG")
    ap.add_argument("--mode", type=int, default=0, help="which mode to draw (0 = the softest)")
    ap.add_argument("--size", type=int, nargs=2, default=[800, 800], metavar=("W", "H"))
    ap.add_argument("--slab", type=float, default=1.0, metavar="FRACTION",
                    help="3D: draw only the middle FRACTION of the cell along z")
    ap.add_argument("--above", type=float, default=0.1, metavar="X",
                    help="arrows only on grains with |u| > X max|u| (default 0.1)")
    args = ap.parse_args()
    if not os.path.isfile(args.xdmf):
        die(f"{args.xdmf}: no such file")
    text = open(args.xdmf, errors="replace").read()
    held = sorted({int(k) for k in re.findall(r'Name="mode_(\d+)"', text)})
    if not held:
        die(f"{args.xdmf}: holds no mode_k arrays (is it a modes file of granpack stiffness --modes?)")
    if args.png and args.mode not in held:
        die(f"{args.xdmf}: --mode {args.mode}: the file holds modes {held[0]} to {held[-1]}")
    paraview_api()
    reader = XDMFReader(FileNames=[args.xdmf])
    reader.UpdatePipeline()
    data = grains(reader)
    if data is None or data.GetNumberOfPoints() == 0:
        die(f"{args.xdmf}: ParaView read no grains from it")
    info = summary(data)
    if not info["modes"]:
        die(f"{args.xdmf}: holds no mode_k arrays (is it a modes file of granpack stiffness --modes?)")
    dimension = 2 if "XY\"" in text else 3
    if args.summary:
        with open(args.summary, "w") as f:
            json.dump({"file": args.xdmf, "dimension": dimension, **info}, f, indent=1)
    if args.png:
        render(reader, info, args.mode, args.png, args.size, dimension, args.slab, args.above)
        print(args.png)


if __name__ == "__main__":
    main()
