# The "Tetra Isosurface" representation in pvbatch, on 1 or 2 MPI ranks, against an exact reference.
#
#   pvbatch tetra_isosurface.py PLUGIN OUT_PREFIX [REFERENCE_PREFIX] [--linear]
#
# The mesh: the box [-1, 1]^3 cut into 6^3 cubes, each into the 6 tetrahedra around its main
# diagonal, as VTK_QUADRATIC_TETRA cells (edge nodes at the midpoints, VTK's node order), or with
# --linear as VTK_TETRA cells; the point array f = |x - c|^2 (c = (0.1, -0.05, 0.07)) and its
# isosurface f = 0.64, drawn next to an opaque ParaView plane z = 0.2 at 320x240. Under MPI the
# cells are redistributed over the ranks (RedistributeDataSet).
#
# Quadratic elements reproduce f exactly, so the surface is the sphere |x - c| = 0.8; checked per
# pixel against the sphere and the plane intersected in double precision (numpy):
#   - coverage: identical except where a ray moved by 0.05 pixels changes the outcome (outlines);
#   - depth: ParaView's depth buffer within 2e-6 of the exact nearest hit (one rank);
#   - composition: pixels whose nearest hit is the plane show its colour, and no sphere pixel does.
# Linear elements: the interpolant of the convex f lies above f by at most L^2 / 4 (L: the longest
# edge; f'' = 2), so its isosurface lies between the sphere of radius 0.8 and that of radius
# sqrt(0.64 - L^2 / 4): every surface pixel's depth must lie between those two spheres' (and every
# pixel that meets the inner sphere must be covered).
# With REFERENCE_PREFIX (the 1-rank run's OUT_PREFIX) the composited image must equal that run's:
# coverage identical, colours within 1 level.
# Writes OUT_PREFIX.png and OUT_PREFIX_rgb.npy. Exit status 1 on any failure (a RuntimeError).
import os
import sys

import numpy as np
from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
import vtk
from vtk.util import numpy_support

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pvcheck  # noqa: E402

args = [a for a in sys.argv[1:] if a != "--linear"]
linear = "--linear" in sys.argv
plugin, out = args[0], args[1]
reference = args[2] if len(args) > 2 else None
LoadPlugin(plugin, remote=False, ns=globals())

W, H = 320, 240
N = 6
CENTER = np.array([0.1, -0.05, 0.07])
R = 0.8
PLANE_Z = 0.2

# Nodes: the grid of half steps (2N + 1)^3, so that every edge midpoint of the cubes' tetrahedra
# is a node; tetrahedra around each cube's diagonal corner 0 -> corner 7.
m = 2 * N + 1
g = np.linspace(-1.0, 1.0, m)
Z, Y, X = np.meshgrid(g, g, g, indexing="ij")
nodes = np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1)  # index i + m (j + m k)
values = ((nodes - CENTER) ** 2).sum(axis=1)


def node(i, j, k):
    return i + m * (j + m * k)


paths = [(1, 3), (1, 5), (2, 3), (2, 6), (4, 5), (4, 6)]  # corner 0 -> a -> b -> corner 7 (bits x y z)
grid = vtk.vtkUnstructuredGrid()
pts = vtk.vtkPoints()
pts.SetData(numpy_support.numpy_to_vtk(nodes, deep=1))
grid.SetPoints(pts)
edges = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]  # VTK_QUADRATIC_TETRA's nodes 4..9
longest = 0.0
for k in range(N):
    for j in range(N):
        for i in range(N):
            def corner(bits, i=i, j=j, k=k):
                return (2 * (i + (bits & 1)), 2 * (j + (bits >> 1 & 1)), 2 * (k + (bits >> 2 & 1)))
            for a, b in paths:
                tet = [corner(0), corner(a), corner(b), corner(7)]
                p = [nodes[node(*t)] for t in tet]
                if np.dot(p[1] - p[0], np.cross(p[2] - p[0], p[3] - p[0])) < 0:
                    tet[1], tet[2] = tet[2], tet[1]  # (positive orientation, as VTK expects)
                ids = [node(*t) for t in tet]
                if linear:
                    grid.InsertNextCell(vtk.VTK_TETRA, 4, ids)
                else:
                    mids = [node(*((np.array(tet[u]) + np.array(tet[v])) // 2)) for u, v in edges]
                    grid.InsertNextCell(vtk.VTK_QUADRATIC_TETRA, 10, ids + mids)
                for u in range(4):
                    for v in range(u + 1, 4):
                        longest = max(longest, np.linalg.norm(nodes[ids[u]] - nodes[ids[v]]))
f_array = numpy_support.numpy_to_vtk(values, deep=1)
f_array.SetName("f")
grid.GetPointData().AddArray(f_array)
writer = vtk.vtkXMLUnstructuredGridWriter()
writer.SetFileName(out + "_mesh.vtu")
writer.SetInputData(grid)
writer.Write()

source = XMLUnstructuredGridReader(FileName=[out + "_mesh.vtu"])
ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
source = pvcheck.distribute(source, ranks, "tetra", "cells")

view = pvcheck.make_view(W, H)
surface = Show(source, view)
surface.SetRepresentationType("Tetra Isosurface")
surface.TetraArray = ["POINTS", "f"]
surface.TetraIsovalue = R * R
surface.DiffuseColor = [0.9, 0.8, 0.6]
plane = Plane(Origin=[-1.5, -1.5, PLANE_Z], Point1=[1.5, -1.5, PLANE_Z], Point2=[-1.5, 1.5, PLANE_Z])
pvcheck.show_green(plane, view)
camera = pvcheck.look_from(view, (2.6, -3.2, 2.4), (0, 0, 0))
depth = pvcheck.depth_buffer(view, W, H) if ranks == 1 else None
rgb, covered = pvcheck.screenshot(view, out, W, H)
plane_colour = pvcheck.plane_coloured(rgb)

# The exact scene along each pixel ray, from the camera's own matrices.
cam = pvcheck.CameraRays(camera, W, H)
eye = cam.eye


def sphere_hits(d, r):
    oc = eye - CENTER
    b = d @ oc
    disc = b * b - (oc @ oc - r * r)
    t = -b - np.sqrt(np.where(disc >= 0, disc, 0))
    return np.where((disc >= 0) & (t > 0), t, np.inf)


def plane_hits(d):
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(np.abs(d[..., 2]) > 0, (PLANE_Z - eye[2]) / d[..., 2], np.inf)
    p = eye + d * np.where(np.isfinite(t), t, 0)[..., None]
    on = np.isfinite(t) & (t > 0) & (np.abs(p[..., 0]) <= 1.5) & (np.abs(p[..., 1]) <= 1.5)
    return np.where(on, t, np.inf)


dirs = cam.directions()
r_inner = np.sqrt(R * R - longest * longest / 4) if linear else R
t_sphere, t_inner, t_plane = sphere_hits(dirs, R), sphere_hits(dirs, r_inner), plane_hits(dirs)
rim = np.zeros((H, W), dtype=bool)
for dx, dy in ((0.05, 0), (-0.05, 0), (0, 0.05), (0, -0.05)):
    d = cam.directions(dx, dy)
    for fn, t in ((lambda d_: sphere_hits(d_, R), t_sphere), (lambda d_: sphere_hits(d_, r_inner), t_inner), (plane_hits, t_plane)):
        rim |= np.isfinite(fn(d)) != np.isfinite(t)
failures = []
with np.errstate(invalid="ignore"):
    sphere_front = np.isfinite(t_sphere) & (t_sphere < t_plane)
    plane_front = np.isfinite(t_plane) & (t_plane < t_sphere) & (t_plane < t_inner)  # (the plane in front of any surface the mesh can have there)
    tie = np.abs(t_sphere - t_plane) < 1e-4
    if linear:
        tie |= (t_plane >= t_sphere) & (t_plane <= t_inner)  # (the plane between the two bounding spheres: either may be in front)
print(f"tetra: {'linear' if linear else 'quadratic'}, {grid.GetNumberOfCells()} cells (longest edge {longest:.3f}), {W}x{H}; covered {covered.sum()} px, "
      f"sphere in front {sphere_front.sum()}, plane in front {plane_front.sum()}, outline px {rim.sum()}")
if sphere_front.sum() < 3000 or plane_front.sum() < 3000:
    failures.append("the scene does not show both the surface and the plane")
if ranks == 1:
    z_sphere, z_inner, z_plane = cam.window_depth(dirs, t_sphere), cam.window_depth(dirs, t_inner), cam.window_depth(dirs, t_plane)
    surf = covered & ~plane_colour & ~rim & ~tie
    if not linear:
        exact_covered = np.isfinite(t_sphere) | np.isfinite(t_plane)
        coverage_diff = (covered != exact_covered) & ~rim
        err = np.abs(depth - z_sphere)
        checked = sphere_front & surf
        worst = err[checked].max() if checked.any() else np.inf
        print(f"tetra: coverage differences away from outlines {coverage_diff.sum()}; depth max error {worst:.3g} over {checked.sum()} px")
        if coverage_diff.any():
            failures.append(f"{coverage_diff.sum()} pixels covered differently from the exact sphere")
        if checked.sum() < 3000:
            failures.append(f"only {checked.sum()} surface pixels to check")
        elif worst > 2e-6:
            failures.append(f"depth off by {worst:.3g}")
    else:
        must = (np.isfinite(t_inner) | np.isfinite(t_plane)) & ~rim
        may = np.isfinite(t_sphere) | np.isfinite(t_plane) | rim
        outside = surf & ((depth < z_sphere - 2e-6) | (depth > z_inner + 2e-6))
        print(f"tetra: pixels that must be covered but are not {(must & ~covered).sum()}, covered but may not be {(covered & ~may).sum()}, "
              f"surface depth outside the two spheres' {outside.sum()} of {(surf & np.isfinite(t_sphere)).sum()}")
        if (must & ~covered).any() or (covered & ~may).any():
            failures.append("coverage outside the bounds of the linear interpolant's isosurface")
        if outside.any():
            failures.append(f"{outside.sum()} pixels' depth outside the bounds of the linear interpolant's isosurface")
wrong_plane = plane_front & ~tie & ~rim & ~plane_colour
wrong_sphere = sphere_front & ~tie & ~rim & np.isfinite(t_inner) & plane_colour
print(f"tetra: plane pixels not plane-coloured {wrong_plane.sum()}, surface pixels plane-coloured {wrong_sphere.sum()}")
if wrong_plane.any() or wrong_sphere.any():
    failures.append("the surface and the plane are not composed by depth")

if reference:
    cov, dc, _ = pvcheck.compare_with_reference(reference, rgb, covered, "tetra")
    if cov or dc > 1:
        failures.append("the image differs from the reference run's")

for f_ in failures:
    print("FAIL:", f_)
Delete(view)  # (before the interpreter's exit: see glyphs.py)
del view
if failures:
    raise RuntimeError("; ".join(failures))
