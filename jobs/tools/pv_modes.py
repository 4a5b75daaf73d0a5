"""Opens the modes file of `granpack stiffness --modes K --modes-file MODES.h5` (its XDMF
sidecar) in ParaView (pvbatch), says what it holds, and renders one mode as arrows on the grains
(docs/visualisation.md, docs/stiffness.md "Modes as fields").

  bash jobs/tools/with_xvfb.sh pvbatch jobs/tools/pv_modes.py MODES.xdmf --summary modes.json
  bash jobs/tools/with_xvfb.sh pvbatch jobs/tools/pv_modes.py MODES.xdmf --mode 0 --png mode0.png
  bash jobs/tools/with_xvfb.sh pvbatch jobs/tools/pv_modes.py MODES.xdmf --mode divalent \
      --grain ID --packing FINAL.h5 --png rolling.png

--summary writes what ParaView read, as jobs/tools/pv_packing.py does for packings: the grid
"grains" with its points, cells and point arrays (radius, id, backbone, divalent, mode_k and,
with friction, mode_k_rotation, and with divalent grains divalent_rolling and
divalent_rolling_rotation; name: number of components, range of the first component), and
`magnitude_range`: per displacement array the range of |u| as ParaView computes it. --png draws
the grains as disks (3D: spheres, the middle --slab of the cell along z) coloured by |u| of
--mode, and an arrow on each grain whose |u| is above --above of the largest, scaled so that the
largest arrow is two mean radii long: a mode is a shape, its amplitude is arbitrary (unit norm
over the backbone). --mode divalent draws instead the divalent grains' free rollings (the array
divalent_rolling, 3D with friction: each divalent grain rolls about the line through its two
contact points, the other grains at rest).

--grain ID (3D, with --png) zooms onto one grain: the grain (orange, translucent), its contact
partners (grey: a divalent grain's two, which the modes file names; for another grain those it
touches with a force, from --packing) and, faint, the grains within --around mean diameters
(nearest periodic image; with --packing only those touching the grain or a partner); the
contacts of the grain (dark) and of its partners (light), from --packing, the configuration
the modes were computed from (without it only a divalent grain's two contacts); and the motion
as arrows: the velocities u + theta x r of 12 points r of the grain's surface on the great
circle across its rotation axis (red, to scale among themselves), the direction of its
centre's displacement u (orange) and its rotation theta (blue, right-hand rule). For a divalent
grain the rolling axis through its two contact points (black dots) is drawn in blue, theta on
it: the grain turns about that line, its contact points at rest. --azimuth and --elevation turn
the camera. --summary then also writes `zoom`: the grain, the ids of the grains drawn, the
partners, the number of faint grains, the contacts drawn (the grain's own by ids), the arrows
(points each Glyph was given, and the points of its output), the contact points.

Bad input (a missing file, a file without modes, a mode it does not hold, a grain it does not
hold, --mode divalent --grain on a grain that is not divalent): exit 2 with a message naming
it.
"""
import argparse
import json
import os
import re
import sys

import numpy as np

# ParaView is imported after the arguments and the file are checked (paraview_api()): a refusal
# then costs no pvbatch start, and plain python3 can give it.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import granpack_io as gio  # noqa: E402

PROG = "pv_modes.py"
DIVALENT = "divalent_rolling"
# --grain's view: the camera TILT degrees from the direction of the centre seen from the rolling
# axis towards the axis, DIST radii away; the fastest surface arrow SCALE radii long.
TILT, DIST, SCALE = 40.0, 11.0, 0.8


def die(msg):
    print(f"{PROG}: error: {msg}", file=sys.stderr)
    sys.exit(2)


def paraview_api():
    """Imports ParaView's modules (pvbatch only) into this module's namespace."""
    from paraview import servermanager
    from paraview.simple import (Calculator, ColorBy, GetColorTransferFunction, Glyph, Render,
                                 SaveScreenshot, Show, TrivialProducer, Tube, XDMFReader)
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
    if DIVALENT in point_arrays:
        modes.append(DIVALENT)
    return {"grains": {"points": data.GetNumberOfPoints(), "cells": data.GetNumberOfCells(),
                       "point_arrays": point_arrays, "bounds": list(data.GetBounds())},
            "modes": modes,
            "magnitude_range": {k: magnitude_range(data, k) for k in modes}}


def render(reader, info, name, png, size, dimension, slab_fraction, above):
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


# --- --grain: one grain's motion, zoomed -------------------------------------------------------

def h5_of(xdmf, text):
    """The modes file a sidecar references (its datasets' file, relative to the sidecar)."""
    found = re.search(r'Format="HDF">([^<:]+):', text)
    if not found:
        die(f"{xdmf}: references no HDF5 file")
    return os.path.join(os.path.dirname(os.path.abspath(xdmf)), found.group(1))


def field(modes, name):
    """u (n, 3) and theta (n, 3) of mode `name` (mode_k or divalent_rolling), 3D files."""
    if name == DIVALENT:
        d = modes["divalent_grains"]
        return d["displacement"], d["rotation"]
    k = int(name[len("mode_"):])
    rot = modes["rotation"]
    return modes["displacement"][k], (np.zeros_like(modes["displacement"][k]) if rot is None
                                      else rot[k])


def zoom_scene(modes, packing, grain, name, around, ring=12):
    """What --grain draws, in numpy (no ParaView): the grain `grain`, its partners (a divalent
    grain's two, from the modes file; else, with `packing`, the grains it touches with N^e > 0)
    and, with `packing` (a gio.Packing of the same grains), the grains that touch one of them,
    or without it every grain, within `around` mean diameters (unwrapped to the image nearest
    the grain); the contacts with N^e > 0 of the grain and its partners among them; the
    grain's displacement u and rotation theta in mode `name`, for a divalent grain its two
    contact points, and the velocities u + theta x r of `ring` points r of its surface on the
    great circle across its rotation axis. Refuses (die) a grain the file does not hold, and
    with --mode divalent a grain that is not divalent."""
    ids = modes["id"]
    rows = np.flatnonzero(ids == grain)
    if len(rows) != 1:
        die(f"--grain {grain}: the modes file holds no grain of that id (ids {ids.min()} to {ids.max()})")
    g = int(rows[0])
    L = modes["cell_length"]
    if L is None:
        die("--grain: the modes file has no /cell_length (written by an older granpack: run "
            "granpack stiffness --modes again)")
    div = modes["divalent_grains"]
    points = None
    partners = np.zeros(0, dtype=np.int64)
    if name == DIVALENT:
        k = np.flatnonzero(div["grain"] == grain) if div is not None else []
        if len(k) != 1:
            some = [] if div is None else div["grain"][:5].tolist()
            die(f"--grain {grain}: not a divalent grain of the file (it has "
                f"{0 if div is None else len(div['grain'])} divalent grains"
                + (f", e.g. {some})" if some else ")"))
        partners = div["neighbours"][k[0]]
    c = modes["position"][g]
    d = modes["position"] - c
    d -= L * np.round(d / L)
    radius = modes["radius"]
    close = np.linalg.norm(d, axis=1) <= around * 2.0 * radius.mean()
    pairs = []  # (id, id) of the contacts with N^e > 0 of the grain and its partners
    if packing is not None:
        if packing.n != len(ids) or not np.array_equal(np.sort(packing.grains["id"]), ids):
            die(f"--packing {packing.path}: not the grains of the modes file "
                f"({packing.n} grains against {len(ids)})")
        pid = packing.grains["id"].astype(np.int64)
        keep = ~packing.distant & (packing.contacts["normal_force"] > 0)
        a, b = pid[packing.i][keep], pid[packing.j][keep]
        if name != DIVALENT:
            mine = (a == grain) | (b == grain)
            partners = np.unique(np.where(a[mine] == grain, b[mine], a[mine]))
        hub = np.append(partners, grain)
        on = np.isin(a, hub) | np.isin(b, hub)
        pairs = list(zip(a[on].tolist(), b[on].tolist()))
        close &= np.isin(ids, [x for pair in pairs for x in pair] + [grain])
    elif name == DIVALENT:
        pairs = [(grain, int(q)) for q in partners]
    near = np.flatnonzero(close | np.isin(ids, partners))
    at = {int(i): r for r, i in enumerate(ids[near])}
    contacts = [(at[x], at[y], grain in (x, y)) for x, y in pairs if x in at and y in at]
    u_all, theta_all = field(modes, name)
    u, theta = u_all[g], theta_all[g]
    if name == DIVALENT:
        points = c + div["contact_points"][k[0]]  # in the order of the partners
    # The surface points shown: the great circle across the rotation axis (for a divalent grain
    # through the direction from the axis to the centre, f).
    t_norm = np.linalg.norm(theta)
    a = theta / t_norm if t_norm > 0 else np.array([0.0, 0.0, 1.0])
    if points is not None:
        f = -(points[0] - c)
    else:
        f = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    f = f - a * (a @ f)
    f /= np.linalg.norm(f)
    t = np.cross(a, f)
    phi = 2 * np.pi * (np.arange(ring) + 0.5) / ring
    r = radius[g] * (np.cos(phi)[:, None] * f + np.sin(phi)[:, None] * t)
    return {"grain": grain, "centre": c, "radius": radius[g], "mean_radius": radius.mean(),
            "ids": ids[near], "positions": c + d[near], "radii": radius[near],
            "partners": np.asarray(partners, dtype=np.int64), "contacts": contacts,
            "u": u, "theta": theta, "contact_points": points, "axis": a, "f": f, "t": t,
            "ring": c + r, "ring_velocity": u + np.cross(theta, r)}


def vtk_points(xyz, arrays=None, lines=None):
    """A vtkPolyData of points (one vertex each, or the given lines) with point arrays."""
    import vtk
    from vtkmodules.util import numpy_support
    pd = vtk.vtkPolyData()
    pts = vtk.vtkPoints()
    pts.SetData(numpy_support.numpy_to_vtk(np.ascontiguousarray(xyz, dtype=float), deep=1))
    pd.SetPoints(pts)
    cells = vtk.vtkCellArray()
    for k in range(len(xyz)) if lines is None else []:
        cells.InsertNextCell(1)
        cells.InsertCellPoint(k)
    for a, b in lines or []:
        cells.InsertNextCell(2)
        cells.InsertCellPoint(a)
        cells.InsertCellPoint(b)
    if lines is None:
        pd.SetVerts(cells)
    else:
        pd.SetLines(cells)
    for key, v in (arrays or {}).items():
        arr = numpy_support.numpy_to_vtk(np.ascontiguousarray(v, dtype=float), deep=1)
        arr.SetName(key)
        pd.GetPointData().AddArray(arr)
    return pd


def producer(pd):
    src = TrivialProducer()
    src.GetClientSideObject().SetOutput(pd)
    src.UpdatePipeline()
    return src


def coloured(display, rgb, opacity=1.0):
    display.ColorArrayName = [None, ""]
    display.AmbientColor = display.DiffuseColor = rgb
    display.Opacity = opacity
    return display


def render_zoom(scene, png, size, azimuth, elevation):
    """Draws zoom_scene()'s `scene`; returns what ParaView holds (the `zoom` of --summary)."""
    view = white_view(size)
    ids, pos, radii = scene["ids"], scene["positions"], scene["radii"]
    rm = scene["mean_radius"]
    role = np.where(ids == scene["grain"], 0, np.where(np.isin(ids, scene["partners"]), 1, 2))
    held = {}
    for which, rgb, opacity in ((2, [0.8, 0.8, 0.8], 0.07), (1, [0.55, 0.55, 0.58], 0.5),
                                (0, [0.98, 0.75, 0.35], 0.45)):
        sel = role == which
        if not sel.any():
            continue
        src = producer(vtk_points(pos[sel], {"radius": radii[sel], "id": ids[sel]}))
        coloured(show_grains(src, view, 3), rgb, opacity)
        held[which] = servermanager.Fetch(src)
    own = [(a, b) for a, b, mine in scene["contacts"] if mine]
    other = [(a, b) for a, b, mine in scene["contacts"] if not mine]
    for lines, width, rgb in ((other, 0.03, [0.7, 0.7, 0.7]), (own, 0.045, [0.2, 0.2, 0.2])):
        if lines:
            tube = Tube(Input=producer(vtk_points(pos, lines=lines)), Radius=width * rm,
                        NumberofSides=12)
            coloured(Show(tube, view), rgb)
    c, R, a = scene["centre"], scene["radius"], scene["axis"]
    if scene["contact_points"] is not None:
        p = scene["contact_points"]
        ends = np.array([p[0] - 0.8 * R * a * np.sign(a @ (p[1] - p[0])),
                         p[1] + 0.8 * R * a * np.sign(a @ (p[1] - p[0]))])
        axis = Tube(Input=producer(vtk_points(ends, lines=[(0, 1)])), Radius=0.06 * rm,
                    NumberofSides=12)
        coloured(Show(axis, view), [0.15, 0.3, 0.8])
        dots = producer(vtk_points(p, {"radius": np.full(2, 0.13 * rm)}))
        coloured(show_grains(dots, view, 3), [0.0, 0.0, 0.0])
        base = 0.5 * (p[0] + p[1])
    else:
        base = c
    # Arrows: the surface velocities to scale, the largest SCALE R long; u 0.9 R and theta 1.2 R
    # long (their directions: u is small when the axis passes near the centre).
    vmax = max(np.linalg.norm(scene["ring_velocity"], axis=1).max(), 1e-300)
    glyphs = {}
    for key, at, vec, rgb, scale in (
            ("u", c[None], scene["u"][None], [0.95, 0.45, 0.0],
             0.9 * R / max(np.linalg.norm(scene["u"]), 1e-300)),
            ("surface", scene["ring"], scene["ring_velocity"], [0.8, 0.1, 0.1], SCALE * R / vmax),
            ("theta", base[None], scene["theta"][None], [0.15, 0.3, 0.8],
             1.2 * R / max(np.linalg.norm(scene["theta"]), 1e-300))):
        if np.linalg.norm(vec, axis=1).max() <= 0:
            continue
        src = producer(vtk_points(at, {"vector": vec}))
        g = Glyph(Input=src, GlyphType="Arrow", OrientationArray=["POINTS", "vector"],
                  ScaleArray=["POINTS", "vector"], ScaleFactor=scale, GlyphMode="All Points")
        g.GlyphType.TipRadius, g.GlyphType.ShaftRadius = 0.12, 0.045
        coloured(Show(g, view), rgb)
        # Arrows drawn: the points Glyph placed one on (each arrow is a polydata of its own).
        glyphs[key] = [servermanager.Fetch(src).GetNumberOfPoints(),
                       servermanager.Fetch(g).GetNumberOfPoints()]
    # The camera: between the direction from the axis to the centre (f) and the direction of
    # the rolling (t = a x f), the axis across the picture, then turned by --azimuth /
    # --elevation.
    Render(view)  # the first render resets the camera: set it afterwards
    cam = view.GetActiveCamera()
    f, t = scene["f"], scene["t"]
    direction = f * np.cos(np.radians(TILT)) + a * np.sin(np.radians(TILT)) + 0.3 * t
    direction = direction / np.linalg.norm(direction)
    up = np.cross(direction, a)
    cam.SetFocalPoint(*c)
    cam.SetPosition(*(c + DIST * R * direction))
    cam.SetViewUp(*(up if up @ t >= 0 else -up))
    cam.Azimuth(azimuth)
    cam.Elevation(elevation)
    cam.OrthogonalizeViewUp()
    cam.SetViewAngle(30)
    view.CameraParallelProjection = 0
    Render(view)
    SaveScreenshot(png, view, ImageResolution=size)
    count = {k: v.GetNumberOfPoints() for k, v in held.items()}
    shown = np.concatenate([np.asarray(v.GetPointData().GetArray("id")) for v in held.values()])
    return {"grain": int(scene["grain"]), "grains": sorted(int(i) for i in shown),
            "partners": [int(i) for i in scene["partners"]],
            "faint": count.get(2, 0), "contacts": len(scene["contacts"]),
            "own_contacts": [[int(ids[a]), int(ids[b])] for a, b in own],
            "arrows": {k: v[0] for k, v in glyphs.items()},
            "arrow_points": {k: v[1] for k, v in glyphs.items()},
            "contact_points": None if scene["contact_points"] is None
            else np.asarray(scene["contact_points"]).tolist()}


def main():
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("xdmf", help="the XDMF sidecar of a modes file (MODES.xdmf)")
    ap.add_argument("--summary", help="write what ParaView read (JSON) here")
    ap.add_argument("--png", help="render --mode into this PNG")
    ap.add_argument("--mode", default="0",
                    help="which mode to draw: K (0 = the softest) or 'divalent' (the divalent "
                         "grains' free rollings)")
    ap.add_argument("--size", type=int, nargs=2, default=[800, 800], metavar=("W", "H"))
    ap.add_argument("--slab", type=float, default=1.0, metavar="FRACTION",
                    help="3D: draw only the middle FRACTION of the cell along z")
    ap.add_argument("--above", type=float, default=0.1, metavar="X",
                    help="arrows only on grains with |u| > X max|u| (default 0.1)")
    ap.add_argument("--grain", type=int, metavar="ID",
                    help="3D: zoom onto this grain (its id) and draw its motion")
    ap.add_argument("--packing", metavar="FILE.h5",
                    help="with --grain: the configuration of the modes, for the contacts")
    ap.add_argument("--around", type=float, default=2.1, metavar="X",
                    help="with --grain: the grains within X mean diameters (default 2.1; with "
                         "--packing only those that touch the grain or a partner)")
    ap.add_argument("--azimuth", type=float, default=0.0, metavar="DEG",
                    help="with --grain: turn the camera about the view-up axis")
    ap.add_argument("--elevation", type=float, default=0.0, metavar="DEG",
                    help="with --grain: tilt the camera")
    args = ap.parse_args()
    if not os.path.isfile(args.xdmf):
        die(f"{args.xdmf}: no such file")
    if args.mode == "divalent":
        name = DIVALENT
    elif re.fullmatch(r"\d+", args.mode):
        name = f"mode_{int(args.mode)}"
    else:
        die(f"--mode {args.mode}: a mode number (0, 1, ...) or 'divalent'")
    if args.around <= 0:
        die(f"--around {args.around}: must be > 0")
    if (args.packing or args.azimuth or args.elevation) and args.grain is None:
        die("--packing, --azimuth and --elevation go with --grain")
    if args.grain is not None and not args.png:
        die("--grain draws one grain: give --png")
    text = open(args.xdmf, errors="replace").read()
    held = sorted({int(k) for k in re.findall(r'Name="mode_(\d+)"', text)})
    if not held:
        die(f"{args.xdmf}: holds no mode_k arrays (is it a modes file of granpack stiffness --modes?)")
    dimension = 2 if "XY\"" in text else 3
    if name == DIVALENT and f'Name="{DIVALENT}"' not in text:
        die(f"{args.xdmf}: --mode divalent: the file holds no divalent rolling (no divalent grains: "
            "they exist in 3D packings with friction, without rolling resistance or cohesion)")
    if args.png and name != DIVALENT and int(args.mode) not in held:
        die(f"{args.xdmf}: --mode {args.mode}: the file holds modes {held[0]} to {held[-1]}")
    scene = None
    if args.grain is not None:
        if dimension != 3:
            die("--grain: 3D modes files only")
        try:
            modes = gio.read_modes(h5_of(args.xdmf, text))
            packing = gio.read_packing(args.packing) if args.packing else None
        except gio.GranpackFileError as e:
            gio.fail(PROG, e)
        if name != DIVALENT and int(args.mode) >= len(modes["eigenvalues"]):
            die(f"{args.xdmf}: --mode {args.mode}: the file holds modes {held[0]} to {held[-1]}")
        scene = zoom_scene(modes, packing, args.grain, name, args.around)
    paraview_api()
    reader = XDMFReader(FileNames=[args.xdmf])
    reader.UpdatePipeline()
    data = grains(reader)
    if data is None or data.GetNumberOfPoints() == 0:
        die(f"{args.xdmf}: ParaView read no grains from it")
    info = summary(data)
    if not info["modes"]:
        die(f"{args.xdmf}: holds no mode_k arrays (is it a modes file of granpack stiffness --modes?)")
    zoom = None
    if args.png:
        if scene is not None:
            zoom = render_zoom(scene, args.png, args.size, args.azimuth, args.elevation)
        else:
            render(reader, info, name, args.png, args.size, dimension, args.slab, args.above)
        print(args.png)
    if args.summary:
        out = {"file": args.xdmf, "dimension": dimension, **info}
        if zoom is not None:
            out["zoom"] = zoom
        with open(args.summary, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
