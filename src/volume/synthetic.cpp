// src/volume/synthetic.cpp -- synthetic test volumes: Marschner-Lobb and the 3-D Franke function
#include "quadcast/volume/synthetic.hpp"

#include <cmath>
#include <numbers>

namespace quadcast::volume {

double marschner_lobb(double x, double y, double z) {
    constexpr double pi = std::numbers::pi, fm = 6.0, alpha = 0.25;
    const double r = std::sqrt(x * x + y * y);
    const double rho_r = std::cos(2.0 * pi * fm * std::cos(pi * r / 2.0));
    return (1.0 - std::sin(pi * z / 2.0) + alpha * (1.0 + rho_r)) / (2.0 * (1.0 + alpha));
}

double franke3(double x, double y, double z) {
    const double a = 9.0 * x, b = 9.0 * y, c = 9.0 * z;
    return 0.75 * std::exp(-((a - 2) * (a - 2) + (b - 2) * (b - 2) + (c - 2) * (c - 2)) / 4.0) +
           0.75 * std::exp(-(a + 1) * (a + 1) / 49.0 - (b + 1) / 10.0 - (c + 1) / 10.0) +
           0.5 * std::exp(-((a - 7) * (a - 7) + (b - 3) * (b - 3) + (c - 5) * (c - 5)) / 4.0) -
           0.2 * std::exp(-(a - 4) * (a - 4) - (b - 7) * (b - 7) - (c - 5) * (c - 5));
}

namespace {

template <class F>
VolumeData sample(int n, double lo, double hi, F&& f, std::string source) {
    if (n < 2) throw VolumeError(source, -1, 0, "size", "needs at least 2 samples per axis, found " + std::to_string(n));
    if (n > 2048) throw VolumeError(source, -1, 0, "size", "at most 2048 samples per axis, found " + std::to_string(n));
    VolumeData v;
    v.source = std::move(source);
    v.grid = spline::Volume<float>(n, n, n);
    const double h = (hi - lo) / (n - 1);
    v.spacing = Vec3d{{h, h, h}};
    v.origin = Vec3d{{lo, lo, lo}};
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                v.grid.at(i, j, k) = static_cast<float>(f(lo + h * i, lo + h * j, lo + h * k));
    update_range(v);
    return v;
}

}  // namespace

VolumeData marschner_lobb_volume(int n) {
    return sample(n, -1.0, 1.0, marschner_lobb, "marschner-lobb " + dims_string(n, n, n) + " (f_M = 6, alpha = 0.25)");
}

VolumeData franke_volume(int n) {
    return sample(n, 0.0, 1.0, franke3, "franke " + dims_string(n, n, n));
}

}  // namespace quadcast::volume
