# What the plugin's pvbatch tests share: the view they draw in, its screenshot and depth buffer,
# the exact pixel rays of its camera, and the comparison with a reference run's image.
import numpy as np
from paraview.simple import CreateView, SaveScreenshot
import vtk
from vtk.util import numpy_support

BACKGROUND = (255, 0, 255)  # magenta: no shaded surface, sphere or plane colour is


def make_view(width, height):
    """A render view of the given size: magenta background, no orientation axes, no FXAA (it
    would blend neighbouring pixels' colours)."""
    view = CreateView("RenderView")
    view.ViewSize = [width, height]
    view.OrientationAxesVisibility = 0
    view.Background = [c / 255 for c in BACKGROUND]
    view.UseColorPaletteForBackground = 0
    view.UseFXAA = 0
    return view


def depth_buffer(view, width, height):
    """The view's window depths, rows bottom first (one rank: under MPI the window does not hold
    IceT's composited depth)."""
    zbuf = vtk.vtkFloatArray()
    view.GetRenderWindow().GetZbufferData(0, 0, width - 1, height - 1, zbuf)
    return numpy_support.vtk_to_numpy(zbuf).reshape(height, width).astype(np.float64)


def screenshot(view, out, width, height):
    """Saves OUT.png (IceT's composited image under MPI) and OUT_rgb.npy; returns the RGB image
    (rows bottom first, int32) and the covered mask (not the background)."""
    SaveScreenshot(out + ".png", view, ImageResolution=[width, height])
    png = vtk.vtkPNGReader()
    png.SetFileName(out + ".png")
    png.Update()
    rgb = numpy_support.vtk_to_numpy(png.GetOutput().GetPointData().GetScalars()).reshape(height, width, -1)[:, :, :3].astype(np.int32)
    np.save(out + "_rgb.npy", rgb)
    return rgb, covered_of(rgb)


def covered_of(rgb):
    return ~((rgb[..., 0] == BACKGROUND[0]) & (rgb[..., 1] == BACKGROUND[1]) & (rgb[..., 2] == BACKGROUND[2]))


def plane_coloured(rgb):
    """Pixels of the tests' green plane (no shaded surface or lookup-table colour is that green)."""
    return rgb[..., 1] - np.maximum(rgb[..., 0], rgb[..., 2]) > 100


class CameraRays:
    """The exact pixel rays of a view's camera, from its own projection matrix, in double."""

    def __init__(self, camera, width, height):
        self.width, self.height = width, height
        m = camera.GetCompositeProjectionTransformMatrix(width / height, -1, 1)
        self.M = np.array([[m.GetElement(r, c) for c in range(4)] for r in range(4)])
        self.Minv = np.linalg.inv(self.M)
        self.eye = np.array(camera.GetPosition())

    def ndc(self, dx=0.0, dy=0.0):
        xs = (np.arange(self.width) + 0.5 + dx) / self.width * 2 - 1
        ys = (np.arange(self.height) + 0.5 + dy) / self.height * 2 - 1
        return np.meshgrid(xs, ys)

    def directions(self, dx=0.0, dy=0.0):
        """Unit directions through the pixel centres moved by (dx, dy) pixels, H x W x 3."""
        X, Y = self.ndc(dx, dy)
        p = np.stack([X, Y, np.ones_like(X), np.ones_like(X)], axis=-1) @ self.Minv.T
        d = p[..., :3] / p[..., 3:4] - self.eye
        return d / np.linalg.norm(d, axis=-1, keepdims=True)

    def window_depth(self, dirs, t):
        """The window depth of eye + t dirs (1 where t is not finite)."""
        p = self.eye + dirs * np.where(np.isfinite(t), t, 1)[..., None]
        h = np.concatenate([p, np.ones(p.shape[:-1] + (1,))], axis=-1) @ self.M.T
        return np.where(np.isfinite(t), (h[..., 2] / h[..., 3] + 1) / 2, 1.0)

    def points(self, depth):
        """The world points whose window depth the depth buffer holds, H x W x 3."""
        X, Y = self.ndc()
        p = np.stack([X, Y, 2 * depth - 1, np.ones_like(X)], axis=-1) @ self.Minv.T
        return p[..., :3] / p[..., 3:4]


def compare_with_reference(reference, rgb, covered, tag):
    """Coverage and colour differences against the reference run's OUT_rgb.npy; returns (the
    number of coverage differences, the largest colour difference, per-pixel differences)."""
    ref_rgb = np.load(reference + "_rgb.npy")
    ref_covered = covered_of(ref_rgb)
    cov = ref_covered != covered
    both = ref_covered & covered
    diff = np.abs(ref_rgb - rgb).max(axis=-1)
    dc = diff[both].max() if both.any() else 0
    print(f"{tag}: against {reference}: coverage differences {cov.sum()}, colour max difference {dc}, "
          f"pixels differing by more than 1 level {(diff[both] > 1).sum()}")
    return cov.sum(), dc, np.where(both, diff, 0)


def show_green(source, view):
    """Shows `source` (the tests' opaque plane) in plain green, without scalar colouring."""
    from paraview.simple import Show
    display = Show(source, view)
    display.DiffuseColor = [0, 1, 0]
    display.AmbientColor = [0, 1, 0]
    display.ColorArrayName = ["POINTS", ""]
    return display


def look_from(view, position, focal_point, view_angle=30):
    """Renders once (the first render resets the camera to the data), then sets the camera (z up,
    perspective) and renders again; returns the camera."""
    from paraview.simple import Render
    Render(view)
    camera = view.GetActiveCamera()
    camera.SetPosition(*position)
    camera.SetFocalPoint(*focal_point)
    camera.SetViewUp(0, 0, 1)
    camera.SetViewAngle(view_angle)
    view.CameraParallelProjection = 0
    Render(view)
    return camera


def distribute(source, ranks, tag, what):
    """Under MPI: the data set's cells redistributed over the ranks (RedistributeDataSet), checked
    to reach more than one rank. One rank: `source` as it is."""
    from paraview.simple import ProcessIdScalars, RedistributeDataSet
    if ranks <= 1:
        return source
    source = RedistributeDataSet(Input=source)
    ids = ProcessIdScalars(Input=source)
    ids.UpdatePipeline()
    lo, hi = ids.PointData["ProcessId"].GetRange()
    print(f"{tag}: {ranks} ranks, {what} on ranks {lo:.0f}..{hi:.0f}")
    if hi < 1:
        raise RuntimeError(f"the {what} were not distributed over the ranks")
    return source
