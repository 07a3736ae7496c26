#!/usr/bin/env python3
"""Standard pictures of a shatter run with ParaView, without a display.

For each field (damage, speed = |velocity|, peak_pressure; those the snapshots hold) writes
FIELD_3d.png (the particles from an oblique view) and FIELD_slice.png (the particles within a thin
slab through the run, seen face on) at one snapshot (the last by default), and with --animate a
frame series FIELD_3d_NNNN.png over all snapshots (for ffmpeg or ParaView's own animation).

Reads RUN/particles.xmf through ParaView's default Xdmf3 reader (python3-paraview, ParaView 5.11).
ParaView renders through X: without $DISPLAY the tool runs itself again under `xvfb-run -a`
(Debian's xvfb and xauth), so it works on a headless machine or in CI. docs/outputs.md,
"Pictures without a display", gives the recipe.

  tools/render.py RUN                     # RUN/pictures/{damage,speed,peak_pressure}_{3d,slice}.png
  tools/render.py RUN --fields damage --time 5e-6 --out figs --size 1200x900
  tools/render.py RUN --animate           # plus FIELD_3d_0000.png ... one per snapshot
"""

import argparse
import os
import shutil
import subprocess
import sys
import time

FIELDS = ("damage", "speed", "peak_pressure")
BACKGROUND = (1.0, 1.0, 1.0)  # white: the test counts the pixels that differ from it


def parse(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog="\n".join(__doc__.split("\n")[2:]))
    p.add_argument("run", help="run directory (holds particles.xmf and snapshots/)")
    p.add_argument("--out", help="folder for the pictures (default RUN/pictures; created)")
    p.add_argument("--fields", default=",".join(FIELDS),
                   help="comma-separated: damage, speed, peak_pressure or any snapshot column "
                        "(default: %(default)s; a field the snapshots lack is skipped, said so)")
    p.add_argument("--time", type=float, help="snapshot time in s (default: the last snapshot)")
    p.add_argument("--views", default="3d,slice", help="3d and/or slice (default: %(default)s)")
    p.add_argument("--slice-axis", choices="xyz",
                   help="normal of the slab (default: the symmetry plane's normal, else z)")
    p.add_argument("--slice-at", type=float,
                   help="slab position along the axis in m (default: on the symmetry plane, "
                        "else the middle of the particles)")
    p.add_argument("--animate", action="store_true", help="also a 3-D frame series per field")
    p.add_argument("--size", default="800x600", help="picture size WxH in pixels")
    p.add_argument("--point-size", type=float, default=3.0, help="particle size in pixels")
    return p.parse_args(argv)


def rerun_under_xvfb():
    """ParaView (Debian's build) renders through X; give it a virtual one when none is set."""
    if os.environ.get("DISPLAY") or os.environ.get("SHATTER_RENDER_UNDER_XVFB"):
        return
    xvfb = shutil.which("xvfb-run")
    if xvfb is None:
        sys.exit("render.py: no $DISPLAY and no xvfb-run: install xvfb and xauth "
                 "(tools/setup.sh --tests) or run under a display")
    env = dict(os.environ, SHATTER_RENDER_UNDER_XVFB="1")
    cmd = [xvfb, "-a", "-s", "-screen 0 1920x1080x24", sys.executable,
           os.path.abspath(__file__)] + sys.argv[1:]
    # xvfb-run -a picks a free display number, but two starting at once can pick the same one
    # ("Xvfb failed to start", or a server that another run's xvfb-run tears down under us, so
    # that ParaView aborts creating its window): try again, a few times. Only these two X
    # start-up failures are retried; any other error is reported at once.
    x_startup = ("Xvfb failed to start", "vtkXOpenGLRenderWindow::CreateAWindow")
    for attempt in range(4):
        r = subprocess.run(cmd, env=env, stderr=subprocess.PIPE, text=True)
        if not any(s in r.stderr for s in x_startup) or r.returncode == 0 or attempt == 3:
            break
        time.sleep(1.0 + attempt)
    sys.stderr.write(r.stderr)
    sys.exit(r.returncode)


def symmetry_axis(run):
    """-1 (none) or 0/1/2 from the first snapshot's header (shatterpy's reading)."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir,
                                    "python"))
    import shatterpy
    return shatterpy.symmetry_axis(run)


class Scene:
    """The reader, one render view, and the speed array; shared by every picture."""

    def __init__(self, args):
        from paraview import simple
        self.simple = simple
        xmf = os.path.abspath(os.path.join(args.run, "particles.xmf"))
        if not os.path.exists(xmf):
            sys.exit(f"render.py: {xmf} not found (is {args.run} a shatter run directory?)")
        self.reader = simple.OpenDataFile(xmf)
        self.times = list(self.reader.TimestepValues) or [0.0]
        self.time = self.times[-1] if args.time is None else min(
            self.times, key=lambda t: abs(t - args.time))
        self.reader.UpdatePipeline(self.time)
        self.arrays = set(self.reader.PointData.keys())
        self.source = simple.Calculator(Input=self.reader, ResultArrayName="speed",
                                        Function="mag(velocity)")
        self.source.UpdatePipeline(self.time)
        w, h = (int(v) for v in args.size.lower().split("x"))
        self.view = simple.CreateView("RenderView")
        self.view.ViewSize = [w, h]
        self.view.OrientationAxesVisibility = 0
        self.view.UseColorPaletteForBackground = 0
        self.view.Background = list(BACKGROUND)
        self.point_size = args.point_size

    def has(self, field):
        return field == "speed" and "velocity" in self.arrays or field in self.arrays

    def show(self, source, field):
        simple = self.simple
        for s in list(simple.GetSources().values()):
            simple.Hide(s, self.view)
        d = simple.Show(source, self.view)
        d.SetRepresentationType("Points")
        d.PointSize = self.point_size
        simple.ColorBy(d, ("POINTS", field))
        d.RescaleTransferFunctionToDataRange(True, False)
        d.SetScalarBarVisibility(self.view, True)
        bar = simple.GetScalarBar(simple.GetColorTransferFunction(field), self.view)
        bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
        return d

    def save(self, path):
        self.simple.SaveScreenshot(path, self.view, ImageResolution=list(self.view.ViewSize),
                                   TransparentBackground=0)
        print(path)


def view_3d(scene, field, out, animate):
    scene.show(scene.source, field)
    scene.view.ViewTime = scene.time
    scene.view.CameraPosition = [1.0, -1.5, 1.2]
    scene.view.CameraFocalPoint = [0.0, 0.0, 0.0]
    scene.view.CameraViewUp = [0.0, 0.0, 1.0]
    scene.view.CameraParallelProjection = 0
    scene.simple.ResetCamera(scene.view)
    scene.save(os.path.join(out, f"{field}_3d.png"))
    if animate:
        for k, t in enumerate(scene.times):
            scene.view.ViewTime = t
            scene.source.UpdatePipeline(t)
            scene.simple.Render(scene.view)
            scene.save(os.path.join(out, f"{field}_3d_{k:04d}.png"))
        scene.view.ViewTime = scene.time


def slab(scene, args):
    """Threshold on the distance to the slab plane: particles (vertex cells) have no extent, so
    ParaView's Slice filter would cut none of them."""
    axis = args.slice_axis
    sym = symmetry_axis(args.run)
    if axis is None:
        axis = "xyz"[sym] if sym >= 0 else "z"
    k = "xyz".index(axis)
    bounds = scene.source.GetDataInformation().GetBounds()
    lo, hi = bounds[2 * k], bounds[2 * k + 1]
    at = args.slice_at
    if at is None:
        at = lo if sym == k else 0.5 * (lo + hi)
    npts = max(scene.source.GetDataInformation().GetNumberOfPoints(), 1)
    extent = [max(bounds[2 * i + 1] - bounds[2 * i], 1e-30) for i in range(3)]
    # About two particle spacings: (box volume / points)^(1/3) for a filled body.
    thickness = 2.0 * (extent[0] * extent[1] * extent[2] / npts) ** (1.0 / 3.0)
    dist = scene.simple.Calculator(Input=scene.source, ResultArrayName="slab_distance",
                                   Function=f"abs(coords{axis.upper()}-({at!r}))")
    cut = scene.simple.Threshold(Input=dist, Scalars=["POINTS", "slab_distance"])
    cut.LowerThreshold = 0.0
    cut.UpperThreshold = thickness
    cut.ThresholdMethod = "Between"
    return cut, k


def view_slice(scene, field, out, cut, k):
    scene.show(cut, field)
    scene.view.ViewTime = scene.time
    normal = [0.0, 0.0, 0.0]
    normal[k] = 1.0
    scene.view.CameraFocalPoint = [0.0, 0.0, 0.0]
    scene.view.CameraPosition = normal
    scene.view.CameraViewUp = [0.0, 0.0, 1.0] if k != 2 else [0.0, 1.0, 0.0]
    # Perspective, face on: ParaView 5.11's ResetCamera left a parallel view of the slab empty.
    scene.view.CameraParallelProjection = 0
    scene.simple.ResetCamera(scene.view)
    scene.save(os.path.join(out, f"{field}_slice.png"))


def main(argv):
    args = parse(argv)
    rerun_under_xvfb()
    out = args.out or os.path.join(args.run, "pictures")
    os.makedirs(out, exist_ok=True)
    scene = Scene(args)
    views = [v.strip() for v in args.views.split(",") if v.strip()]
    for v in views:
        if v not in ("3d", "slice"):
            sys.exit(f"render.py: --views: unknown view '{v}' (3d, slice)")
    cut = slab(scene, args) if "slice" in views else None
    drawn = 0
    for field in (f.strip() for f in args.fields.split(",") if f.strip()):
        if not scene.has(field):
            print(f"render.py: {field}: not in the snapshots (arrays: "
                  f"{', '.join(sorted(scene.arrays))}); skipped", file=sys.stderr)
            continue
        if "3d" in views:
            view_3d(scene, field, out, args.animate)
        if cut is not None:
            view_slice(scene, field, out, *cut)
        drawn += 1
    if drawn == 0:
        sys.exit("render.py: none of the fields asked for is in the snapshots")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
