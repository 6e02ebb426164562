# Frame times of N spheres in pvbatch: the Quadric Glyphs representation against ParaView's Point
# Gaussian ("Sphere" preset) and 3D Glyphs (a sphere mesh per point) representations, in one run.
#
#   pvbatch glyphs_bench.py PLUGIN [--count N] [--frames F] [--glyph-max N] [--png PREFIX]
#
# The scene of `quadcast bench spheres`: N random spheres in the unit cube, radius 0.3 N^(-1/3),
# 1024x768, 30 degrees, eye (0.5, 0.5, 3). Under mpirun the points are spread over the ranks
# (RedistributeDataSet) and IceT composites the frames. Per representation: the first frame after
# Show (the data delivered to the mapper and uploaded: its time to first image in this process),
# then F frames, interleaved between the representations (each in a view of its own), each ended by reading one pixel back on
# one rank (so the time includes the GPU work; under MPI IceT's compositing reads the frames back). Prints medians and their ratios; the 3D Glyphs
# representation only up to --glyph-max points (its meshes have N x 50 triangles).
import argparse
import statistics
import sys
import time

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
import vtk
import numpy as np
from vtk.util import numpy_support

ap = argparse.ArgumentParser()
ap.add_argument("plugin")
ap.add_argument("--count", type=int, default=1000000)
ap.add_argument("--frames", type=int, default=5)
ap.add_argument("--glyph-max", type=int, default=100000)
ap.add_argument("--png", default=None, help="PREFIX: a screenshot of each representation's last frame, PREFIX_<name>.png")
args = ap.parse_args()
LoadPlugin(args.plugin, remote=False, ns=globals())
ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()

n = args.count
r = 0.3 * n ** (-1.0 / 3.0)
rng = np.random.default_rng(1)
centers = rng.random((n, 3))
points = vtk.vtkPoints()
points.SetData(numpy_support.numpy_to_vtk(centers, deep=1))
verts = vtk.vtkCellArray()
conn = numpy_support.numpy_to_vtkIdTypeArray(np.arange(n, dtype=np.int64), deep=1)
offsets = numpy_support.numpy_to_vtkIdTypeArray(np.arange(n + 1, dtype=np.int64), deep=1)
verts.SetData(offsets, conn)
poly = vtk.vtkPolyData()
poly.SetPoints(points)
poly.SetVerts(verts)
path = "/tmp/quadcast_glyphs_bench_%d.vtp" % n
writer = vtk.vtkXMLPolyDataWriter()
writer.SetFileName(path)
writer.SetInputData(poly)
writer.SetDataModeToAppended()
writer.Write()
source = XMLPolyDataReader(FileName=[path])
if ranks > 1:
    source = RedistributeDataSet(Input=source)
source.UpdatePipeline()  # (collective: every rank reads and redistributes here, not in a render)



def make_view():
    v = CreateView("RenderView")
    v.ViewSize = [1024, 768]
    v.OrientationAxesVisibility = 0
    v.UseFXAA = 0
    return v


def frame(v, k):
    camera = v.GetActiveCamera()
    camera.SetFocalPoint(0.5, 0.5, 0.5)
    camera.SetPosition(0.5, 0.5, 3.0 + 1e-6 * k)  # (a new camera each frame: every frame renders)
    camera.SetViewUp(0, 1, 0)
    camera.SetViewAngle(30)
    t = time.perf_counter()
    Render(v)
    if ranks == 1:  # (under MPI, IceT's compositing reads every rank's frame back already)
        px = vtk.vtkUnsignedCharArray()
        v.GetRenderWindow().GetRGBACharPixelData(0, 0, 0, 0, 0, px)
    return time.perf_counter() - t


displays = {}
glyph_filter = None


def show(name, view):
    global glyph_filter
    own = PassArrays(Input=source)  # (its own pipeline object: one display per representation)
    if name == "Quadric Glyphs":
        d = Show(own, view)
        d.SetRepresentationType("Quadric Glyphs")
        d.GlyphRadius = r
    elif name == "Point Gaussian":
        d = Show(own, view)
        d.SetRepresentationType("Point Gaussian")
        d.ShaderPreset = "Sphere"
        d.GaussianRadius = r
    else:
        glyph_filter = Glyph(Input=own, GlyphType="Sphere")
        glyph_filter.GlyphType.ThetaResolution = 8
        glyph_filter.GlyphType.PhiResolution = 6  # (about 50 triangles per sphere)
        glyph_filter.GlyphType.Radius = 1.0
        glyph_filter.ScaleArray = ["POINTS", "No scale array"]
        glyph_filter.ScaleFactor = r
        glyph_filter.GlyphMode = "All Points"
        d = Show(glyph_filter, view)
    d.DiffuseColor = [0.8, 0.8, 0.8]
    return d


names = ["Quadric Glyphs", "Point Gaussian"] + (["3D Glyphs"] if n <= args.glyph_max else [])
first = {}
views = {}
for name in names:  # (one view per representation: no visibility changes between frames)
    views[name] = make_view()
    t = time.perf_counter()
    displays[name] = show(name, views[name])
    frame(views[name], 0)
    first[name] = time.perf_counter() - t  # show + first frame
times = {name: [] for name in names}
for k in range(args.frames):
    for name in names:
        times[name].append(frame(views[name], k + 1))

if args.png:
    for name in names:
        SaveScreenshot(f"{args.png}_{name.replace(' ', '_')}.png", views[name], ImageResolution=[1024, 768])
print(f"pvbatch {ranks} rank(s), {n} spheres (r = {r:.4g}), 1024x768, median of {args.frames} interleaved frames")
med = {name: statistics.median(v) * 1e3 for name, v in times.items()}
for name in names:
    print(f"  {name:16s} frame {med[name]:9.1f} ms   show + first frame {first[name]:7.2f} s")
for name in names[1:]:
    print(f"  Quadric Glyphs against {name}: {med[name] / med['Quadric Glyphs']:.2f}x the frame rate")
sys.stdout.flush()
for v in views.values():
    Delete(v)
views.clear()
