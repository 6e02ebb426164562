#!/usr/bin/python3
"""tools/bench_vtk.py -- quadcast against VTK 9 on the same scenes, measured in one run.

    make bench-vtk                      # installs python3-vtk9, python3-numpy, xvfb; runs this
    tools/bench_vtk.py --quadcast build/tools/quadcast [--cases spheres:10000,sticks:50000,skull:qss]
                       [--rounds 5] [--frames 5] [--orbit DEG] [--width 1024 --height 768] [--out DIR] [--data DIR]

The scenes are those of `quadcast bench spheres` and `bench sticks`: N random spheres in the unit
cube of radius 0.3 N^(-1/3) (written by tools/sphere_scene.sh; VTK draws the numbers of that file),
or N capped cylinders of length 0.05 and radius 0.005 with uniform directions; a 30 degree perspective camera from (0.5, 0.5, 3) looking at (0.5, 0.5, 0.5); one
grey colour; the default headlight. Each scene is a quadcast JSON scene, and its numbers go to VTK
as a NumPy file (VTK reads binary arrays, so its loading is not slowed by JSON).

quadcast: `quadcast render SCENE.json --frames F` (its default options: back-face culling, and the
occlusion cull pass where the frame's expected overlap reaches 3), the median of F frames after a
warm-up, each frame ending in glFinish.
VTK: vtkOpenGLSphereMapper / vtkOpenGLStickMapper (VTK's impostor mappers, the ones
vtkMoleculeMapper uses) in an offscreen vtkRenderWindow under Xvfb, the median of F
Render() + WaitForCompletion() (glFinish) after a warm-up frame. Both run on the same Mesa
llvmpipe. Rounds alternate the order (quadcast, VTK; VTK, quadcast; ...) so that load from other
processes hits both alike; printed are the medians over the rounds and the ratio of the medians
(> 1: quadcast faster), with the range of the per-round ratios.

The isosurface cases (skull:qss, skull:s31, skull:trilinear): CGAL's skull_2.9.inr (64^3 floats,
`make data` fetches it into build/data) at isovalue 2.9, from the skull demo's camera (36 degrees),
one colour, the default headlight. quadcast draws the scheme's isosurface with its GL isosurface
renderer (default options, forward shading); VTK extracts the same volume's isosurface with
vtkFlyingEdges3D (normals on) once and draws the triangle mesh with vtkPolyDataMapper (its frames
redraw the mesh; the extraction is in its time to the first image).

With --orbit DEG the camera moves: each timed frame's camera orbits the target by DEG degrees more
around the up vector (quadcast `render --orbit DEG`; VTK's vtkCamera::Azimuth(DEG) and
ResetCameraClippingRange before each Render()), so no frame sees the view of the one before.

Time to first image: the wall time of a whole process that reads the scene, draws one frame and
writes a PNG (quadcast render without --frames; the VTK worker in --first mode, its Python and VTK
start-up included), and its peak resident memory (getrusage of the child).

Sanity check beside the times: the share of pixels each PNG covers (not the background); the two
renderers draw the same geometry, so the shares agree to the silhouettes' rounding.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def make_scene(kind, n, seed, scene, data_dir):
    """Writes the quadcast scene file `scene` and returns the arrays VTK draws from it."""
    import numpy as np
    if kind == "spheres":
        # The scene of `bench spheres` as tools/sphere_scene.sh writes it; VTK gets its numbers.
        with open(scene, "w") as f:
            subprocess.run(["sh", os.path.join(HERE, "sphere_scene.sh"), str(n), str(seed)], stdout=f, check=True)
        with open(scene) as f:
            objects = json.load(f)["objects"]
        return {"centers": np.array([o["sphere"]["center"] for o in objects]), "radius": objects[0]["sphere"]["radius"]}
    if kind == "sticks":
        rng = np.random.default_rng(seed)
        dirs = []
        while sum(len(d) for d in dirs) < n:
            d = rng.uniform(-1.0, 1.0, (2 * n, 3))
            l = np.linalg.norm(d, axis=1)
            keep = (l > 0.05) & (l <= 1.0)  # uniform directions
            dirs.append(d[keep] / l[keep, None])
        d = np.concatenate(dirs)[:n]
        c = rng.random((n, 3))
        p0, p1 = np.round(c - 0.025 * d, 6), np.round(c + 0.025 * d, 6)
        with open(scene, "w") as f:
            f.write('{"camera": {"eye": [0.5, 0.5, 3], "target": [0.5, 0.5, 0.5], "fov_y": 30},\n "objects": [\n')
            f.write(",\n".join('{"cylinder":{"p0":[%.6f,%.6f,%.6f],"p1":[%.6f,%.6f,%.6f],"radius":0.005,"caps":true}}' % (*a, *b)
                               for a, b in zip(p0, p1)))
            f.write("\n]}\n")
        return {"p0": p0, "p1": p1, "radius": 0.005}
    if kind == "skull":
        if n not in ("qss", "s31", "trilinear"):
            raise SystemExit(f"bench_vtk.py: skull:{n}: the scheme must be qss, s31 or trilinear")
        volume = os.path.abspath(os.path.join(data_dir, "skull_2.9.inr"))
        if not os.path.exists(volume):
            raise SystemExit(f"bench_vtk.py: {volume} not found (make data)")
        with open(scene, "w") as f:
            json.dump({"camera": SKULL_CAMERA, "objects": [{"volume": volume, "iso": 2.9, "scheme": n, "color": SKULL_COLOR}]}, f)
        return {"volume": volume}
    raise SystemExit(f"bench_vtk.py: unknown case kind '{kind}' (spheres, sticks or skull)")


# The skull demo's camera (examples/demo/skull_s31.json) and a bone colour, for both renderers.
SKULL_CAMERA = {"eye": [560.0, -260.0, 180.0], "target": [126.0, 126.0, 110.0], "up": [0.0, 0.0, 1.0], "fov_y": 36}
SKULL_COLOR = [0.92, 0.88, 0.78]


def read_inr(path):
    """An INR volume of floats (the skull's): its samples (z, y, x) and spacing."""
    import numpy as np
    with open(path, "rb") as f:
        raw = f.read()
    end = raw.index(b"##}\n") + 4
    fields = dict(l.split("=", 1) for l in raw[:end].decode("ascii").splitlines() if "=" in l)
    if fields.get("TYPE") != "float" or fields.get("PIXSIZE") != "32 bits":
        raise SystemExit(f"bench_vtk.py: {path}: only 32-bit float INR volumes")
    nx, ny, nz = (int(fields[k]) for k in ("XDIM", "YDIM", "ZDIM"))
    dtype = "<f4" if fields.get("CPU", "decm") in ("decm", "pc", "alpha") else ">f4"
    a = np.frombuffer(raw, dtype=dtype, count=nx * ny * nz, offset=end).reshape(nz, ny, nx)
    return a, (float(fields["VX"]), float(fields["VY"]), float(fields["VZ"]))


def vtk_worker(args):
    """One VTK process: load the arrays, draw, time frames or the first image."""
    t_start = time.perf_counter()
    import numpy as np
    import vtk
    from vtkmodules.util import numpy_support as ns
    z = np.load(args.vtk_worker)
    kind = str(z["kind"])
    pd = vtk.vtkPolyData()
    pts = vtk.vtkPoints()
    if kind == "skull":
        samples, spacing = read_inr(str(z["volume"]))
        image = vtk.vtkImageData()
        image.SetDimensions(samples.shape[2], samples.shape[1], samples.shape[0])
        image.SetSpacing(*spacing)
        image.SetOrigin(0.0, 0.0, 0.0)
        image.GetPointData().SetScalars(ns.numpy_to_vtk(np.ascontiguousarray(samples, dtype=np.float32).ravel(), deep=True))
        fe = vtk.vtkFlyingEdges3D()
        fe.SetInputData(image)
        fe.SetValue(0, 2.9)
        fe.ComputeNormalsOn()
        fe.ComputeScalarsOff()
        fe.Update()
        mapper = vtk.vtkPolyDataMapper()
        mapper.SetInputData(fe.GetOutput())
        mapper.ScalarVisibilityOff()
    elif kind == "spheres":
        centers = np.ascontiguousarray(z["centers"], dtype=np.float32)
        pts.SetData(ns.numpy_to_vtk(centers, deep=True))
        mapper = vtk.vtkOpenGLSphereMapper()
        mapper.SetRadius(float(z["radius"]))
        mapper.ScalarVisibilityOff()
    else:
        p0, p1 = z["p0"].astype(np.float64), z["p1"].astype(np.float64)
        centers = np.ascontiguousarray((p0 + p1) * 0.5, dtype=np.float32)
        axis = p1 - p0
        length = np.linalg.norm(axis, axis=1)
        pts.SetData(ns.numpy_to_vtk(centers, deep=True))
        # vtkOpenGLStickMapper, as vtkMoleculeMapper feeds it: per point (and vertex cell) the
        # centre, a unit orientation, a 3-component scale (length, radius, radius), a selection id
        # and direct RGBA colours (without colours it draws nothing).
        def add(a, name, vtk_type=None):
            x = ns.numpy_to_vtk(a, deep=True, array_type=vtk_type) if vtk_type else ns.numpy_to_vtk(a, deep=True)
            x.SetName(name)
            pd.GetPointData().AddArray(x)
            return x
        add(np.ascontiguousarray(axis / length[:, None], dtype=np.float32), "orient")
        r = float(z["radius"])
        add(np.ascontiguousarray(np.stack([length, np.full_like(length, r), np.full_like(length, r)], axis=1), dtype=np.float32), "scale")
        add(np.zeros(len(centers), dtype=np.uint32), "selection", vtk.VTK_UNSIGNED_INT)
        pd.GetPointData().SetScalars(add(np.full((len(centers), 4), (204, 204, 204, 255), dtype=np.uint8), "colors", vtk.VTK_UNSIGNED_CHAR))
        mapper = vtk.vtkOpenGLStickMapper()
        mapper.SetOrientationArray("orient")
        mapper.SetScaleArray("scale")
        mapper.SetSelectionIdArray("selection")
        mapper.SetColorModeToDirectScalars()
        mapper.ScalarVisibilityOn()
    if kind != "skull":
        pd.SetPoints(pts)
        # one vertex cell per point (the mappers draw the points of the vertex cells)
        n = pts.GetNumberOfPoints()
        conn = np.empty(2 * n, dtype=np.int64)
        conn[0::2] = 1
        conn[1::2] = np.arange(n)
        verts = vtk.vtkCellArray()
        verts.SetCells(n, ns.numpy_to_vtkIdTypeArray(conn, deep=True))
        pd.SetVerts(verts)
        mapper.SetInputData(pd)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(*(SKULL_COLOR if kind == "skull" else (0.8, 0.8, 0.8)))
    ren = vtk.vtkRenderer()
    ren.AddActor(actor)
    ren.SetBackground(1.0, 1.0, 1.0)
    cam = ren.GetActiveCamera()
    if kind == "skull":
        cam.SetPosition(*SKULL_CAMERA["eye"])
        cam.SetFocalPoint(*SKULL_CAMERA["target"])
        cam.SetViewUp(*SKULL_CAMERA["up"])
        cam.SetViewAngle(SKULL_CAMERA["fov_y"])
    else:
        cam.SetPosition(0.5, 0.5, 3.0)
        cam.SetFocalPoint(0.5, 0.5, 0.5)
        cam.SetViewUp(0.0, 1.0, 0.0)
        cam.SetViewAngle(30.0)
    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetSize(args.width, args.height)
    win.AddRenderer(ren)
    ren.ResetCameraClippingRange()
    win.Render()
    win.WaitForCompletion()
    if args.png:
        w2i = vtk.vtkWindowToImageFilter()
        w2i.SetInput(win)
        w2i.ReadFrontBufferOff()
        w2i.Update()
        wr = vtk.vtkPNGWriter()
        wr.SetFileName(args.png)
        wr.SetInputConnection(w2i.GetOutputPort())
        wr.Write()
    if args.frames == 0:
        print("first %.1f ms" % ((time.perf_counter() - t_start) * 1e3))
        return
    ms = []
    for _ in range(args.frames):
        t0 = time.perf_counter()
        if args.orbit:
            cam.Azimuth(args.orbit)
            ren.ResetCameraClippingRange()
        win.Render()
        win.WaitForCompletion()
        ms.append((time.perf_counter() - t0) * 1e3)
    print("median %.3f ms" % statistics.median(ms))


def run(cmd, env):
    """Runs a child to completion and returns its standard output."""
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    if p.returncode != 0:
        sys.stderr.write(p.stderr)
        raise SystemExit(f"bench_vtk.py: {' '.join(cmd)} failed with status {p.returncode}")
    return p.stdout


def first_image(cmd, env):
    """Wall time and peak RSS (MB) of one whole process, measured by a fresh helper process."""
    probe = ("import resource,subprocess,sys,time;t=time.perf_counter();"
             "p=subprocess.run(sys.argv[1:],stdout=subprocess.DEVNULL,stderr=subprocess.PIPE);"
             "w=time.perf_counter()-t;"
             "sys.stderr.write(p.stderr.decode()) if p.returncode else None;"
             "print(p.returncode,w,resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss/1024.0)")
    out = subprocess.run([sys.executable, "-c", probe] + cmd, stdout=subprocess.PIPE, text=True, env=env).stdout.split()
    if not out or out[0] != "0":
        raise SystemExit(f"bench_vtk.py: {' '.join(cmd)} failed")
    return float(out[1]), float(out[2])


def covered_share(png):
    import vtk
    from vtkmodules.util import numpy_support as ns
    r = vtk.vtkPNGReader()
    r.SetFileName(png)
    r.Update()
    img = r.GetOutput()
    a = ns.vtk_to_numpy(img.GetPointData().GetScalars())
    rgb = a[:, :3].astype(int)
    return float(((rgb != 255).any(axis=1)).mean())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quadcast", default=os.path.join(HERE, "..", "build", "tools", "quadcast"))
    ap.add_argument("--cases", default="spheres:10000,spheres:100000,spheres:1000000,sticks:50000")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--frames", type=int, default=5)
    ap.add_argument("--orbit", type=float, default=0.0, help="degrees the camera orbits the target per timed frame (0: it stays)")
    ap.add_argument("--width", type=int, default=1024)
    ap.add_argument("--height", type=int, default=768)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", default=None, help="keep scenes and PNGs here (default: a temporary directory)")
    ap.add_argument("--data", default=os.path.join(HERE, "..", "build", "data"), help="where `make data` put CGAL's skull_2.9.inr")
    ap.add_argument("--vtk-worker", help=argparse.SUPPRESS)
    ap.add_argument("--png", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.vtk_worker:
        return vtk_worker(args)

    if not os.path.exists(args.quadcast):
        raise SystemExit(f"bench_vtk.py: no quadcast program at {args.quadcast} (make build, or --quadcast PATH)")
    import numpy as np
    import vtk
    out = args.out or tempfile.mkdtemp(prefix="quadcast-vtk-")
    os.makedirs(out, exist_ok=True)
    # VTK 9.1 in Debian opens an X display even offscreen: one Xvfb for the whole run.
    xvfb = None
    env = dict(os.environ)
    if not env.get("DISPLAY"):
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        from with_xvfb import start_xvfb, stop_xvfb
        try:
            xvfb, env["DISPLAY"] = start_xvfb()
        except RuntimeError as e:
            raise SystemExit(f"bench_vtk.py: {e}")
    me = [sys.executable, os.path.abspath(__file__)]
    size = ["--width", str(args.width), "--height", str(args.height)]
    print(f"quadcast against VTK {vtk.vtkVersion.GetVTKVersion()}: {args.width}x{args.height}, 30 degree perspective from (0.5, 0.5, 3); "
          f"medians of {args.frames} frames per process, {args.rounds} rounds, order alternating; ratio > 1: quadcast faster" +
          (f"; the camera orbiting the target by {args.orbit:g} degrees a frame" if args.orbit else ""))
    print("%-16s %10s %10s %7s %13s | %9s %9s %7s | %8s %8s | %7s %7s" % (
        "case", "quadcast", "VTK", "ratio", "round ratios", "qc first", "VTK first", "ratio", "qc MB", "VTK MB", "qc cov", "VTK cov"))
    try:
        for case in args.cases.split(","):
            kind, n = case.split(":")
            n = n if kind == "skull" else int(n)
            scene = os.path.join(out, f"{kind}_{n}.json")
            arrays = os.path.join(out, f"{kind}_{n}.npz")
            data = make_scene(kind, n, args.seed, scene, args.data)
            np.savez(arrays, kind=kind, **data)
            qpng = os.path.join(out, f"{kind}_{n}_quadcast.png")
            vpng = os.path.join(out, f"{kind}_{n}_vtk.png")
            qcmd = [args.quadcast, "render", scene, "-o", qpng] + size
            vcmd = me + ["--vtk-worker", arrays, "--png", vpng] + size
            q_ms, v_ms = [], []
            for r in range(args.rounds):
                order = [0, 1] if r % 2 == 0 else [1, 0]
                for who in order:
                    if who == 0:
                        s = run(qcmd + ["--frames", str(args.frames)] + (["--orbit", str(args.orbit)] if args.orbit else []), env)
                        m = re.search(r"median frame ([0-9.]+) ms", s)
                        q_ms.append(float(m.group(1)))
                    else:
                        s = run(vcmd + ["--frames", str(args.frames), "--orbit", str(args.orbit)], env)
                        m = re.search(r"median ([0-9.]+) ms", s)
                        v_ms.append(float(m.group(1)))
            qf, qm, vf, vm = [], [], [], []
            for r in range(max(1, args.rounds // 2)):
                for who in ([0, 1] if r % 2 == 0 else [1, 0]):
                    if who == 0:
                        w, m = first_image(qcmd, env)
                        qf.append(w), qm.append(m)
                    else:
                        w, m = first_image(vcmd + ["--frames", "0"], env)
                        vf.append(w), vm.append(m)
            ratios = [v / q for q, v in zip(q_ms, v_ms)]
            qmed, vmed = statistics.median(q_ms), statistics.median(v_ms)
            print("%-16s %8.1f ms %7.1f ms %6.2fx %5.2f-%5.2fx | %7.2f s %7.2f s %6.2fx | %8.0f %8.0f | %6.1f%% %6.1f%%" % (
                f"{kind} {n}", qmed, vmed, vmed / qmed, min(ratios), max(ratios),
                statistics.median(qf), statistics.median(vf), statistics.median(vf) / statistics.median(qf),
                max(qm), max(vm), 100 * covered_share(qpng), 100 * covered_share(vpng)), flush=True)
    finally:
        if xvfb:
            stop_xvfb(xvfb)
    print(f"scenes and PNGs in {out}")


if __name__ == "__main__":
    main()
