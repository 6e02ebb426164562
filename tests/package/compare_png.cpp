// tests/package/compare_png.cpp -- checks the README example's pictures: GL and CPU agree
#include <quadcast/image/image_io.hpp>

#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: compare_png GL.png CPU.png\n");
        return 2;
    }
    const quadcast::render::Image a = quadcast::render::read_png(argv[1]), b = quadcast::render::read_png(argv[2]);
    if (a.width != 1024 || a.height != 768 || b.width != a.width || b.height != a.height) {
        std::fprintf(stderr, "compare_png: unexpected sizes %dx%d, %dx%d\n", a.width, a.height, b.width, b.height);
        return 1;
    }
    // The background is white; a glyph pixel is anything else.
    long glyph = 0, coverage_diff = 0, colour_diff = 0, colours = 0;
    int seen[64] = {};
    for (std::size_t i = 0; i < std::size_t(a.width) * a.height; ++i) {
        const unsigned char* p = &a.rgba[i * 4];
        const unsigned char* q = &b.rgba[i * 4];
        const bool ga = !(p[0] == 255 && p[1] == 255 && p[2] == 255), gb = !(q[0] == 255 && q[1] == 255 && q[2] == 255);
        glyph += ga;
        if (ga != gb) { ++coverage_diff; continue; }
        for (int c = 0; c < 3; ++c)
            if (std::abs(int(p[c]) - int(q[c])) > 2) { ++colour_diff; break; }
        const int bin = (p[0] >> 6) * 16 + (p[1] >> 6) * 4 + (p[2] >> 6);
        if (ga && !seen[bin]++) ++colours;
    }
    std::printf("compare_png: %ld glyph pixels of %d, %ld coverage and %ld colour differences (> 2 LSB) between GL and CPU, %ld colour bins\n",
                glyph, a.width * a.height, coverage_diff, colour_diff, colours);
    const bool ok = glyph > a.width * a.height / 10 && coverage_diff <= glyph / 200 && colour_diff <= glyph / 50 && colours >= 8;
    return ok ? 0 : 1;
}
