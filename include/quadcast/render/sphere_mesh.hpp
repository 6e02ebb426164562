// quadcast/render/sphere_mesh.hpp -- geodesic tessellation of the unit sphere and its distance to the sphere
#pragma once
// Host-only; no GL. The tessellated spheres that the impostors are compared with
// (`quadcast bench meshes`, tests/gl): each face of the icosahedron is cut into f^2 triangles
// (class I geodesic sphere of frequency f: 10 f^2 + 2 vertices, 20 f^2 triangles) and the
// vertices are pushed onto the sphere, so the mesh is inscribed in it.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <vector>

#include "quadcast/linalg.hpp"

namespace quadcast::render {

/// A tessellated unit sphere in double: vertices on the sphere (each is its own normal),
/// triangles counter-clockwise seen from outside.
struct SphereMesh {
    int frequency = 0;
    std::vector<Vec3<double>> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

/// The geodesic sphere of frequency f >= 1 (f = 1: the icosahedron). Vertex i + j/f along the
/// edges of an icosahedron face, (A + (B - A) i / f + (C - A) j / f) normalised, in double;
/// vertices shared by neighbouring faces are merged (equal to 1e-9 after rounding).
inline SphereMesh geodesic_sphere(int f) {
    if (f < 1 || f > 4096) throw std::invalid_argument("quadcast::render::geodesic_sphere: frequency must be in [1, 4096]");
    const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
    const Vec3<double> ico[12] = {{{-1, phi, 0}}, {{1, phi, 0}}, {{-1, -phi, 0}}, {{1, -phi, 0}}, {{0, -1, phi}}, {{0, 1, phi}},
                                  {{0, -1, -phi}}, {{0, 1, -phi}}, {{phi, 0, -1}}, {{phi, 0, 1}}, {{-phi, 0, -1}}, {{-phi, 0, 1}}};
    const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                              {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                              {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    SphereMesh m;
    m.frequency = f;
    std::map<std::array<long long, 3>, std::uint32_t> merged;
    auto vertex = [&](const Vec3<double>& p) {
        const Vec3<double> u = normalize(p);
        const std::array<long long, 3> key = {std::llround(u[0] * 1e9), std::llround(u[1] * 1e9), std::llround(u[2] * 1e9)};
        auto it = merged.find(key);
        if (it != merged.end()) return it->second;
        const auto id = static_cast<std::uint32_t>(m.vertices.size());
        m.vertices.push_back(u);
        merged.emplace(key, id);
        return id;
    };
    std::vector<std::uint32_t> grid;
    for (const auto& fc : faces) {
        Vec3<double> a = ico[fc[0]], b = ico[fc[1]], c = ico[fc[2]];
        if (dot(cross(b - a, c - a), a + b + c) < 0) std::swap(b, c);  // counter-clockwise from outside
        // grid[i (f + 1) + j]: the vertex at i/f along a->b and j/f along a->c (i + j <= f)
        grid.assign(static_cast<std::size_t>((f + 1) * (f + 1)), 0);
        for (int i = 0; i <= f; ++i)
            for (int j = 0; i + j <= f; ++j)
                grid[static_cast<std::size_t>(i * (f + 1) + j)] = vertex(a + (b - a) * (double(i) / f) + (c - a) * (double(j) / f));
        auto at = [&](int i, int j) { return grid[static_cast<std::size_t>(i * (f + 1) + j)]; };
        for (int i = 0; i < f; ++i)
            for (int j = 0; i + j < f; ++j) {
                m.triangles.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
                if (i + j + 1 < f) m.triangles.push_back({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
            }
    }
    return m;
}

/// 1 - (the smallest distance from the centre to a triangle's plane), in double: the largest
/// distance between the unit sphere and the inscribed mesh (an upper bound; exact where the
/// foot of the centre lies in its triangle, which holds for these nearly equilateral triangles).
/// The mesh contains the ball of radius 1 - sagitta and lies in the unit ball, so its outline
/// lies between the outlines of the two spheres.
inline double sphere_mesh_sagitta(const SphereMesh& m) {
    double dmin = 1.0;
    for (const auto& t : m.triangles) {
        const Vec3<double>& a = m.vertices[t[0]];
        const Vec3<double> n = normalize(cross(m.vertices[t[1]] - a, m.vertices[t[2]] - a));
        dmin = std::min(dmin, std::fabs(dot(n, a)));
    }
    return 1.0 - dmin;
}

}  // namespace quadcast::render
