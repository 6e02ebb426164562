// tests/slim/against_mesh.hpp -- SLIM surfaces of closed OFF meshes seen next to the meshes themselves (test helpers, CPU and GL tests)
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "quadcast/render/slim_cpu_renderer.hpp"
#include "quadcast/scene/off.hpp"
#include "quadcast/scene/scene_render.hpp"
#include "quadcast/slim/build.hpp"
#include "quadcast/slim/scene_loader.hpp"
#include "slim/reference_geometry.hpp"

namespace quadcast::slim::testing {

/// A closed OFF mesh, its oriented samples (slim::read_points' default count) and the SLIM surface
/// built from them at relative error `error`.
struct MeshSlim {
    scene::OffMesh mesh;
    OrientedPoints points;
    BuildResult slim;
    V3 lo, hi;
    double diagonal() const { return length(hi - lo); }
};

inline MeshSlim build_mesh_slim(const std::string& file, double error, const BuildOptions& base = {}) {
    MeshSlim b;
    b.mesh = scene::read_off(file);
    b.points = read_points(file);
    BuildOptions o = base;
    o.error = error;
    b.slim = build(b.points, o);
    b.lo = b.hi = b.mesh.vertices.front();
    for (const V3& p : b.mesh.vertices)
        for (int k = 0; k < 3; ++k) b.lo[k] = std::min(b.lo[k], p[k]), b.hi[k] = std::max(b.hi[k], p[k]);
    return b;
}

/// The frame of the SLIM surface seen orthographically from direction `view` (as `quadcast bench
/// slim`: image height 0.8 diagonals, centred on the mesh's box).
inline render::Frame mesh_slim_frame(const MeshSlim& b, const V3& view, int w, int h) {
    const V3 centre = (b.lo + b.hi) * 0.5;
    const double diag = b.diagonal();
    scene::Scene s;
    s.camera.projection = scene::Projection::orthographic;
    s.camera.target = centre;
    s.camera.eye = centre + normalize(view) * (1.5 * diag);
    s.camera.height = 0.8 * diag;
    s.camera.near = 0.5 * diag;
    s.camera.far = 2.5 * diag;
    s.lights.push_back(scene::Light{});
    scene::Slim so;
    so.balls = scene_balls(b.slim.model);
    s.slims.push_back(so);
    return render::build_frame(s, w, h);
}

/// The mesh's first hit along every pixel ray of `fr` (rows top first, as render::Image and
/// render::SlimPixel), +inf where the ray misses it: an independent reference (MeshRaycaster,
/// double), the mesh scaled by `scale` about its box centre (1: the mesh itself).
inline std::vector<double> mesh_lambdas(const MeshSlim& b, const render::Frame& fr, double scale = 1.0) {
    const V3 centre = (b.lo + b.hi) * 0.5;
    std::vector<V3> pos;
    for (const V3& p : b.mesh.vertices) pos.push_back(fr.transform.point(centre + (p - centre) * scale));
    std::vector<std::array<std::uint32_t, 3>> tri;
    for (const auto& f : b.mesh.faces)
        for (std::size_t k = 1; k + 1 < f.size(); ++k) tri.push_back({std::uint32_t(f[0]), std::uint32_t(f[k]), std::uint32_t(f[k + 1])});
    const MeshRaycaster rc(pos, tri);
    const render::FrameSetup f = render::frame_setup(fr.camera, fr.options.width, fr.options.height);
    std::vector<double> out(std::size_t(f.width) * f.height);
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            const render::PixelRay ray = render::pixel_ray(f, x, y);
            V3 o, d;
            for (int k = 0; k < 3; ++k) o[k] = ray.origin[k], d[k] = ray.dir[k];
            out[std::size_t(f.height - 1 - y) * f.width + x] = rc.first_hit(o, d);
        }
    return out;
}

/// Pixels covered by only one of two images, by their distance in pixels to the reference's
/// silhouette: ring 0 is a pixel whose 8-neighbourhood (itself included) holds both a covered and
/// an uncovered reference pixel, ring k one k 8-neighbour steps from ring 0.
struct Coverage {
    long reference = 0, tested = 0, only_tested = 0, only_reference = 0;
    long silhouette = 0;       ///< ring 0 pixels
    long beyond_band = 0;      ///< differing pixels farther than the band
    int worst_ring = 0;        ///< of a differing pixel
};

inline Coverage compare_coverage(const std::vector<char>& tested, const std::vector<char>& reference, int w, int h, int band) {
    Coverage c;
    const int far = 1 << 20;
    std::vector<int> ring(tested.size(), far);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            bool in = false, out = false;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    const bool m = xx >= 0 && yy >= 0 && xx < w && yy < h && reference[std::size_t(yy) * w + xx];
                    (m ? in : out) = true;
                }
            if (in && out) {
                ring[std::size_t(y) * w + x] = 0;
                ++c.silhouette;
            }
        }
    // Rings by repeated dilation, up to 64 (farther counts as 64).
    for (int k = 1; k <= 64; ++k)
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                int& r = ring[std::size_t(y) * w + x];
                if (r < k) continue;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int xx = x + dx, yy = y + dy;
                        if (xx >= 0 && yy >= 0 && xx < w && yy < h && ring[std::size_t(yy) * w + xx] == k - 1) r = k;
                    }
            }
    for (std::size_t i = 0; i < tested.size(); ++i) {
        c.reference += reference[i] != 0;
        c.tested += tested[i] != 0;
        if ((tested[i] != 0) == (reference[i] != 0)) continue;
        ++(tested[i] ? c.only_tested : c.only_reference);
        const int r = std::min(ring[i], 64);
        c.worst_ring = std::max(c.worst_ring, r);
        if (r > band) ++c.beyond_band;
    }
    return c;
}

/// The band of `compare_coverage` for a SLIM surface of threshold E (world units) seen with pixels
/// of `footprint` world units: ceil(2 E / footprint) + 1 pixels. Why 2 E: every ball's zero set is
/// within E of the ball's points (the fit's acceptance) and, sampled, within the support distance
/// of some input point (the support check: 2 E, or 2 point spacings where the points are sparser
/// than E, which the meshes' 100000 samples are not); a pixel whose centre is d from the mesh's
/// silhouette curve is about d / footprint rings from it, plus one for the pixels of ring 0 on
/// either side of the curve.
inline int coverage_band(double threshold, double footprint) { return int(std::ceil(2 * threshold / footprint)) + 1; }

}  // namespace quadcast::slim::testing
