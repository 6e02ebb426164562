# Isosurfaces of image data in pvbatch: the Spline Isosurface representation (QSS and trilinear)
# against ParaView's Contour filter (Flying Edges on image data) shown as a surface, in one run.
#
#   pvbatch isosurface_bench.py PLUGIN [--size N] [--iso V] [--frames F] [--png PREFIX]
#
# ParaView's Wavelet source on N^3 samples (extent -N/2 .. N/2 - 1), the isosurface RTData = V,
# 1024x768, 30 degrees, seen from a direction that turns a little each frame. Under mpirun the
# Wavelet's extent is split over the ranks; IceT composites. Per representation, each in a view of
# its own: the first frame after Show (the time to first image: the Contour filter's extraction,
# or the representation's spline preparation, with the upload and the first frame; the Wavelet
# source has run before, except that the Spline Isosurface asks for one ghost level on 2 ranks
# and the source runs again for it), then F frames interleaved between the representations, each
# ended by reading one pixel back on one rank. Prints medians and their ratios.
import argparse
import math
import statistics
import sys
import time

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
import vtk

ap = argparse.ArgumentParser()
ap.add_argument("plugin")
ap.add_argument("--size", type=int, default=128)
ap.add_argument("--iso", type=float, default=160.0)
ap.add_argument("--frames", type=int, default=5)
ap.add_argument("--png", default=None, help="PREFIX: a screenshot of each representation's last frame, PREFIX_<name>.png")
args = ap.parse_args()
LoadPlugin(args.plugin, remote=False, ns=globals())
ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()

h = args.size // 2
wavelet = Wavelet(WholeExtent=[-h, h - 1, -h, h - 1, -h, h - 1])
wavelet.UpdatePipeline()
W, H = 1024, 768


def make_view():
    v = CreateView("RenderView")
    v.ViewSize = [W, H]
    v.OrientationAxesVisibility = 0
    v.UseFXAA = 0
    return v


def frame(v, k):
    camera = v.GetActiveCamera()
    a = 0.6 + 0.02 * k  # (a new camera each frame: every frame renders)
    d = 3.2 * h
    camera.SetFocalPoint(0, 0, 0)
    camera.SetPosition(d * math.cos(a), -d * math.sin(a), 0.6 * d)
    camera.SetViewUp(0, 0, 1)
    camera.SetViewAngle(30)
    t = time.perf_counter()
    Render(v)
    if ranks == 1:  # (under MPI, IceT's compositing reads every rank's frame back already)
        px = vtk.vtkUnsignedCharArray()
        v.GetRenderWindow().GetRGBACharPixelData(0, 0, 0, 0, 0, px)
    return time.perf_counter() - t


def show(name, view):
    if name == "Contour":
        contour = Contour(Input=wavelet, ContourBy=["POINTS", "RTData"], Isosurfaces=[args.iso], ComputeNormals=1, ComputeScalars=0)
        d = Show(contour, view)
        d.SetRepresentationType("Surface")
        d.ColorArrayName = ["POINTS", ""]
    else:
        d = Show(wavelet, view)
        d.SetRepresentationType("Spline Isosurface")
        d.SplineArray = ["POINTS", "RTData"]
        d.SplineIsovalue = args.iso
        d.SplineScheme = "QSS" if name == "Spline QSS" else "Trilinear"
    d.DiffuseColor = [0.8, 0.8, 0.8]
    return d


names = ["Spline QSS", "Spline trilinear", "Contour"]
first, views, displays = {}, {}, {}
for name in names:
    views[name] = make_view()
    t = time.perf_counter()
    displays[name] = show(name, views[name])
    frame(views[name], 0)
    first[name] = time.perf_counter() - t
times = {name: [] for name in names}
for k in range(args.frames):
    for name in names:
        times[name].append(frame(views[name], k + 1))
if args.png:
    for name in names:
        SaveScreenshot(f"{args.png}_{name.replace(' ', '_')}.png", views[name], ImageResolution=[W, H])
print(f"pvbatch {ranks} rank(s), Wavelet {args.size}^3, isosurface {args.iso}, {W}x{H}, median of {args.frames} interleaved frames")
med = {name: statistics.median(v) * 1e3 for name, v in times.items()}
for name in names:
    print(f"  {name:17s} frame {med[name]:9.1f} ms   show + first frame {first[name]:7.2f} s")
for name in names[:2]:
    print(f"  {name} against Contour: {med['Contour'] / med[name]:.2f}x the frame rate, "
          f"{first['Contour'] / first[name]:.2f}x the speed to first image")
sys.stdout.flush()
for v in views.values():
    Delete(v)
views.clear()
