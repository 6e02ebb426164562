// tests/slim/against_mesh.cpp -- SLIM surfaces of closed meshes against the meshes themselves and their input points: silhouette coverage, hits near the input, seams
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "quadcast/render/slim_cpu_renderer.hpp"
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
