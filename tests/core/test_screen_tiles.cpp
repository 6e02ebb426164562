// The screen-space index arithmetic of the GL passes, against direct counts over pixels:
// the max-depth pyramid's 2 x 2 reduction (`pyramid_children`) and the deferred background pass's
// outline tiles (`outline_tile_reach`, `outline_tile_centre`, `is_cleared_gnormal`).
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "quadcast/occlusion.hpp"
#include "quadcast/shading.hpp"

using namespace quadcast;

namespace {

// Viewport sides: every size up to 70, then some large odd and even ones.
std::vector<int> sides() {
    std::vector<int> s;
    for (int n = 1; n <= 70; ++n) s.push_back(n);
    for (int n : {127, 128, 255, 257, 511, 768, 1023, 1024, 1025}) s.push_back(n);
    return s;
}

}  // namespace

TEST_CASE("a max-depth pyramid built by pyramid_children holds the largest depth over each texel's pixels") {
    std::mt19937 rng(61206);
    long texels = 0;
    for (int w : sides())
        for (int h : {1, 2, 3, 7, 8, 9, 33, w}) {
            // Level 0: random depth bits; levels halve, rounding up, down to 1 x 1.
            std::vector<std::vector<std::uint32_t>> level{std::vector<std::uint32_t>(std::size_t(w) * h)};
            for (auto& v : level[0]) v = rng();
            std::vector<std::pair<int, int>> size{{w, h}};
            while (size.back().first > 1 || size.back().second > 1) {
                const auto [bw, bh] = size.back();
                const int lw = (bw + 1) / 2, lh = (bh + 1) / 2;
                std::vector<std::uint32_t> next(std::size_t(lw) * lh);
                for (int y = 0; y < lh; ++y)
                    for (int x = 0; x < lw; ++x) {
                        const Vec4<float> c = pyramid_children(vec2(float(x), float(y)), vec2(float(bw), float(bh)));
                        // The children lie in the level below: the first column and row are 2 t.
                        REQUIRE(c[0] == 2.0f * x);
                        REQUIRE(c[1] == 2.0f * y);
                        REQUIRE(c[2] < float(bw));
                        REQUIRE(c[3] < float(bh));
                        const auto at = [&](float cx, float cy) { return level.back()[std::size_t(cy) * bw + std::size_t(cx)]; };
                        next[std::size_t(y) * lw + x] = std::max(std::max(at(c[0], c[1]), at(c[2], c[1])), std::max(at(c[0], c[3]), at(c[2], c[3])));
                    }
                level.push_back(std::move(next));
                size.push_back({lw, lh});
            }
            REQUIRE(size.back() == std::pair<int, int>{1, 1});
            // Texel t of level l: the largest over the pixels [2^l t, 2^l (t + 1) - 1] of level 0.
            for (std::size_t l = 1; l < level.size(); ++l) {
                const int span = 1 << l;
                for (int y = 0; y < size[l].second; ++y)
                    for (int x = 0; x < size[l].first; ++x) {
                        std::uint32_t m = 0;
                        for (int py = y * span; py < std::min((y + 1) * span, h); ++py)
                            for (int px = x * span; px < std::min((x + 1) * span, w); ++px) m = std::max(m, level[0][std::size_t(py) * w + px]);
                        REQUIRE(level[l][std::size_t(y) * size[l].first + x] == m);
                        ++texels;
                    }
            }
        }
    MESSAGE(texels << " pyramid texels checked against their pixels");
}

TEST_CASE("an outline tile's reach is exactly the texels its pixels' 3 x 3 neighbourhoods read") {
    for (int w : sides())
        for (int h : {1, 2, 5, 8, 9, 16, 17, w}) {
            const Vec2<float> viewport = vec2(float(w), float(h)), last = vec2(float(w - 1), float(h - 1));
            for (int ty = 0; ty < (h + 7) / 8; ++ty)
                for (int tx = 0; tx < (w + 7) / 8; ++tx) {
                    // The texels read, as the silhouette pass reads them (`neighbour_texel`).
                    std::vector<std::pair<int, int>> read;
                    for (int y = ty * 8; y < std::min(ty * 8 + 8, h); ++y)
                        for (int x = tx * 8; x < std::min(tx * 8 + 8, w); ++x)
                            for (int dy = -1; dy <= 1; ++dy)
                                for (int dx = -1; dx <= 1; ++dx) {
                                    const Vec2<float> n = neighbour_texel(vec2(x + 0.5f, y + 0.5f), float(dx), float(dy), last);
                                    read.push_back({int(n[0]), int(n[1])});
                                }
                    std::sort(read.begin(), read.end());
                    read.erase(std::unique(read.begin(), read.end()), read.end());
                    const Vec4<float> r = outline_tile_reach(vec2(float(tx), float(ty)), viewport);
                    long outside = 0, inside = 0;
                    for (const auto& [x, y] : read) {
                        const bool in = x >= r[0] && x <= r[2] && y >= r[1] && y <= r[3];
                        outside += !in;
                        inside += in;
                    }
                    const long missed = long(r[2] - r[0] + 1) * long(r[3] - r[1] + 1) - inside;
                    INFO(w << " x " << h << ", tile " << tx << ", " << ty);
                    REQUIRE(outside == 0);  // nothing read lies outside the reach
                    REQUIRE(missed == 0);   // and the reach reads nothing more
                }
        }
}

TEST_CASE("an outline tile's 8-pixel point keeps its centre in the view and covers the whole tile") {
    long partial = 0;
    for (int w : sides())
        for (int h : {1, 3, 7, 8, 9, 15, 16, w}) {
            const Vec2<float> viewport = vec2(float(w), float(h));
            for (int ty = 0; ty < (h + 7) / 8; ++ty)
                for (int tx = 0; tx < (w + 7) / 8; ++tx) {
                    const Vec2<float> c = outline_tile_centre(vec2(float(tx), float(ty)), viewport);
                    INFO(w << " x " << h << ", tile " << tx << ", " << ty << ": centre " << c[0] << ", " << c[1]);
                    // GL clips a point whose centre leaves the view.
                    REQUIRE(c[0] > 0.0f);
                    REQUIRE(c[0] < float(w));
                    REQUIRE(c[1] > 0.0f);
                    REQUIRE(c[1] < float(h));
                    // Every pixel centre of the tile lies strictly inside the point's square
                    // (no pixel depends on the rasteriser's edge rule).
                    for (int k = 0; k < 2; ++k) {
                        const int t = k == 0 ? tx : ty, size = k == 0 ? w : h;
                        const float first = 8.0f * t + 0.5f, lastc = float(std::min(8 * t + 8, size) - 1) + 0.5f;
                        REQUIRE(first > c[k] - 4.0f);
                        REQUIRE(lastc < c[k] + 4.0f);
                    }
                    partial += (8 * tx + 8 > w) || (8 * ty + 8 > h);
                }
        }
    CHECK(partial > 0);
}

TEST_CASE("the cleared geometry-buffer texel: recognised, -0 included, and nine of them draw no outline") {
    const Vec4<float> c = cleared_gnormal<float>();
    CHECK(is_cleared_gnormal(c));
    CHECK(is_cleared_gnormal(vec4(-0.0f, 0.0f, -0.0f, 1.0f)));
    for (int k = 0; k < 4; ++k) {
        Vec4<float> g = c;
        g[k] = k == 3 ? 0.999f : 1e-30f;
        CHECK_FALSE(is_cleared_gnormal(g));
    }
    // A perspective projection (near 0.1, far 100) and the outline thresholds of the demos.
    const float n = 0.1f, f = 100.0f;
    const Vec4<float> pz = vec4(-(f + n) / (f - n), -2.0f * f * n / (f - n), -1.0f, 0.0f);
    const Vec4<float> params = vec4(0.05f, 0.5f, 1.0f, 0.0f);
    float depth[9];
    Vec3<float> normal[9];
    for (int i = 0; i < 9; ++i) {
        depth[i] = c[3];
        normal[i] = vec3(c[0], c[1], c[2]);
    }
    CHECK(silhouette_weight(depth, normal, pz, params) == 0.0f);
    // One drawn texel beside the centre gives an outline: the test is needed there.
    depth[5] = 0.9f;
    normal[5] = vec3(0.0f, 0.0f, 1.0f);
    CHECK(silhouette_weight(depth, normal, pz, params) > 0.0f);
}
