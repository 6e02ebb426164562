// tests/slim/against_mesh.cpp -- SLIM surfaces of closed meshes against the meshes themselves and their input points: silhouette coverage, hits near the input, seams
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "quadcast/image/image_io.hpp"
#include "quadcast/render/slim_cpu_renderer.hpp"
#include "quadcast/volume/sdf.hpp"
#include "slim/against_mesh.hpp"
#include "slim/slim_testing.hpp"

using namespace quadcast;
using namespace quadcast::slim;
using namespace quadcast::slim::testing;

namespace {

std::string data(const char* name) { return std::string(QUADCAST_SLIM_TEST_DATA) + "/" + name; }

const V3 bench_view = vec3(0.35, 0.3, 1.0);

std::vector<char> slim_coverage(const std::vector<render::SlimPixel>& px) {
    std::vector<char> c(px.size());
    for (std::size_t i = 0; i < px.size(); ++i) c[i] = px[i].covered;
    return c;
}

std::vector<char> hit(const std::vector<double>& lambda) {
    std::vector<char> c(lambda.size());
    for (std::size_t i = 0; i < lambda.size(); ++i) c[i] = std::isfinite(lambda[i]);
    return c;
}

}  // namespace

TEST_CASE("a SLIM surface of a closed mesh covers the mesh's pixels, up to a band of 2 E and a pixel at the silhouette (CPU reference)") {
    // The mesh's own coverage is ray casting of its triangles (MeshRaycaster, double), not SLIM code.
    // Every pixel covered by only one of the two must lie within coverage_band (ceil(2 E /
    // footprint) + 1) rings of the mesh's silhouette: no hole and no flake elsewhere.
    struct Case {
        std::string file;
        int w, h;
    };
    for (const Case& c : {Case{"torus_1024.off", 256, 192}, Case{"bunny_3k.off", 256, 192}, Case{"bunny_3k.off", 512, 384}}) {
        CAPTURE(c.file);
        CAPTURE(c.w);
        const MeshSlim b = build_mesh_slim(data(c.file.c_str()), 3e-3);
        const render::Frame fr = mesh_slim_frame(b, bench_view, c.w, c.h);
        std::vector<render::SlimPixel> px;
        render::render_slim_cpu(fr.slim_balls, fr.camera, fr.light, fr.options, &px);
        const double footprint = 0.8 * b.diagonal() / c.h;
        const int band = coverage_band(b.slim.stats.threshold, footprint);
        const Coverage cov = compare_coverage(slim_coverage(px), hit(mesh_lambdas(b, fr)), c.w, c.h, band);
        // The same measure against the mesh grown by 10% about its centre (its silhouette moves by
        // up to about 10 E): the measure does see a shifted silhouette.
        const Coverage grown = compare_coverage(slim_coverage(px), hit(mesh_lambdas(b, fr, 1.1)), c.w, c.h, band);
        MESSAGE(c.file << " " << c.w << "x" << c.h << ": " << b.slim.stats.balls << " balls, footprint " << footprint / b.slim.stats.threshold
                       << " E, band " << band << " px; mesh " << cov.reference << " px, SLIM " << cov.tested << " px, silhouette " << cov.silhouette
                       << " px; only SLIM " << cov.only_tested << ", only mesh " << cov.only_reference << ", farthest ring " << cov.worst_ring
                       << ", beyond the band " << cov.beyond_band << " (against the mesh grown by 10%: " << grown.beyond_band << ")");
        CHECK(cov.reference > c.w * c.h / 8);
        CHECK(cov.beyond_band == 0);
        CHECK(grown.beyond_band > cov.silhouette / 10);
    }
}

TEST_CASE("CGAL's bunny, fandisk and Chinese dragon (when build/data has them): the SLIM surface covers the mesh's pixels up to the band, in four views") {
    // As the test above, on the meshes the demo draws (make data fetches them; `make test` does):
    // fandisk's creases and corners and the dragon's thin mane and claws, where fins and blobs
    // stood off the edges by up to 48 rings (fandisk, before the support check's boundary test).
    for (const char* name : {"bunny00.off", "fandisk.off", "ChineseDragon-10kv.off"}) {
        CAPTURE(name);
        const std::filesystem::path f = cgal_data(name);
        if (!std::filesystem::exists(f)) {
            MESSAGE("skipped: " << f.string() << " is absent (make data, or tools/fetch_cgal_data.sh build/data)");
            continue;
        }
        const MeshSlim b = build_mesh_slim(f.string(), 3e-3);
        const int w = 512, h = 384;
        const double footprint = 0.8 * b.diagonal() / h;
        const int band = coverage_band(b.slim.stats.threshold, footprint);
        for (const V3& view : {vec3(0.35, 0.3, 1.0), vec3(1.3, 0.9, 1.3), vec3(-1.0, 0.5, -0.7), vec3(0.2, -1.0, 0.3)}) {
            CAPTURE(view[0]);
            CAPTURE(view[1]);
            const render::Frame fr = mesh_slim_frame(b, view, w, h);
            std::vector<render::SlimPixel> px;
            render::render_slim_cpu(fr.slim_balls, fr.camera, fr.light, fr.options, &px);
            const Coverage cov = compare_coverage(slim_coverage(px), hit(mesh_lambdas(b, fr)), w, h, band);
            MESSAGE(std::string(name) << " view (" << view[0] << ", " << view[1] << ", " << view[2] << "): " << b.slim.stats.balls << " balls ("
                         << b.slim.stats.sharp_pairs << " sharp pairs, " << b.slim.stats.forced << " forced), band " << band << " px; only SLIM "
                         << cov.only_tested << ", only mesh " << cov.only_reference << ", farthest ring " << cov.worst_ring << ", beyond the band "
                         << cov.beyond_band);
            CHECK(cov.reference > w * h / 16);
            CHECK(cov.beyond_band == 0);
        }
    }
}

TEST_CASE("no flakes: every blended hit of a sparsely sampled bunny lies within the samples' covering radius + 2 E of a sample") {
    // Flakes (a quadric's second sheet or a sheet folded back through the points, drawn by the
    // renderers away from the surface; the kitten's ears and the dragon's mane showed them) are hits
    // far from every input point. The reference is the input itself: rho, the covering radius of
    // the samples on the mesh (the largest distance from 400000 other points of the mesh to the
    // nearest sample), measured by a grid search (NearestPoint), not by SLIM code. A hit on the
    // surface is within rho of a sample; the blended surface is within E of the points and the
    // support check keeps every ball's zero set within 2 E (2 spacings where sparser) of a sample,
    // so a hit farther than rho + 2 E from every sample is off the surface. 10000 samples of the
    // 3k-face bunny at E = 3e-3 are about as sparse as CGAL's kitten (5210 points) at that E.
    const std::string file = data("bunny_3k.off");
    ReadOptions ro;
    ro.mesh_samples = 10000;
    const OrientedPoints pts = read_points(file, ro);
    ro.mesh_samples = 400000;
    ro.seed = 7;
    const OrientedPoints dense = read_points(file, ro);
    for (const bool support : {true, false}) {
        CAPTURE(support);
        MeshSlim b;
        b.mesh = scene::read_off(file);
        b.points = pts;
        BuildOptions o;
        o.error = 3e-3;
        o.support_check = support;
        b.slim = build(pts, o);
        b.lo = b.hi = b.mesh.vertices.front();
        for (const V3& p : b.mesh.vertices)
            for (int k = 0; k < 3; ++k) b.lo[k] = std::min(b.lo[k], p[k]), b.hi[k] = std::max(b.hi[k], p[k]);
        const double E = b.slim.stats.threshold;
        const NearestPoint near(pts.positions, 2 * E);
        double rho = 0;
        for (const V3& q : dense.positions) rho = std::max(rho, near.distance(q));
        long far = 0, covered = 0;
        double worst = 0;
        for (const V3& view : {vec3(0.35, 0.3, 1.0), vec3(-0.8, 0.4, -0.5)}) {
            const render::Frame fr = mesh_slim_frame(b, view, 320, 240);
            std::vector<render::SlimPixel> px;
            render::render_slim_cpu(fr.slim_balls, fr.camera, fr.light, fr.options, &px);
            for (const render::SlimPixel& p : px) {
                if (!p.covered) continue;
                ++covered;
                V3 x;
                for (int k = 0; k < 3; ++k) x[k] = double(p.origin[k]) + double(p.lambda) * double(p.dir[k]);
                const double d = near.distance(fr.transform.offset + x * fr.transform.scale);
                worst = std::max(worst, d);
                far += d > rho + 2 * E;
            }
        }
        MESSAGE("bunny_3k.off, 10000 samples, E = 3e-3, support check " << std::string(support ? "on" : "off") << ": " << b.slim.stats.balls << " balls ("
                << b.slim.stats.forced << " forced), covering radius " << rho / E << " E; of " << covered << " covered pixels (two views) " << far
                << " farther than rho + 2 E from every sample, the farthest " << worst / E << " E");
        if (support) CHECK(far == 0);
        else CHECK(far > 0);  // the same measure finds the flakes of the unchecked fits
    }
}

namespace {

double angle_deg(const V3& a, const V3& b) {
    const double c = dot(a, b) / std::sqrt(dot(a, a) * dot(b, b));
    return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
}

}  // namespace

TEST_CASE("no seams on the bunny: neighbouring pixels of one sheet differ in blended normal as the mesh's smooth normals do, within a bound") {
    const MeshSlim b = build_mesh_slim(data("bunny_3k.off"), 3e-3);
    const int w = 320, h = 240;
    const render::Frame fr = mesh_slim_frame(b, bench_view, w, h);
    std::vector<render::SlimPixel> px;
    render::Image img = render::render_slim_cpu(fr.slim_balls, fr.camera, fr.light, fr.options, &px);
    // The reference normal: the mesh's area-weighted vertex normals interpolated over the triangle
    // the pixel's ray hits first (MeshRaycaster, double).
    std::vector<V3> pos, vn(b.mesh.vertices.size(), vec3(0.0, 0.0, 0.0));
    for (const V3& p : b.mesh.vertices) pos.push_back(fr.transform.point(p));
    std::vector<std::array<std::uint32_t, 3>> tri;
    for (const auto& f : b.mesh.faces)
        for (std::size_t k = 1; k + 1 < f.size(); ++k) tri.push_back({std::uint32_t(f[0]), std::uint32_t(f[k]), std::uint32_t(f[k + 1])});
    for (const auto& t : tri) {
        const V3 n = cross(pos[t[1]] - pos[t[0]], pos[t[2]] - pos[t[0]]);
        for (const std::uint32_t v : t) vn[v] = vn[v] + n;
    }
    const MeshRaycaster rc(pos, tri);
    std::vector<V3> ref(px.size()), blended(px.size()), x(px.size()), dir(px.size()), face(px.size(), vec3(0.0, 0.0, 0.0));
    std::vector<char> ok(px.size(), 0);
    for (std::size_t i = 0; i < px.size(); ++i) {
        const render::SlimPixel& p = px[i];
        V3 o;
        for (int k = 0; k < 3; ++k) o[k] = p.origin[k], dir[i][k] = p.dir[k], blended[i][k] = p.normal[k];
        std::uint32_t t = 0;
        double u = 0, v = 0;
        if (!p.covered || !std::isfinite(rc.first_hit(o, dir[i], &t, &u, &v))) continue;
        const auto& T = tri[t];
        ref[i] = normalize(normalize(vn[T[0]]) * (1 - u - v) + normalize(vn[T[1]]) * u + normalize(vn[T[2]]) * v);
        face[i] = normalize(cross(pos[T[1]] - pos[T[0]], pos[T[2]] - pos[T[0]]));
        for (int k = 0; k < 3; ++k) x[i][k] = double(p.origin[k]) + double(p.lambda) * double(p.dir[k]);
        // Facing the eye at |cos| >= 1/2 (at grazing angles neighbouring pixels are far apart on the surface)
        ok[i] = std::fabs(dot(dir[i], ref[i])) >= 0.5 * length(dir[i]);
    }
    auto interior = [&](std::size_t i) {
        const int xx = int(i % std::size_t(w)), yy = int(i / std::size_t(w));
        if (xx == 0 || yy == 0 || xx == w - 1 || yy == h - 1) return false;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                if (!ok[std::size_t(yy + dy) * w + std::size_t(xx + dx)]) return false;
        return true;
    };
    // The mesh's own creases: pixels next to a neighbour whose first-hit triangle's face normal
    // differs by more than crease_deg (the bunny's flat base meets its sides at about 90 degrees). A
    // SLIM surface keeps such a crease sharp (a sharp pair), where the interpolated vertex normals
    // round it over a triangle: a step the reference does not have, but no seam.
    const double crease_deg = 45;
    std::vector<char> crease(px.size(), 0);
    for (int yy = 1; yy + 1 < h; ++yy)
        for (int xx = 1; xx + 1 < w; ++xx) {
            const std::size_t i = std::size_t(yy) * w + std::size_t(xx);
            for (const std::size_t j : {i + 1, i + std::size_t(w)})
                if (dot(face[i], face[i]) > 0 && dot(face[j], face[j]) > 0 && angle_deg(face[i], face[j]) > crease_deg)
                    for (const std::size_t k : {i, j}) crease[k] = 1;
        }
    const double footprint = fr.transform.length(0.8 * b.diagonal() / h);
    std::vector<double> errors, seams, steps, ref_steps;
    long lone_rims = 0;  // a pixel blending almost nothing (sum w < 0.05) next to one of full weight (> 0.5)
    long crease_pairs = 0;
    for (std::size_t i = 0; i < px.size(); ++i) {
        if (!interior(i)) continue;
        errors.push_back(angle_deg(blended[i], ref[i]));
        for (const std::size_t j : {i + 1, i + std::size_t(w)}) {
            if (!interior(j) || length(x[i] - x[j]) > 3 * footprint) continue;  // one sheet
            if (crease[i] || crease[j]) {
                ++crease_pairs;
                continue;
            }
            const double a = angle_deg(blended[i], blended[j]), m = angle_deg(ref[i], ref[j]);
            steps.push_back(a);
            ref_steps.push_back(m);
            seams.push_back(a - m);
            lone_rims += std::min(px[i].weight, px[j].weight) < 0.05f && std::max(px[i].weight, px[j].weight) > 0.5f;
            if (a - m > 10) img.rgba[i * 4] = 255, img.rgba[i * 4 + 1] = 0, img.rgba[i * 4 + 2] = 0;
            else if (a - m > 3) img.rgba[i * 4] = 0, img.rgba[i * 4 + 1] = 0, img.rgba[i * 4 + 2] = 255;
        }
    }
    MESSAGE("bunny_3k.off, E = 3e-3, " << w << "x" << h << ": " << b.slim.stats.balls << " balls, " << errors.size() << " interior pixels, " << seams.size()
            << " neighbour pairs; blended normal vs the mesh's smooth normal: median " << percentile(errors, 0.5) << ", 99% " << percentile(errors, 0.99)
            << ", max " << percentile(errors, 1.0) << " deg; neighbours' blended normals: median " << percentile(steps, 0.5) << ", 99% "
            << percentile(steps, 0.99) << ", 99.9% " << percentile(steps, 0.999) << ", max " << percentile(steps, 1.0) << " deg (mesh: median "
            << percentile(ref_steps, 0.5) << ", 99% " << percentile(ref_steps, 0.99) << ", max " << percentile(ref_steps, 1.0)
            << " deg); difference (seam): 99% " << percentile(seams, 0.99) << ", 99.9% " << percentile(seams, 0.999) << ", max " << percentile(seams, 1.0)
            << " deg; " << lone_rims << " pairs of a pixel of sum w < 0.05 next to one > 0.5; " << crease_pairs << " pairs on the mesh's creases (over "
            << crease_deg << " degrees) left out");
    if (std::getenv("QC_SLIM_TEST_PNG")) render::write_png(std::string(std::getenv("QC_SLIM_TEST_PNG")) + "bunny_seams.png", img);
    // The argument: the weights are C1 and vanish on their spheres, so the blend of the same hits is
    // C1 and two neighbours of one sheet differ as the surface does plus the change of the blend's
    // normal error; a jump needs a hit that enters or leaves with weight. The visibility window was
    // one such: a small ball's rim hit a little in front of the surface (its quadric's deviation at
    // the rim) shut out the surface's hits behind it, and its pixel showed that one hit of weight
    // ~0.01 alone (45-70 degree jumps measured here). Its push now grows towards the rim
    // (slim_depth_window, quadcast/slim_blend.hpp): no pixel of a pair blends a lone rim hit next to
    // a fully weighted neighbour.
    CHECK(lone_rims == 0);
    // What remains are the shallower creases of the 3k-face mesh itself (the samples are its faces;
    // small balls fit planes on either side of a crease, which the mesh's interpolated normals
    // smooth over): 99% of the pairs differ from the mesh's own step by at most twice the blended
    // normal's median error against the mesh plus two degrees, 99.9% by at most 10 degrees (both
    // partly empirical; measured 4.2 and 8.3 degrees, the most 19.7). With the pairs on creases
    // over 45 degrees counted, as before, 99.9% measured 14.2-15.3 degrees, the changes between
    // builder versions all at the base's crease.
    CHECK(percentile(seams, 0.99) <= 2 * percentile(errors, 0.5) + 2.0);
    CHECK(percentile(seams, 0.999) <= 10.0);
}

TEST_CASE("no fins at creases and corners: every record's zero set in its ball lies near the faces of an L-shaped prism") {
    // A quadric continued past a crease (one face's plane beyond its edge, or the plane pair x y = 0
    // of a ball across the crease) or past a corner is drawn by the renderers as a fin or a blob
    // standing off the edge (fandisk showed them). The reference is the prism's own 20 triangles:
    // the distance of every sampled zero-set point (long double roots, 31 x 31 x 3 lines per ball)
    // to the nearest triangle (volume::point_triangle_distance2 in long double), not SLIM code. The support check
    // keeps every zero-set point it samples within its support distance (2 E here: 100000
    // samples) of an input point, so of the faces, and the boundary test keeps it from running
    // past the points' edge; its lines lie two thirds of the support distance apart, so an unsampled
    // zero-set point is within 2/3 E of a sampled one: 2.67 E in all, below the 3 E checked.
    const std::string file = data("l_prism.off");
    struct Variant {
        const char* name;
        double max_gap;
        bool support;
    };
    for (const Variant v : {Variant{"support check", 240, true}, Variant{"support check without its boundary test", 360, true},
                            Variant{"no support check", 360, false}}) {
        CAPTURE(v.name);
        BuildOptions o;
        o.support_max_gap_degrees = v.max_gap;
        o.support_check = v.support;
        const MeshSlim b = build_mesh_slim(file, 3e-3, o);
        const long double E = b.slim.stats.threshold;
        std::vector<std::array<V3L, 3>> tri;
        for (const auto& f : b.mesh.faces)
            for (std::size_t k = 1; k + 1 < f.size(); ++k)
                tri.push_back({to_long(b.mesh.vertices[f[0]]), to_long(b.mesh.vertices[f[k]]), to_long(b.mesh.vertices[f[k + 1]])});
        long double worst = 0;
        V3L worst_at{};
        const Ball* worst_ball = nullptr;
        long samples = 0, beyond_2e = 0, beyond_3e = 0;
        for (const Ball& ball : b.slim.model.balls)
            zero_set_samples(ball, 31, [&](const V3L& x) {
                long double d = std::numeric_limits<long double>::infinity();
                for (const auto& t : tri) d = std::min(d, std::sqrt(volume::point_triangle_distance2(x, t[0], t[1], t[2])));
                if (d > worst) worst = d, worst_at = x, worst_ball = &ball;
                ++samples;
                beyond_2e += d > 2 * E;
                beyond_3e += d > 3 * E;
            });
        MESSAGE("l_prism.off, E = 3e-3, " << std::string(v.name) << ": " << b.slim.stats.balls << " balls (" << b.slim.stats.sharp_pairs << " sharp pairs, "
                << b.slim.stats.forced << " forced); " << samples << " zero-set samples, " << beyond_2e << " farther than 2 E from the faces, "
                << beyond_3e << " farther than 3 E, the farthest " << double(worst / E) << " E (at (" << double(worst_at[0]) << ", " << double(worst_at[1])
                << ", " << double(worst_at[2]) << "), of a record with " << (worst_ball ? int(worst_ball->has_plane) + int(worst_ball->has_plane2) : -1)
                << " planes, radius " << (worst_ball ? worst_ball->radius / double(E) : 0.0) << " E)");
        CHECK(samples > 100 * long(b.slim.stats.balls));
        // Measured with saddle corners, the face normals of the clusters (`face_normal` in
        // src/slim/build.cpp) and the pairs' tangent planes: 0 samples beyond 2 E, the farthest
        // 1.52 E (0.43 E without the tangent planes: another cover; a small pair's face runs past
        // the third face at the notch's saddle corner, inside the solid); without the boundary
        // test 0 and 1.74 E; without the support check 20580 and 81 E. Before them: 0 and 1.79 E, 292
        // and 2.95 E (the boundary test removed the fins of pairs whose clusters held a third face's
        // points, at the notch's saddle corners), 28561 and 81 E; before the corner triples: 20 and
        // 2.67 E, 639 and 3.1 E, 92454 and 81 E.
        if (v.support) CHECK(beyond_2e == 0);
        else CHECK(beyond_2e > 100);  // the measure sees fins
    }
}

namespace {

/// Per pixel of `fr`, the unit normal of the mesh triangle first hit (frame coordinates; the
/// frame is the world scaled and shifted, so normals are the world's), (0, 0, 0) where the ray
/// misses: an independent reference (MeshRaycaster, double).
std::vector<V3> mesh_face_normals(const MeshSlim& b, const render::Frame& fr) {
    std::vector<V3> pos;
    for (const V3& p : b.mesh.vertices) pos.push_back(fr.transform.point(p));
    std::vector<std::array<std::uint32_t, 3>> tri;
    for (const auto& f : b.mesh.faces)
        for (std::size_t k = 1; k + 1 < f.size(); ++k) tri.push_back({std::uint32_t(f[0]), std::uint32_t(f[k]), std::uint32_t(f[k + 1])});
    const MeshRaycaster rc(pos, tri);
    const render::FrameSetup f = render::frame_setup(fr.camera, fr.options.width, fr.options.height);
    std::vector<V3> out(std::size_t(f.width) * f.height, vec3(0.0, 0.0, 0.0));
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            const render::PixelRay ray = render::pixel_ray(f, x, y);
            V3 o, d;
            for (int k = 0; k < 3; ++k) o[k] = ray.origin[k], d[k] = ray.dir[k];
            std::uint32_t t = 0;
            double u = 0, v = 0;
            if (!std::isfinite(rc.first_hit(o, d, &t, &u, &v))) continue;
            const V3 n = cross(pos[tri[t][1]] - pos[tri[t][0]], pos[tri[t][2]] - pos[tri[t][0]]);
            out[std::size_t(f.height - 1 - y) * f.width + x] = normalize(n);
        }
    return out;
}

/// Pixels of the SLIM surface whose blended normal is more than `deg` degrees from the mesh's face
/// normal, away from the mesh's creases and silhouette: pixels farther than `margin` pixels (8-
/// neighbour steps) from any pixel whose mesh normal differs from a 4-neighbour's by more than
/// 25 degrees or that borders the background.
long normal_outliers(const std::vector<render::SlimPixel>& px, const std::vector<V3>& mesh_n, int w, int h, int margin, double deg, long* checked,
                     long* near_crease = nullptr, long* near_wrong = nullptr) {
    const int far = 1 << 20;
    std::vector<int> dist(px.size(), far);
    const double cos_crease = std::cos(25.0 * std::numbers::pi / 180);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const V3& n = mesh_n[std::size_t(y) * w + x];
            const bool bg = dot(n, n) == 0;
            bool edge = false;
            const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
            for (int k = 0; k < 4; ++k) {
                const int xx = x + dx[k], yy = y + dy[k];
                if (xx < 0 || yy < 0 || xx >= w || yy >= h) { edge = true; continue; }
                const V3& m = mesh_n[std::size_t(yy) * w + xx];
                const bool mbg = dot(m, m) == 0;
                edge = edge || (bg != mbg) || (!bg && !mbg && dot(n, m) < cos_crease);
            }
            if (edge) dist[std::size_t(y) * w + x] = 0;
        }
    // Two chamfer sweeps (8-neighbour steps).
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int dy = -1; dy <= 0; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    if (dy == 0 && dx >= 0) continue;
                    const int xx = x + dx, yy = y + dy;
                    if (xx >= 0 && yy >= 0 && xx < w) dist[std::size_t(y) * w + x] = std::min(dist[std::size_t(y) * w + x], dist[std::size_t(yy) * w + xx] + 1);
                }
    for (int y = h - 1; y >= 0; --y)
        for (int x = w - 1; x >= 0; --x)
            for (int dy = 0; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    if (dy == 0 && dx <= 0) continue;
                    const int xx = x + dx, yy = y + dy;
                    if (xx >= 0 && yy < h && xx < w) dist[std::size_t(y) * w + x] = std::min(dist[std::size_t(y) * w + x], dist[std::size_t(yy) * w + xx] + 1);
                }
    const double cos_max = std::cos(deg * std::numbers::pi / 180);
    long bad = 0;
    *checked = 0;
    const double cos_wrong = std::cos(45.0 * std::numbers::pi / 180);
    for (std::size_t i = 0; i < px.size(); ++i) {
        const V3& n = mesh_n[i];
        if (px[i].covered && dot(n, n) != 0 && dist[i] >= 1 && dist[i] <= margin && near_crease && near_wrong) {
            ++*near_crease;
            const V3 s = vec3(double(px[i].normal[0]), double(px[i].normal[1]), double(px[i].normal[2]));
            *near_wrong += dot(s, n) < cos_wrong;
        }
        if (!px[i].covered || dot(n, n) == 0 || dist[i] <= margin) continue;
        ++*checked;
        const V3 s = vec3(double(px[i].normal[0]), double(px[i].normal[1]), double(px[i].normal[2]));
        bad += dot(s, n) < cos_max;
    }
    return bad;
}

}  // namespace

TEST_CASE("fandisk (when build/data has it): away from its creases the blended normal is the mesh's face normal, no flakes; near them few pixels show the wrong face") {
    // Near fandisk's creases the cover ends in balls of a few E whose plane, tilted between the two
    // faces, is within E of their points: drawn as discs and specks with a normal between the
    // faces' (BuildOptions::crease_normal_degrees; README, "Creases in small balls"). Reference:
    // the mesh's own triangles, their face normals at each pixel's first hit. Checked: pixels more
    // than 2 px (1.4 E at this size; the flakes reach about 2.4 E from their crease) from the
    // mesh's creases (25 degrees between neighbouring pixels' face normals) and silhouette. The
    // curved faces' triangles are flat, so a few degrees of difference are the tessellation's; a
    // flake's normal is 30-45 degrees off. And the pixels 1-2 px from the creases (or the
    // silhouette) whose normal is more than 45 degrees off: the other face's (a face ending past its crease or short of it,
    // the sharp pairs' planes: BuildOptions::pair_tangent_planes; README, "Face normals and edge
    // planes").
    const std::filesystem::path f = cgal_data("fandisk.off");
    if (!std::filesystem::exists(f)) {
        MESSAGE("skipped: " << f.string() << " is absent (make data, or tools/fetch_cgal_data.sh build/data)");
        return;
    }
    const int w = 512, h = 384, margin = 2;
    const double deg = 20;
    const V3 views[4] = {vec3(0.35, 0.3, 1.0), vec3(1.3, 0.9, 1.3), vec3(-1.0, 0.5, -0.7), vec3(0.2, -1.0, 0.3)};
    const char* names[3] = {"fandisk.off at 3e-3", "fandisk.off at 3e-3 without the crease test", "fandisk.off at 3e-3 with the pairs' planes between the faces"};
    long outliers[3] = {0, 0, 0}, wrong_face[3] = {0, 0, 0};
    for (int variant = 0; variant < 3; ++variant) {
        BuildOptions o;
        if (variant == 1) o.crease_normal_degrees = 180;  // without the crease test
        if (variant == 2) o.pair_tangent_planes = false;
        const MeshSlim b = build_mesh_slim(f.string(), 3e-3, o);
        for (const V3& view : views) {
            const render::Frame fr = mesh_slim_frame(b, view, w, h);
            std::vector<render::SlimPixel> px;
            render::render_slim_cpu(fr.slim_balls, fr.camera, fr.light, fr.options, &px);
            long checked = 0, near = 0, wrong = 0;
            const long bad = normal_outliers(px, mesh_face_normals(b, fr), w, h, margin, deg, &checked, &near, &wrong);
            MESSAGE(names[variant] << ", view (" << view[0] << ", " << view[1] << ", " << view[2] << "): " << b.slim.stats.balls << " balls, " << checked
                                   << " pixels away from creases, " << bad << " with the blended normal more than " << deg << " degrees from the mesh's; "
                                   << near << " pixels 1-2 px from creases or the silhouette, " << wrong << " of them more than 45 degrees off");
            CHECK(checked > w * h / 8);
            CHECK(near > w * h / 40);
            outliers[variant] += bad;
            wrong_face[variant] += wrong;
        }
    }
    MESSAGE("outliers with the crease test " << outliers[0] << ", without " << outliers[1] << ", with the planes between the faces " << outliers[2]
                                             << "; near creases the wrong face " << wrong_face[0] << ", " << wrong_face[1] << ", " << wrong_face[2]);
    // Measured: 5 outliers (3 of them a sliver along the narrow strip between the arches, seen from
    // below), 16-17 without the crease test, 2 with the planes between the faces; near creases
    // 109 pixels of the wrong face, 151 with the planes between the faces (their chords of the
    // curved creases: steps along the strip's edges, a fin where the rounded column meets the top).
    CHECK(outliers[0] <= 6);
    CHECK(outliers[1] > outliers[0]);  // the measure sees what the crease test removes
    CHECK(wrong_face[0] <= 125);
    CHECK(wrong_face[2] > wrong_face[0]);  // and what the tangent planes remove
}
