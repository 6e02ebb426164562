# The "Spline Isosurface" representation in pvbatch, on 1 or 2 MPI ranks.
#
#   pvbatch isosurface.py PLUGIN OUT_PREFIX [REFERENCE_PREFIX] [--scheme qss|s31|trilinear] [--no-ghosts]
#
# The scene: ParaView's Wavelet source (RTData, extent -16..16 on each axis: 33^3 samples whose
# index space does not start at 0), its isosurface RTData = ISO drawn by the plugin with the
# actor scaled by 1.5 along z (anisotropic voxels), next to an opaque ParaView plane through it,
# seen obliquely at 320x240. Under MPI the Wavelet source splits its extent over the ranks (VTK's
# pieces) and the representation asks for one ghost level.
#
# Checked on one rank, per pixel, against the exact trilinear isosurface computed here in double
# precision (numpy, independent of quadcast): each pixel ray of the view's own projection walked
# cell by cell through the samples vtkRTAnalyticSource gives, and in each cell its first crossing of
# ISO found by sampling the trilinear interpolant and bisection.
#   - trilinear: coverage identical except where a ray moved by 0.05 pixels changes the outcome
#     (outlines, grazing rays); the window depth in ParaView's depth buffer within 2e-6 of the
#     exact crossing's;
#   - QSS and S31 (smooth splines of the same samples, not the same surface: where the trilinear
#     surface has a thin bridge the splines may not, and the ray goes on): along the ray, the
#     surface within 0.1 voxel (median) and 0.35 voxel (95th percentile) of the trilinear one
#     wherever both are hit away from outlines, and fewer than 5% of the pixels hit by one only;
#   - the plane and the surface composed by depth: pixels whose nearest hit is the plane show its
#     colour (trilinear only: there the exact surface is known).
# With REFERENCE_PREFIX (the 1-rank run's OUT_PREFIX) the composited image must equal that run's:
# coverage identical and colours within 1 level -- the pieces join without a seam. With
# --no-ghosts (the representation asks for no ghost level) the image must differ from that run's:
# the seam the test is there to find shows (a check that the comparison can fail).
# Writes OUT_PREFIX.png, OUT_PREFIX_rgb.npy and (one rank) OUT_PREFIX_depth.npy. Exit status 1 on any failure (a RuntimeError).
import os
import sys

import numpy as np
from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
import vtk
from vtk.util import numpy_support

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pvcheck  # noqa: E402

args = sys.argv[1:]
scheme = "qss"
if "--scheme" in args:
    k = args.index("--scheme")
    scheme = args[k + 1]
    del args[k:k + 2]
no_ghosts = "--no-ghosts" in args
args = [a for a in args if a != "--no-ghosts"]
plugin, out = args[0], args[1]
reference = args[2] if len(args) > 2 else None
LoadPlugin(plugin, remote=False, ns=globals())

W, H = 320, 240
EXT = 16
ISO = 190.0
ZSCALE = 1.5
PLANE_Y = 2.5

wavelet = Wavelet(WholeExtent=[-EXT, EXT, -EXT, EXT, -EXT, EXT])
ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
if ranks > 1:
    ids = ProcessIdScalars(Input=wavelet)
    ids.UpdatePipeline()
    lo, hi = ids.PointData["ProcessId"].GetRange()
    print(f"isosurface: {ranks} ranks, samples on ranks {lo:.0f}..{hi:.0f}")
    if hi < 1:
        raise RuntimeError("the image was not split over the ranks")

view = pvcheck.make_view(W, H)
surface = Show(wavelet, view)
surface.SetRepresentationType("Spline Isosurface")
surface.SplineArray = ["POINTS", "RTData"]
surface.SplineIsovalue = ISO
surface.SplineScheme = {"qss": "QSS", "s31": "S31", "trilinear": "Trilinear"}[scheme]
surface.SplineGhostLevels = 0 if no_ghosts else 1
surface.Scale = [1, 1, ZSCALE]
surface.DiffuseColor = [0.9, 0.8, 0.6]
plane = Plane(Origin=[-20, PLANE_Y, -30], Point1=[20, PLANE_Y, -30], Point2=[-20, PLANE_Y, 30])
pvcheck.show_green(plane, view)
camera = pvcheck.look_from(view, (52, -64, 40), (0, 0, 0))
depth = None
if ranks == 1:
    depth = pvcheck.depth_buffer(view, W, H)
    np.save(out + "_depth.npy", depth)
rgb, covered = pvcheck.screenshot(view, out, W, H)
plane_colour = pvcheck.plane_coloured(rgb)
failures = []

if ranks == 1:
    # The samples, straight from VTK's source (i fastest), and the pixel rays of the view.
    src = vtk.vtkRTAnalyticSource()
    src.SetWholeExtent(-EXT, EXT, -EXT, EXT, -EXT, EXT)
    src.Update()
    n = 2 * EXT + 1
    f = numpy_support.vtk_to_numpy(src.GetOutput().GetPointData().GetArray("RTData")).astype(np.float64).reshape(n, n, n)  # [k, j, i]
    cam = pvcheck.CameraRays(camera, W, H)
    eye = cam.eye
    rays = cam.directions

    scale = np.array([1.0, 1.0, ZSCALE])

    def trilinear_hits(d):
        """Nearest t > 0 of eye + t d on the isosurface of the trilinear interpolant (inf: none)."""
        d = d.reshape(-1, 3)
        o = eye / scale + EXT  # index space: sample (i, j, k) at i - EXT, j - EXT, ZSCALE (k - EXT)
        di = d / scale
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / di
            t_a = (0 - o) * inv
            t_b = (n - 1 - o) * inv
        t_in = np.nanmax(np.minimum(t_a, t_b), axis=1).clip(min=0)
        t_out = np.nanmin(np.maximum(t_a, t_b), axis=1)
        best = np.full(len(d), np.inf)
        active = t_in < t_out
        p = o + di * t_in[:, None]
        cell = np.clip(np.floor(p + 1e-9 * np.sign(di)), 0, n - 2).astype(np.int64)
        step = np.where(di > 0, 1, -1)
        with np.errstate(divide="ignore", invalid="ignore"):
            t_next = np.where(di != 0, (cell + (step > 0) - o) * inv, np.inf)
            t_delta = np.where(di != 0, np.abs(inv), np.inf)
        t0 = t_in.copy()

        def value(idx, c, t):
            """The interpolant minus ISO at parameters t ((N,) or (N, S)) of rays idx in cells c."""
            tt = t if t.ndim == 2 else t[:, None]
            q = o + di[idx][:, None, :] * tt[..., None] - c[:, None, :]
            u, v, w = q[..., 0], q[..., 1], q[..., 2]
            ci, cj, ck = c[:, 0, None], c[:, 1, None], c[:, 2, None]
            s = 0.0
            for a in (0, 1):
                for b in (0, 1):
                    for e in (0, 1):
                        s = s + f[ck + e, cj + b, ci + a] * (u if a else 1 - u) * (v if b else 1 - v) * (w if e else 1 - w)
            s = s - ISO
            return s if t.ndim == 2 else s[:, 0]

        samples = np.linspace(0.0, 1.0, 17)
        while active.any():
            idx = np.nonzero(active)[0]
            c = cell[idx]
            t1 = np.minimum(t_next[idx].min(axis=1), t_out[idx])
            ts = t0[idx, None] + (t1 - t0[idx])[:, None] * samples[None, :]
            g = value(idx, c, ts)
            sign_change = (g[:, :-1] <= 0) != (g[:, 1:] <= 0)
            has = sign_change.any(axis=1)
            if has.any():
                first = sign_change.argmax(axis=1)
                hi_i = idx[has]
                lo_t = ts[has, first[has]]
                hi_t = ts[has, first[has] + 1]
                lo_g = g[has, first[has]]
                ch = c[has]
                for _ in range(40):
                    mid = 0.5 * (lo_t + hi_t)
                    gm = value(hi_i, ch, mid)
                    same = (gm <= 0) == (lo_g <= 0)
                    lo_t = np.where(same, mid, lo_t)
                    lo_g = np.where(same, gm, lo_g)
                    hi_t = np.where(same, hi_t, mid)
                best[hi_i] = 0.5 * (lo_t + hi_t)
                active[hi_i] = False
            # next cell for the rays still walking
            go = idx[~has]
            axis = t_next[go].argmin(axis=1)
            t0[go] = t_next[go, axis]
            cell[go, axis] += step[go, axis]
            t_next[go, axis] += t_delta[go, axis]
            out_of = (cell[go, axis] < 0) | (cell[go, axis] > n - 2) | (t0[go] >= t_out[go])
            active[go[out_of]] = False
        return best.reshape(H, W)

    dirs = rays()
    t_iso = trilinear_hits(dirs)
    rim = np.zeros((H, W), dtype=bool)
    for dx, dy in ((0.05, 0), (-0.05, 0), (0, 0.05), (0, -0.05)):
        rim |= np.isfinite(trilinear_hits(rays(dx, dy))) != np.isfinite(t_iso)

    def window_depth(t):
        return cam.window_depth(dirs, t)

    def plane_hits(d):
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(np.abs(d[..., 1]) > 0, (PLANE_Y - eye[1]) / d[..., 1], np.inf)
        pp = eye + d * np.where(np.isfinite(t), t, 0)[..., None]
        on_plane = np.isfinite(t) & (t > 0) & (np.abs(pp[..., 0]) <= 20) & (np.abs(pp[..., 2]) <= 30)
        return np.where(on_plane, t, np.inf)

    t_plane = plane_hits(dirs)
    for dx, dy in ((0.05, 0), (-0.05, 0), (0, 0.05), (0, -0.05)):
        rim |= np.isfinite(plane_hits(rays(dx, dy))) != np.isfinite(t_plane)  # (the plane's edges too)
    z_iso, z_plane = window_depth(t_iso), window_depth(t_plane)
    iso_front = np.isfinite(t_iso) & (t_iso < t_plane)
    plane_front = np.isfinite(t_plane) & (t_plane < t_iso)
    with np.errstate(invalid="ignore"):
        tie = np.abs(t_iso - t_plane) < 1e-3
    print(f"isosurface: {scheme}, {W}x{H}; covered {covered.sum()} px; exact trilinear surface in front {iso_front.sum()}, "
          f"plane in front {plane_front.sum()}, outline px {rim.sum()}")
    if iso_front.sum() < 5000 or plane_front.sum() < 2000:
        failures.append("the scene does not show both the surface and the plane")
    # Where the drawn surface is: the depth buffer's window depth turned back into a point and a
    # distance from the eye.
    p_drawn = cam.points(depth)
    t_drawn = np.linalg.norm(p_drawn - eye, axis=-1)
    drawn_iso = covered & ~plane_colour & (depth < 1)
    if scheme == "trilinear":
        # The renderer clips each cell's ray grown by 1/32 of the pixel's footprint (its seal
        # against cracks between cells, quadcast/spline/render.hpp `clip_pad`): where a ray
        # grazes the surface at a cell face, the cell's interpolant continued that far beyond the
        # face may cross ISO where the neighbour's does not. Pixels whose drawn or exact hit lies
        # within twice that pad of a cell face are counted apart ("face pixels"); there only a
        # drawn hit within the pad of a face is accepted. Everywhere else: exact.
        pad = 2 * (np.radians(30) / H / 32) * np.where(np.isfinite(t_iso), t_iso, t_drawn)

        def face_distance(pw):
            ip = pw / scale + EXT
            return (np.abs(ip - np.round(ip)) * scale).min(axis=-1)  # world units to the nearest cell face plane

        p_exact = eye + dirs * np.where(np.isfinite(t_iso), t_iso, 0)[..., None]
        drawn_at_face = drawn_iso & (face_distance(p_drawn) < pad)
        face = drawn_at_face | (np.isfinite(t_iso) & (face_distance(p_exact) < pad))
        exact_covered = np.isfinite(t_iso) | np.isfinite(t_plane)
        coverage_diff = (covered != exact_covered) & ~rim & ~drawn_at_face
        err = np.abs(depth - z_iso)
        checked = iso_front & ~rim & ~tie & covered & ~face
        off_face = drawn_iso & ~face & ~rim & (err > 2e-6)
        print(f"isosurface: coverage differences away from outlines {coverage_diff.sum()}; "
              f"depth max error {err[checked].max():.3g} over {checked.sum()} px (median {np.median(err[checked]):.2g}); "
              f"face pixels {face.sum()}, of them drawn nearer than the exact surface {(face & (depth < z_iso - 2e-6)).sum()}, "
              f"by more than 0.1 voxel {(face & drawn_iso & (t_drawn < np.where(np.isfinite(t_iso), t_iso, np.inf) - 0.1)).sum()}")
        for j, i in list(zip(*np.nonzero(coverage_diff | off_face)))[:10]:
            print(f"  pixel ({i}, {j}): depth {depth[j, i]:.7f}, exact surface {z_iso[j, i]:.7f}, plane {z_plane[j, i]:.7f}, rgb {rgb[j, i]}")
        if coverage_diff.any():
            failures.append(f"{coverage_diff.sum()} pixels covered differently from the exact trilinear isosurface")
        if err[checked].max() > 2e-6:
            failures.append(f"depth off by {err[checked].max():.3g}")
        if off_face.any():
            failures.append(f"{off_face.sum()} pixels drawn off the exact surface away from cell faces")
        wrong_plane = plane_front & ~tie & ~rim & ~plane_colour & ~drawn_at_face
        wrong_iso = iso_front & ~tie & ~rim & plane_colour
        print(f"isosurface: plane pixels not plane-coloured {wrong_plane.sum()}, surface pixels plane-coloured {wrong_iso.sum()}")
        if wrong_plane.any() or wrong_iso.any():
            failures.append("the surface and the plane are not composed by depth")
    else:
        # The spline's surface against the trilinear one: distance along the ray, in voxels.
        both = drawn_iso & iso_front & ~rim & ~tie
        gap = np.abs(t_drawn - t_iso)[both]
        differ = (drawn_iso != iso_front) & ~rim & ~tie
        q50, q95 = np.percentile(gap, [50, 95]) if gap.size else (np.inf, np.inf)
        print(f"isosurface: {scheme} surface against the trilinear one over {both.sum()} px: distance median {q50:.3g}, "
              f"95th percentile {q95:.3g}, max {gap.max() if gap.size else 0:.3g} voxels; pixels hit by one only {differ.sum()}")
        if both.sum() < 5000:
            failures.append("too few pixels where both surfaces are hit")
        elif q50 > 0.1 or q95 > 0.35:
            failures.append(f"the {scheme} surface lies {q50:.3g} (median) / {q95:.3g} (95th percentile) voxels from the trilinear one")
        if differ.sum() > 0.05 * iso_front.sum():
            failures.append(f"{differ.sum()} pixels hit by only one of the {scheme} and trilinear surfaces")

if reference:
    cov, dc, diff = pvcheck.compare_with_reference(reference, rgb, covered, "isosurface")
    if no_ghosts:
        if cov + (diff > 8).sum() < 20:
            failures.append("without ghost levels the split image still equals the whole one: the comparison cannot see a seam")
    elif cov or dc > 1:
        failures.append("the image differs from the reference run's")

for f_ in failures:
    print("FAIL:", f_)
Delete(view)  # (before the interpreter's exit: see glyphs.py)
del view
if failures:
    raise RuntimeError("; ".join(failures))
