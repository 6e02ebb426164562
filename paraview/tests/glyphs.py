# The "Quadric Glyphs" representation in pvbatch, on 1 or 2 MPI ranks, against an exact reference.
#
#   pvbatch glyphs.py PLUGIN OUT_PREFIX [REFERENCE_PREFIX] [--tensors]
#
# --tensors: every point is the ellipsoid of a random symmetric positive-definite tensor (a
# 6-component point array in VTK's symmetric order xx yy zz xy yz xz, eigenvalues 0.4 .. 1.6)
# scaled by the same radius, whose semi-axes are the eigenvectors times their eigenvalues; the
# reference intersects each pixel ray with the ellipsoid {c + r T u : |u| <= 1}.
# --bonds: line cells too (each point to its nearest neighbour, and one polyline through 10
# points), drawn with GlyphBondRadius as capped cylinders; the reference intersects each pixel
# ray with the capped cylinders (side and end discs) and leaves out the pixels whose outcome
# changes when the ray moves by 0.02 pixels (outlines).
#
# A scene of random spheres (radius from a point array times GlyphRadius, coloured through the
# lookup table) cut by an opaque ParaView plane, drawn in a render view. Under MPI the points are
# redistributed over the ranks (RedistributeDataSet) and IceT composites the ranks' images by depth.
#
# Checked, per pixel of the view, against the scene computed here in double precision (numpy): the
# pixel ray of the view's own projection against every sphere and the plane.
#   - coverage: a pixel is covered exactly where its ray meets a sphere or the plane, except
#     where the ray passes within 0.02 pixels of a sphere's outline (rounding decides there);
#   - depth: the window depth ParaView's depth buffer holds is the nearest hit's, within 2e-6
#     (float rounding of the ray cast), wherever the nearest hit is a sphere not closer than 0.02
#     pixels to its outline and not within 1e-5 of the plane's depth (a tie);
#   - composition: pixels whose nearest hit is the plane show the plane's colour (green, lit),
#     pixels whose nearest hit is a sphere do not.
# The depth check needs the view's depth buffer, read on one rank only; coverage and composition are
# checked on the composited screenshot on any number of ranks.
# With REFERENCE_PREFIX (the 1-rank run's OUT_PREFIX) the image must also equal that run's:
# identical coverage, colours within 1 level.
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

argv = [a for a in sys.argv[1:] if a not in ("--tensors", "--bonds")]
tensor_mode = "--tensors" in sys.argv  # tensor ellipsoids instead of spheres
bond_mode = "--bonds" in sys.argv  # line cells drawn as cylinders too
plugin, out = argv[0], argv[1]
reference = argv[2] if len(argv) > 2 else None
LoadPlugin(plugin, remote=False, ns=globals())

W, H = 320, 240
N = 300
GLYPH_RADIUS = 0.04
PLANE_Z = 0.5

# Random spheres in the unit cube: radius GLYPH_RADIUS * (0.5 .. 1.5), coloured by x.
rng = np.random.default_rng(11)
centers = rng.random((N, 3))
scales = 0.5 + rng.random(N)
radii = GLYPH_RADIUS * scales
tensors = np.tile(np.eye(3), (N, 1, 1))
if tensor_mode:
    for k in range(N):
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        tensors[k] = q @ np.diag(0.4 + 1.2 * rng.random(3)) @ q.T
points = vtk.vtkPoints()
points.SetData(numpy_support.numpy_to_vtk(centers, deep=1))
scale_array = numpy_support.numpy_to_vtk(scales, deep=1)
scale_array.SetName("scale")
value_array = numpy_support.numpy_to_vtk(centers[:, 0].copy(), deep=1)
value_array.SetName("value")
poly = vtk.vtkPolyData()
poly.SetPoints(points)
verts = vtk.vtkCellArray()  # (one vertex cell per point: RedistributeDataSet moves cells)
for i in range(N):
    verts.InsertNextCell(1)
    verts.InsertCellPoint(i)
poly.SetVerts(verts)
BOND_RADIUS = 0.012
bond_segments = []
if bond_mode:
    lines = vtk.vtkCellArray()
    d2 = ((centers[:, None, :] - centers[None, :, :]) ** 2).sum(-1) + np.eye(N) * 1e9
    pairs = sorted({(min(i, j), max(i, j)) for i, j in enumerate(d2.argmin(1))})
    for i, j in pairs:
        lines.InsertNextCell(2)
        lines.InsertCellPoint(i)
        lines.InsertCellPoint(j)
        bond_segments.append((i, j))
    lines.InsertNextCell(10)
    for i in range(10):
        lines.InsertCellPoint(i)
        if i > 0:
            bond_segments.append((i - 1, i))
    poly.SetLines(lines)
poly.GetPointData().AddArray(scale_array)
poly.GetPointData().AddArray(value_array)
if tensor_mode:
    sym = np.stack([tensors[:, 0, 0], tensors[:, 1, 1], tensors[:, 2, 2], tensors[:, 0, 1], tensors[:, 1, 2], tensors[:, 0, 2]], axis=1)
    tensor_array = numpy_support.numpy_to_vtk(sym, deep=1)
    tensor_array.SetName("tensor")
    poly.GetPointData().AddArray(tensor_array)
writer = vtk.vtkXMLPolyDataWriter()
writer.SetFileName(out + "_points.vtp")
writer.SetInputData(poly)
writer.Write()

source = XMLPolyDataReader(FileName=[out + "_points.vtp"])
ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
source = pvcheck.distribute(source, ranks, "glyphs", "points")

view = pvcheck.make_view(W, H)
glyphs = Show(source, view)
glyphs.SetRepresentationType("Quadric Glyphs")
glyphs.GlyphRadius = GLYPH_RADIUS
if bond_mode:
    glyphs.GlyphBondRadius = BOND_RADIUS
if tensor_mode:
    glyphs.QuadricGlyphType = "Tensor Ellipsoid"
    glyphs.GlyphTensorArray = ["POINTS", "tensor"]
glyphs.GlyphScaleByArray = 1
glyphs.GlyphScaleArray = ["POINTS", "scale"]
ColorBy(glyphs, ("POINTS", "value"))
plane = Plane(Origin=[-0.3, -0.3, PLANE_Z], Point1=[1.3, -0.3, PLANE_Z], Point2=[-0.3, 1.3, PLANE_Z])
pvcheck.show_green(plane, view)
camera = pvcheck.look_from(view, (0.5 + 1.4, 0.5 - 1.1, 0.5 + 2.0), (0.5, 0.5, 0.45))
# The depth buffer on one rank (IceT composites colours into the screenshot; the window's own
# depth buffer holds the composited depths only when there is one rank).
depth = pvcheck.depth_buffer(view, W, H) if ranks == 1 else None
rgb, covered = pvcheck.screenshot(view, out, W, H)
# The exact scene along each pixel ray, from the camera's own matrices.
cam = pvcheck.CameraRays(camera, W, H)
origin = cam.eye
dirs = cam.directions()

def window_depth(t):
    return cam.window_depth(dirs, t)

inf = np.inf
t_sphere = np.full((H, W), inf)
rim = np.zeros((H, W), dtype=bool)  # the ray passes within 0.02 px of some sphere's outline
pixel_angle = np.radians(30) / H  # radians per pixel (vertical field of view / rows)
for c, r, T in zip(centers, radii, tensors):
    # the ellipsoid c + A u, |u| <= 1, A = r T (a sphere: T = I); the ray in u coordinates
    Ainv = np.linalg.inv(r * T)
    o_l = Ainv @ (origin - c)
    d_l = dirs @ Ainv.T
    a = np.einsum("ijk,ijk->ij", d_l, d_l)
    b = d_l @ o_l
    cc = o_l @ o_l - 1
    disc = b * b - a * cc
    hit = disc >= 0
    t = np.where(hit, (-b - np.sqrt(np.where(hit, disc, 0))) / a, inf)
    t = np.where(t > 0, t, inf)
    t_sphere = np.minimum(t_sphere, t)
    # how far the ray passes from the outline, in pixels at the centre's distance (its distance
    # from the centre in u coordinates against 1, times the largest semi-axis)
    dist_l = np.sqrt(np.maximum(cc + 1 - b * b / a, 0))
    d = np.linalg.norm(origin - c)
    rim |= np.abs(dist_l - 1) * r * np.linalg.eigvalsh(T).max() < 0.02 * pixel_angle * d
def capped_cylinder_hits(o, dd, a, b, rho):
    """Nearest t > 0 of each ray o + t dd (dd: H x W x 3) on the capped cylinder a-b of radius rho."""
    L = np.linalg.norm(b - a)
    u = (b - a) / L
    w = o - a
    du = dd @ u
    wu = w @ u
    dp = dd - du[..., None] * u
    wp = w - wu * u
    A = np.einsum("ijk,ijk->ij", dp, dp)
    B = dp @ wp
    C = wp @ wp - rho * rho
    disc = B * B - A * C
    best = np.full(dd.shape[:2], inf)
    ok = (disc >= 0) & (A > 0)
    sq = np.sqrt(np.where(ok, disc, 0))
    for sign in (-1, 1):
        t = np.where(ok, (-B + sign * sq) / np.where(A > 0, A, 1), inf)
        ax = wu + t * du
        good = ok & (t > 0) & (ax >= 0) & (ax <= L)
        best = np.where(good, np.minimum(best, t), best)
    for center, axial in ((a, 0.0), (b, L)):
        t = np.where(np.abs(du) > 0, (axial - wu) / np.where(np.abs(du) > 0, du, 1), inf)
        q = w + t[..., None] * dd - axial * u
        rad2 = np.einsum("ijk,ijk->ij", q, q) - (q @ u) ** 2
        good = (t > 0) & (rad2 <= rho * rho) & np.isfinite(t)
        best = np.where(good, np.minimum(best, t), best)
    return best

if bond_mode:
    # jittered rays: 0.02 px along x and y (the pixel's window offsets through the inverse projection)
    jitter = [cam.directions(dx, dy) for dx, dy in ((0.02, 0), (-0.02, 0), (0, 0.02), (0, -0.02))]
    for i, j in bond_segments:
        a, b = centers[i], centers[j]
        t = capped_cylinder_hits(origin, dirs, a, b, BOND_RADIUS)
        t_sphere = np.minimum(t_sphere, t)
        for jd in jitter:
            rim |= np.isfinite(capped_cylinder_hits(origin, jd, a, b, BOND_RADIUS)) != np.isfinite(t)
    print(f"glyphs: {len(bond_segments)} bonds (radius {BOND_RADIUS})")
t_plane = np.where(np.abs(dirs[..., 2]) > 0, (PLANE_Z - origin[2]) / dirs[..., 2], inf)
p = origin + dirs * np.where(np.isfinite(t_plane), t_plane, 0)[..., None]
on_plane = np.isfinite(t_plane) & (t_plane > 0) & (p[..., 0] >= -0.3) & (p[..., 0] <= 1.3) & (p[..., 1] >= -0.3) & (p[..., 1] <= 1.3)
t_plane = np.where(on_plane, t_plane, inf)
z_sphere = np.where(np.isfinite(t_sphere), window_depth(np.where(np.isfinite(t_sphere), t_sphere, 1)), 1.0)
z_plane = np.where(np.isfinite(t_plane), window_depth(np.where(np.isfinite(t_plane), t_plane, 1)), 1.0)
z_exact = np.minimum(z_sphere, z_plane)

failures = []
exact_covered = z_exact < 1.0
coverage_diff = (covered != exact_covered) & ~rim
sphere_front = (z_sphere < z_plane) & np.isfinite(t_sphere)
plane_front = (z_plane < z_sphere) & np.isfinite(t_plane)
tie = np.abs(z_sphere - z_plane) < 1e-5
checked = sphere_front & ~rim & ~tie & covered
plane_colour = pvcheck.plane_coloured(rgb)
print(f"glyphs: {W}x{H}, {N} spheres; covered {covered.sum()} px (exact {exact_covered.sum()}), "
      f"sphere in front {sphere_front.sum()}, plane in front {plane_front.sum()}, outline px {rim.sum()}")
print(f"glyphs: coverage differences away from outlines {coverage_diff.sum()}")
if coverage_diff.any():
    failures.append(f"{coverage_diff.sum()} pixels covered differently from the exact scene")
if checked.sum() < 2000:
    failures.append(f"only {checked.sum()} sphere pixels checked: the scene does not show the spheres")
if depth is not None:
    # (The view's orientation-axes renderer clears the depth buffer in the lower-left quarter of
    # each side even when the axes are hidden: no depth is checked there; colours are.)
    axes_box = (np.arange(W)[None, :] < W // 4) & (np.arange(H)[:, None] < H // 4)
    depth = np.where(axes_box & covered, z_exact, depth)
    depth_err = np.abs(depth - z_exact)
    plane_checked = plane_front & ~tie & ~rim & ~axes_box
    checked = checked & ~axes_box
    print(f"glyphs: sphere depth max error {depth_err[checked].max():.3g} over {checked.sum()} px; "
          f"plane depth max error {depth_err[plane_checked].max():.3g} over {plane_checked.sum()} px")
    if (depth < 1.0).sum() != covered.sum() or ((depth < 1.0) != covered).any():
        failures.append("the depth buffer and the colour image cover different pixels")
    if depth_err[checked].max() > 2e-6:
        failures.append(f"sphere depth off by {depth_err[checked].max():.3g}")
    if depth_err[plane_checked].max() > 2e-6:
        failures.append(f"plane depth off by {depth_err[plane_checked].max():.3g}")
wrong_plane = plane_front & ~tie & ~rim & ~plane_colour
wrong_sphere = sphere_front & ~tie & ~rim & plane_colour
for j, i in zip(*np.nonzero(wrong_plane | wrong_sphere)):
    print(f"  pixel ({i}, {j}): rgb {rgb[j, i]}, depth {depth[j, i]:.7f}, sphere {z_sphere[j, i]:.7f}, plane {z_plane[j, i]:.7f}")
print(f"glyphs: plane pixels not plane-coloured {wrong_plane.sum()}, sphere pixels plane-coloured {wrong_sphere.sum()}")
if wrong_plane.any() or wrong_sphere.any():
    failures.append("the spheres and the plane are not composed by depth")
# Colour by the lookup table: the leftmost and rightmost spheres differ in colour (blue .. red).
sphere_rgb = rgb[checked]
if not (sphere_rgb[:, 2].max() - sphere_rgb[:, 0].min() > 100 and sphere_rgb[:, 0].max() - sphere_rgb[:, 2].min() > 100):
    failures.append("the spheres are not coloured through the lookup table")

if reference:
    cov, dc, _ = pvcheck.compare_with_reference(reference, rgb, covered, "glyphs")
    if cov or dc > 1:
        failures.append("the image differs from the reference run's")

for f in failures:
    print("FAIL:", f)
# Delete the view while the process's shared render window lives: left to the interpreter's exit,
# the view's window is finalized after that window's GLX context (GLXBadContext from
# glXMakeCurrent, exit status 1, with or without this plugin).
Delete(view)
del view
if failures:  # (an exception: pvbatch then exits with status 1 on every rank, through MPI_Finalize)
    raise RuntimeError("; ".join(failures))
