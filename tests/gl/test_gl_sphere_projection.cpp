// tests/gl/test_gl_sphere_projection.cpp -- the GL quadric renderer draws a sphere as its exact perspective projection
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "quadcast/gl/osmesa_context.hpp"
#include "quadcast/gl/quadric_renderer.hpp"
#include "render/render_testing.hpp"

using namespace quadcast;
using namespace quadcast::render;

namespace {

/// The expected image of a sphere, straight from the geometry of the float camera, in double
/// (independent of the renderers' pixel rays): the pixel centre (x + 1/2, y + 1/2) is covered
/// when its ray d from the eye e lies in the cone with apex e tangent to the sphere (c, r),
///   (d.w)^2 - (|w|^2 - r^2) |d|^2 >= 0  and  d.w > 0,   w = c - e,
/// whose trace on the image plane is the ellipse (a conic, in general) of the projection. The
/// ray of a pixel: d = R^T ((x_ndc + P20) / P00, (y_ndc + P21) / P11, -1) for a projection
/// with P10 = P30 = P01 = P31 = 0 (gluPerspective), R = the view rotation.
struct SphereProjection {
    double rt[3][3];  // R^T
    double p00, p11, p20, p21;
    Vec3<double> w;   // c - e
    double r2, w2;
    int width, height;

    SphereProjection(const Camera& cam, const Vec3<float>& center, float radius, int w_px, int h_px) : width(w_px), height(h_px) {
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) rt[i][j] = double(cam.view[i][j]);  // (R^T)_ij = R_ji = view[i][j]
        p00 = double(cam.projection[0][0]);
        p11 = double(cam.projection[1][1]);
        p20 = double(cam.projection[2][0]);
        p21 = double(cam.projection[2][1]);
        w = cast<double>(center) - cast<double>(cam.eye);
        r2 = double(radius) * double(radius);
        w2 = dot(w, w);
    }
    Vec3<double> ray(double px, double py) const {
        const double v[3] = {(2.0 * px / width - 1.0 + p20) / p00, (2.0 * py / height - 1.0 + p21) / p11, -1.0};
        Vec3<double> d{};
        for (int i = 0; i < 3; ++i) d[i] = rt[i][0] * v[0] + rt[i][1] * v[1] + rt[i][2] * v[2];
        return d;
    }
    /// The cone's quadratic form at window position (px, py) (>= 0 inside either nappe).
    double cone(double px, double py) const {
        const Vec3<double> d = ray(px, py);
        const double dw = dot(d, w);
        return dw * dw - (w2 - r2) * dot(d, d);
    }
    bool covered(int x, int y) const {
        const double px = x + 0.5, py = y + 0.5;
        return cone(px, py) >= 0 && dot(ray(px, py), w) > 0;
    }
    /// Distance in pixels from the centre of pixel (x, y) to the conic, to first order: |f| / |grad f|
    /// (f is quadratic in the window position, so the central differences are its exact gradient).
    double boundary_distance(int x, int y) const {
        const double px = x + 0.5, py = y + 0.5, hstep = 0.5;
        const double gx = (cone(px + hstep, py) - cone(px - hstep, py)) / (2 * hstep);
        const double gy = (cone(px, py + hstep) - cone(px, py - hstep)) / (2 * hstep);
        return std::fabs(cone(px, py)) / std::sqrt(gx * gx + gy * gy);
    }
};

/// gluLookAt in double, rounded to float (the eye first, so that view and eye agree).
Camera look_at_f(const Vec3<double>& eye_d, const Vec3<double>& target, const Vec3<double>& up, double fov_deg, double aspect, double n, double f) {
    const Vec3<float> eye_f = cast<float>(eye_d);
    const Vec3<double> eye = cast<double>(eye_f);
    const Vec3<double> zf = normalize(eye - target), x = normalize(cross(up, zf)), y = cross(zf, x);
    Mat4<double> v = identity<double, 4>();
    for (int j = 0; j < 3; ++j) {
        v[j][0] = x[j];
        v[j][1] = y[j];
        v[j][2] = zf[j];
    }
    v[3][0] = -dot(x, eye);
    v[3][1] = -dot(y, eye);
    v[3][2] = -dot(zf, eye);
    const double t = 1.0 / std::tan(fov_deg * M_PI / 360.0);
    Mat4<double> p = zero_mat<double, 4, 4>();
    p[0][0] = t / aspect;
    p[1][1] = t;
    p[2][2] = -(f + n) / (f - n);
    p[3][2] = -2.0 * f * n / (f - n);
    p[2][3] = -1.0;
    return Camera{cast<float>(v), cast<float>(p), eye_f, false};
}

}  // namespace

TEST_CASE("the GL quadric renderer covers exactly the analytic projection of a sphere, from 1.05 r to 1000 r, fov 20-120 degrees") {
    // A pixel may disagree with the analytic cone only when its centre lies within `tol` pixels
    // of the conic: the GPU builds its rays in float (directions rounded to ~1e-7 relative, the
    // ray terms interpolated over the bounding quad) and solves in float, which moves the
    // silhouette by far less than 1e-3 px at this resolution; everything farther must match.
    // near = 0.1 (k - 1) r and far = 2 (k + 2) r keep the whole sphere in the depth range, so the
    // cone alone decides coverage.
    const double tol = 1e-3;
    const int w = 320, h = 240;
    gl::OsmesaContext ctx;
    gl::QuadricRenderer gr(ctx.api());
    RenderOptions opt;
    opt.width = w;
    opt.height = h;
    Light light;
    light.direction = vec3(-0.3f, -0.5f, -1.0f);
    long views = 0, total_cover = 0, total_mismatch = 0, total_near = 0, far_mismatch = 0;
    double worst = 0;  // largest boundary distance (px) of a mismatching pixel
    std::uint32_t it = 0;
    for (double k : {1.05, 1.5, 4.0, 30.0, 300.0, 1000.0})
        for (double fov : {20.0, 60.0, 90.0, 120.0})
            for (bool off : {false, true})
                for (int rep = 0; rep < 2; ++rep) {
                    std::mt19937 rng = qc_render_test::rng_for(401, it++);
                    const Vec3<double> c = vec3(3.7, -1.2, 2.5);
                    const double r = 0.8;
                    const Vec3<double> dir = qc_render_test::random_dir(rng);
                    const Vec3<double> u = normalize(cross(dir, qc_render_test::random_dir(rng)));
                    // Off axis: the centre 0.35 half-fovs off the view axis, in a random direction.
                    const double alpha = off ? 0.35 * fov * M_PI / 360.0 : 0.0;
                    const Vec3<double> eye = c + dir * (k * r);
                    const Vec3<double> target = c + u * (k * r * std::tan(alpha));
                    const Camera cam = look_at_f(eye, target, cross(dir, u), fov, double(w) / h, 0.1 * (k - 1) * r, 2.0 * (k + 2) * r);
                    const render::Primitive sph = qc_render_test::sphere(cast<float>(c), float(r));
                    gr.set_primitives({sph});
                    gr.draw(cam, light, opt);
                    const Image img = gr.read();
                    const SphereProjection ex(cam, sph.shape.center, sph.shape.radius, w, h);
                    long cover = 0, mismatch = 0, near = 0;
                    for (int y = 0; y < h; ++y)
                        for (int x = 0; x < w; ++x) {
                            const bool want = ex.covered(x, y);
                            const double dist = ex.boundary_distance(x, y);
                            cover += want;
                            near += dist <= tol;
                            if (want == qc_render_test::covered(img, x, y)) continue;
                            ++mismatch;
                            worst = std::max(worst, dist);
                            if (dist > tol) {
                                ++far_mismatch;
                                CHECK_MESSAGE(dist <= tol, "k=" << k << " fov=" << fov << " off=" << off << " rep=" << rep << " pixel (" << x << ", " << y
                                                                << ") expected " << want << ", " << dist << " px from the conic");
                            }
                        }
                    ++views;
                    total_cover += cover;
                    total_mismatch += mismatch;
                    total_near += near;
                }
    std::printf("[gl] sphere projection: %ld views, %ld covered pixels, %ld pixel centres within %.0e px of the conic, "
                "%ld mismatches (largest distance from the conic %.2e px), %ld farther than %.0e px\n",
                views, total_cover, total_near, tol, total_mismatch, worst, far_mismatch, tol);
    CHECK(far_mismatch == 0);
    CHECK(total_cover > 500000);
}
