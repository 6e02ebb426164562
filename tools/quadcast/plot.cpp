// tools/quadcast/plot.cpp -- log-log scatter plots drawn into an RGBA image (benchmark figures)
#include "plot.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>

namespace quadcast::cli {

namespace {

/// A 5x7 glyph: 7 rows top first, bit 4 = leftmost column.
struct Glyph {
    char c;
    std::array<std::uint8_t, 7> rows;
};

constexpr Glyph font[] = {
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}}, {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}}, {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}}, {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}}, {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}}, {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'A', {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}}, {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}}, {'D', {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}},
    {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}}, {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
    {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}}, {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}}, {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}}, {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}}, {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
    {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
    {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}}, {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}}, {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}}, {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}}, {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
    {' ', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}}, {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
    {',', {0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08}}, {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
    {'+', {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}}, {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}},
    {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}}, {'/', {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}},
    {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}}, {'=', {0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00}},
    {'^', {0x04, 0x0A, 0x11, 0x00, 0x00, 0x00, 0x00}}, {'%', {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}},
    {'_', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F}}, {'*', {0x00, 0x04, 0x15, 0x0E, 0x15, 0x04, 0x00}},
    {'[', {0x0E, 0x08, 0x08, 0x08, 0x08, 0x08, 0x0E}}, {']', {0x0E, 0x02, 0x02, 0x02, 0x02, 0x02, 0x0E}},
    {'|', {0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}}, {'?', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x00, 0x04}},
};

const Glyph& glyph(char c) {
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
    for (const Glyph& g : font)
        if (g.c == c) return g;
    return font[sizeof font / sizeof font[0] - 1];  // '?'
}

using Rgb = std::array<std::uint8_t, 3>;

class Canvas {
public:
    Canvas(int w, int h) {
        img_.width = w;
        img_.height = h;
        img_.rgba.assign(std::size_t(w) * h * 4, 255);
        img_.depth.assign(std::size_t(w) * h, 1.0f);
    }
    int width() const { return img_.width; }
    int height() const { return img_.height; }
    /// Pixel (x, y), y = 0 the top row.
    void set(int x, int y, Rgb c) {
        if (x < 0 || y < 0 || x >= img_.width || y >= img_.height) return;
        std::uint8_t* p = &img_.rgba[(std::size_t(y) * img_.width + x) * 4];
        p[0] = c[0];
        p[1] = c[1];
        p[2] = c[2];
    }
    void fill(int x0, int y0, int x1, int y1, Rgb c) {
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) set(x, y, c);
    }
    /// Bresenham line, `t` pixels thick (a t x t square per step).
    void line(int x0, int y0, int x1, int y1, Rgb c, int t = 1) {
        const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0), sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
        int err = dx + dy;
        while (true) {
            fill(x0 - (t - 1) / 2, y0 - (t - 1) / 2, x0 + t / 2, y0 + t / 2, c);
            if (x0 == x1 && y0 == y1) break;
            const int e2 = 2 * err;
            if (e2 >= dy) { err += dy; x0 += sx; }
            if (e2 <= dx) { err += dx; y0 += sy; }
        }
    }
    /// Text with its top-left corner at (x, y), glyph cells 6s x 8s; `vertical` runs bottom to top.
    void text(int x, int y, const std::string& s, Rgb c, int scale = 1, bool vertical = false) {
        for (std::size_t n = 0; n < s.size(); ++n) {
            const Glyph& g = glyph(s[n]);
            for (int r = 0; r < 7; ++r)
                for (int col = 0; col < 5; ++col) {
                    if (!((g.rows[static_cast<std::size_t>(r)] >> (4 - col)) & 1)) continue;
                    const int u = int(n) * 6 + col, v = r;  // glyph-space position
                    for (int a = 0; a < scale; ++a)
                        for (int b = 0; b < scale; ++b) {
                            if (vertical) set(x + v * scale + b, y - u * scale - a, c);
                            else set(x + u * scale + a, y + v * scale + b, c);
                        }
                }
        }
    }
    static int text_width(const std::string& s, int scale = 1) { return int(s.size()) * 6 * scale - scale; }
    /// Marker of kind k (circle, square, triangle, diamond, cross, plus, ...) centred at (x, y).
    void marker(int x, int y, int kind, Rgb c) {
        constexpr int r = 5;
        switch (kind % 6) {
        case 0:
            for (int v = -r; v <= r; ++v)
                for (int u = -r; u <= r; ++u)
                    if (u * u + v * v <= r * r) set(x + u, y + v, c);
            break;
        case 1: fill(x - r + 1, y - r + 1, x + r - 1, y + r - 1, c); break;
        case 2:
            for (int v = -r; v <= r; ++v) {
                const int half = (v + r) / 2;
                for (int u = -half; u <= half; ++u) set(x + u, y + v, c);
            }
            break;
        case 3:
            for (int v = -r; v <= r; ++v)
                for (int u = -(r - std::abs(v)); u <= r - std::abs(v); ++u) set(x + u, y + v, c);
            break;
        case 4:
            line(x - r, y - r, x + r, y + r, c, 3);
            line(x - r, y + r, x + r, y - r, c, 3);
            break;
        default:
            line(x - r, y, x + r, y, c, 3);
            line(x, y - r, x, y + r, c, 3);
            break;
        }
    }
    render::Image take() { return std::move(img_); }

private:
    render::Image img_;
};

constexpr Rgb palette[] = {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {255, 127, 14}, {148, 103, 189}, {140, 86, 75}, {23, 190, 207}, {127, 127, 127}};

/// "0.01", "100", "1E-05": a decade's label.
std::string decade_label(int e) {
    char buf[32];
    if (e >= -4 && e < 0) std::snprintf(buf, sizeof buf, "%.*f", -e, std::pow(10.0, e));
    else if (e >= 0 && e <= 5) std::snprintf(buf, sizeof buf, "%.0f", std::pow(10.0, e));
    else std::snprintf(buf, sizeof buf, "1E%d", e);
    return buf;
}

}  // namespace

render::Image draw_loglog(const LogLogPlot& plot, int width, int height) {
    if (width < 200 || height < 150) throw std::invalid_argument("draw_loglog: the image must be at least 200 x 150");
    // Data range in decades
    double xlo = HUGE_VAL, xhi = -HUGE_VAL, ylo = HUGE_VAL, yhi = -HUGE_VAL;
    auto usable = [](double x, double y) { return x > 0 && y > 0 && std::isfinite(x) && std::isfinite(y); };
    for (const PlotSeries& s : plot.series)
        for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
            if (usable(s.x[i], s.y[i])) {
                xlo = std::min(xlo, std::log10(s.x[i]));
                xhi = std::max(xhi, std::log10(s.x[i]));
                ylo = std::min(ylo, std::log10(s.y[i]));
                yhi = std::max(yhi, std::log10(s.y[i]));
            }
    if (!(xlo <= xhi)) xlo = 0, xhi = 1, ylo = 0, yhi = 1;
    // A margin of 3% of a decade keeps markers and labels off the frame
    xlo -= 0.03, xhi += 0.03, ylo -= 0.03, yhi += 0.03;
    const int ex0 = int(std::floor(xlo)), ex1 = std::max(ex0 + 1, int(std::ceil(xhi)));
    const int ey0 = int(std::floor(ylo)), ey1 = std::max(ey0 + 1, int(std::ceil(yhi)));
    Canvas cv(width, height);
    int legend_w = 0;
    for (const PlotSeries& s : plot.series) legend_w = std::max(legend_w, Canvas::text_width(s.name));
    const int left = 70, right = width - legend_w - 50, top = 30, bottom = height - 45;
    auto px = [&](double x) { return left + int(std::lround((std::log10(x) - ex0) / (ex1 - ex0) * (right - left))); };
    auto py = [&](double y) { return bottom - int(std::lround((std::log10(y) - ey0) / (ey1 - ey0) * (bottom - top))); };
    const Rgb grid{225, 225, 225}, ink{0, 0, 0};
    // Grid lines at decades and minor ticks at 2..9
    for (int e = ex0; e <= ex1; ++e) {
        const int x = px(std::pow(10.0, e));
        cv.line(x, top, x, bottom, grid);
        cv.line(x, bottom, x, bottom + 5, ink);
        const std::string l = decade_label(e);
        cv.text(x - Canvas::text_width(l) / 2, bottom + 9, l, ink);
        if (e < ex1)
            for (int m = 2; m <= 9; ++m) cv.line(px(m * std::pow(10.0, e)), bottom, px(m * std::pow(10.0, e)), bottom + 2, ink);
    }
    for (int e = ey0; e <= ey1; ++e) {
        const int y = py(std::pow(10.0, e));
        cv.line(left, y, right, y, grid);
        cv.line(left - 5, y, left, y, ink);
        const std::string l = decade_label(e);
        cv.text(left - 8 - Canvas::text_width(l), y - 3, l, ink);
        if (e < ey1)
            for (int m = 2; m <= 9; ++m) cv.line(left - 2, py(m * std::pow(10.0, e)), left, py(m * std::pow(10.0, e)), ink);
    }
    cv.line(left, top, left, bottom, ink);
    cv.line(left, bottom, right, bottom, ink);
    cv.line(right, top, right, bottom, ink);
    cv.line(left, top, right, top, ink);
    // Series: polyline, markers, point labels
    for (std::size_t k = 0; k < plot.series.size(); ++k) {
        const PlotSeries& s = plot.series[k];
        const Rgb c = palette[k % (sizeof palette / sizeof palette[0])];
        int last_x = 0, last_y = 0;
        bool have_last = false;
        for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
            if (!usable(s.x[i], s.y[i])) continue;
            const int x = px(s.x[i]), y = py(s.y[i]);
            if (have_last) cv.line(last_x, last_y, x, y, c);
            last_x = x;
            last_y = y;
            have_last = true;
        }
        for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
            if (!usable(s.x[i], s.y[i])) continue;
            const int x = px(s.x[i]), y = py(s.y[i]);
            cv.marker(x, y, int(k), c);
            if (i < s.labels.size()) cv.text(x + 7, y - 10, s.labels[i], c);
        }
        // Legend entry
        const int ly = top + 10 + int(k) * 16;
        cv.marker(right + 18, ly + 3, int(k), c);
        cv.text(right + 30, ly, s.name, ink);
    }
    cv.text((left + right) / 2 - Canvas::text_width(plot.title, 2) / 2, 8, plot.title, ink, 2);
    cv.text((left + right) / 2 - Canvas::text_width(plot.x_label) / 2, height - 16, plot.x_label, ink);
    cv.text(8, (top + bottom) / 2 + Canvas::text_width(plot.y_label) / 2, plot.y_label, ink, 1, true);
    return cv.take();
}

}  // namespace quadcast::cli
