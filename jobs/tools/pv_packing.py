"""Opens a granpack file's XDMF sidecar in ParaView (pvbatch), says what it holds, and renders
the force network: grains as spheres (2D: disks) scaled by their radius, contacts as tubes whose
width and colour follow the normal force (docs/visualisation.md).

  bash jobs/tools/with_xvfb.sh pvbatch jobs/tools/pv_packing.py out/main/final.xdmf --png chains.png
  bash jobs/tools/with_xvfb.sh pvbatch jobs/tools/pv_packing.py FILE.xdmf --summary summary.json

--summary writes, per grid of the file ("particles", "contacts"; of the first step of a time
series, jobs/tools/xdmf_series.py), its numbers of points and cells and its point and cell
arrays (name: number of components, range of the first), and the time steps, as ParaView read
them: what tests/cli/paraview.sh compares with the HDF5 file. --png renders
offscreen (Debian's ParaView draws through X: run it on a virtual X server, with_xvfb.sh). Bad input: exit 2 with a
message naming the file.
"""
import argparse
import json
import os
import sys

from paraview import servermanager
from paraview.simple import (ColorBy, ExtractBlock, GetActiveViewOrCreate, GetColorTransferFunction,
                             Render, ResetCamera, SaveScreenshot, Show, Threshold, Tube,
                             XDMFReader, CellDatatoPointData, ExtractSurface, Calculator)

PROG = "pv_packing.py"


def die(msg):
    print(f"{PROG}: error: {msg}", file=sys.stderr)
    sys.exit(2)


def blocks(data, name="particles"):
    """(name, dataset) of each leaf of a fetched composite dataset (multiblock, maybe of multipiece
    blocks), or the dataset itself."""
    if data.IsA("vtkMultiPieceDataSet"):
        pieces = [data.GetPiece(k) for k in range(data.GetNumberOfPieces())]
        return [(name, p) for p in pieces if p is not None][:1]
    if not data.IsA("vtkMultiBlockDataSet"):
        return [(name, data)]
    out = []
    for k in range(data.GetNumberOfBlocks()):
        meta = data.GetMetaData(k)
        label = meta.Get(data.NAME()) if meta is not None and meta.Has(data.NAME()) else str(k)
        block = data.GetBlock(k)
        if block is not None:
            out.extend(blocks(block, label))
    return out


def arrays(fields):
    out = {}
    for k in range(fields.GetNumberOfArrays()):
        a = fields.GetArray(k)
        if a is not None:
            out[a.GetName()] = {"components": a.GetNumberOfComponents(),
                                "range": list(a.GetRange(0)) if a.GetNumberOfTuples() else None}
    return out


def mean_compressive_force(reader):
    """<N> over the contacts with N > 0 (0 if none)."""
    from vtk.numpy_interface import dataset_adapter as dsa
    for name, b in blocks(servermanager.Fetch(reader)):
        if name == "contacts" and b.GetNumberOfCells():
            n = dsa.WrapDataObject(b).CellData["normal_force"]
            n = n[n > 0]
            return float(n.mean()) if len(n) else 0.0
    return 0.0


def summary(reader):
    data = servermanager.Fetch(reader)
    return {name: {"points": b.GetNumberOfPoints(), "cells": b.GetNumberOfCells(),
                   "point_arrays": arrays(b.GetPointData()), "cell_arrays": arrays(b.GetCellData()),
                   "bounds": list(b.GetBounds())}
            for name, b in blocks(data)}


def threshold(source, array, lo, hi, points=False):
    """Cells of `source` with lo <= array <= hi (points: every point of the cell must be)."""
    t = Threshold(Input=source, Scalars=["POINTS" if points else "CELLS", array])
    if hasattr(t, "LowerThreshold"):
        t.LowerThreshold, t.UpperThreshold = lo, hi
        if hasattr(t, "ThresholdMethod"):
            t.ThresholdMethod = "Between"
    else:
        t.ThresholdRange = [lo, hi]
    if points and hasattr(t, "AllScalars"):
        t.AllScalars = 1
    return t


def slab(source, info, fraction):
    """The part of `source` within the middle `fraction` of the cell along z (3D)."""
    if fraction >= 1:
        return source
    z0, z1 = info["particles"]["bounds"][4:6]
    mid, half = 0.5 * (z0 + z1), 0.5 * fraction * (z1 - z0)
    z = Calculator(Input=source, ResultArrayName="z_coordinate", Function="coordsZ")
    return threshold(z, "z_coordinate", mid - half, mid + half, points=True)


def colour_grains(g, info, array):
    """Colours the grains by a point array: cluster_id by one flat colour per cluster,
    anything else by a sequential map over its range
    (a tensor or vector by its magnitude)."""
    arrays_ = info["particles"]["point_arrays"]
    if array not in arrays_:
        die(f"--colour {array}: the file's grains have no such array (they have {', '.join(sorted(arrays_))})")
    components = arrays_[array]["components"]
    ColorBy(g, ("POINTS", array) if components == 1 else ("POINTS", array, "Magnitude"))
    lut = GetColorTransferFunction(array)
    lo, hi = arrays_[array]["range"]
    if array == "cluster_id":
        lut.ApplyPreset("Rainbow Uniform", True)
        lut.Discretize = 1  # one flat colour per cluster id
        lut.NumberOfTableValues = max(int(hi - lo) + 1, 2)
        lut.RescaleTransferFunction(lo, max(hi, lo + 1))
    else:
        lut.ApplyPreset("Viridis (matplotlib)", True)
        if components == 1:
            lut.RescaleTransferFunction(lo, max(hi, lo + 1e-300))
    g.LookupTable = lut


def render(reader, info, png, size, dimension, strong, slab_fraction, colour=None,
           no_contacts=False):
    view = white_view(size)
    cut = slab_fraction if dimension == 3 else 1.0
    grains = slab(ExtractBlock(Input=reader, Selectors=["/Root/particles"]), info, cut)
    g = show_grains(grains, view, dimension)
    g.ColorArrayName = [None, ""]
    g.AmbientColor = g.DiffuseColor = [0.82, 0.82, 0.82]
    if colour:
        colour_grains(g, info, colour)
    g.Opacity = 1.0 if dimension == 2 else 0.2 if cut < 1 else 0.35
    if "contacts" in info and info["contacts"]["cells"] > 0 and not no_contacts:
        contacts = slab(ExtractBlock(Input=reader, Selectors=["/Root/contacts"]), info, cut)
        fmin, fmax = info["contacts"]["cell_arrays"]["normal_force"]["range"]
        radius = info["particles"]["point_arrays"]["radius"]["range"][1]
        if fmin < 0:  # tensile (cohesive) contacts and distant pairs: thin green lines
            tensile = threshold(contacts, "normal_force", fmin, 0.0)
            t = Show(tensile, view)
            t.ColorArrayName = [None, ""]
            t.AmbientColor = t.DiffuseColor = [0.17, 0.63, 0.17]
            t.LineWidth = 2.0
        # Compressive contacts (only those above <N> with `strong`, [AR]'s strong network)
        # as tubes whose width and colour grow with N. Tube needs polygonal data with point
        # values: each contact has its own two points, so a point's value is its contact's.
        lo = max(strong * info["mean_compressive_force"], 0.0)
        compressive = threshold(contacts, "normal_force", lo, max(fmax, 1e-300))
        points = ExtractSurface(Input=CellDatatoPointData(Input=compressive))
        tubes = Tube(Input=points, Scalars=["POINTS", "normal_force"], VaryRadius="By Scalar",
                     Radius=0.06 * radius, RadiusFactor=8.0, NumberofSides=8)
        t = Show(tubes, view)
        t.ColorArrayName = ["POINTS", "normal_force"]
        lut = GetColorTransferFunction("normal_force")
        lut.ApplyPreset("Inferno (matplotlib)", True)
        lut.RescaleTransferFunction(0.0, max(fmax, 1e-300))
        lut.InvertTransferFunction()
    save_view(view, png, size, dimension, cut, zoom_2d=1.3)


def show_grains(source, view, dimension):
    """Shows the points of `source` as spheres (2D: disks) of their `radius` array; returns the
    display (pv_modes.py draws its grains with it too)."""
    g = Show(source, view)
    g.SetRepresentationType("Point Gaussian")
    g.ShaderPreset = "Sphere" if dimension == 3 else "Plain circle"
    g.ScaleByArray = 1
    g.SetScaleArray = ["POINTS", "radius"]
    if hasattr(g, "UseScaleFunction"):
        g.UseScaleFunction = 0
    g.GaussianRadius = 1.0
    return g


def white_view(size):
    """The render view, white, without axes (pv_modes.py draws in the same)."""
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = size
    view.OrientationAxesVisibility = 0
    view.Background = [1, 1, 1]
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    return view


def save_view(view, png, size, dimension, cut, zoom_2d):
    """Frames the scene (2D face on; a 3D slab face on down z, the whole 3D cell from above at
    an angle) and writes the PNG."""
    if dimension == 2:
        view.InteractionMode = "2D"
    ResetCamera(view)
    if dimension == 3 and cut >= 1:
        cam = view.GetActiveCamera()
        cam.Elevation(25)
        cam.Azimuth(30)
        ResetCamera(view)
    view.GetActiveCamera().Zoom(zoom_2d if dimension == 2 else 1.1)
    Render(view)
    SaveScreenshot(png, view, ImageResolution=size)


def main():
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("xdmf", help="the XDMF sidecar of a granpack file (FILE.xdmf)")
    ap.add_argument("--summary", help="write what ParaView read (JSON) here")
    ap.add_argument("--png", help="render the force network into this PNG")
    ap.add_argument("--size", type=int, nargs=2, default=[800, 800], metavar=("W", "H"))
    ap.add_argument("--strong", type=float, default=0.0, metavar="X",
                    help="draw the compressive contacts with N > X <N> only (1: [AR]'s strong network)")
    ap.add_argument("--slab", type=float, default=1.0, metavar="FRACTION",
                    help="3D: draw only the middle FRACTION of the cell along z")
    ap.add_argument("--colour", metavar="ARRAY",
                    help="colour the grains by this point array (e.g. cluster_id, mean_stress, "
                         "bond_order; default grey)")
    ap.add_argument("--no-contacts", action="store_true", help="draw the grains only")
    args = ap.parse_args()
    if not os.path.isfile(args.xdmf):
        die(f"{args.xdmf}: no such file")
    reader = XDMFReader(FileNames=[args.xdmf])
    reader.UpdatePipeline()
    info = summary(reader)
    if "particles" not in info or info["particles"]["points"] == 0:
        die(f"{args.xdmf}: ParaView read no grains from it")
    dimension = 2 if "XY\"" in open(args.xdmf).read() else 3
    if args.summary:
        with open(args.summary, "w") as f:
            json.dump({"file": args.xdmf, "dimension": dimension, "grids": info,
                       "times": [float(t) for t in reader.TimestepValues]}, f, indent=1)
    if args.png:
        info["mean_compressive_force"] = mean_compressive_force(reader)
        render(reader, info, args.png, args.size, dimension, args.strong, args.slab, args.colour,
               args.no_contacts)
        print(args.png)


if __name__ == "__main__":
    main()
