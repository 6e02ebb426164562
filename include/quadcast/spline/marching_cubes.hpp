// quadcast/spline/marching_cubes.hpp -- host side: marching-cubes isosurface of sampled data (indexed mesh, index space)
#pragma once

// The reference polygonisation the spline isosurfaces are compared with (Lorensen & Cline 1987),
// with a case table that is DERIVED, not typed in:
//
// - Cell corner c (0..7) is (c&1, (c>>1)&1, (c>>2)&1) of the cell; corner c is "above" iff its
//   sample is > ρ (a sample equal to ρ counts as below). Case = the 8 above bits.
// - Edge e (0..11) runs along axis a = e/4; its other two coordinates are the bits of r = e%4
//   (the lower-numbered free axis in bit 0): x edges 0-3 (y = r&1, z = r>>1), y edges 4-7
//   (x = r&1, z = r>>1), z edges 8-11 (x = r&1, y = r>>1). An edge crosses iff its ends differ.
// - Per cell face (4 corners in cyclic order) the crossing edges are joined by segments: 2
//   crossings give one segment; 4 crossings (the ambiguous face, diagonal corners alike) give two
//   segments, each cutting off one ABOVE corner (the above corners are always separated). Both
//   cells of a face see the same corners, hence the same segments: the mesh is crack-free.
// - Each segment is directed so that, seen from outside the cell, the above side is on its left.
//   Every crossing edge lies on two faces and is left by one segment and entered by the other,
//   so the segments chain into closed directed polygons. Each polygon is triangulated with
//   diagonals that never join two crossings on one face (interval dynamic programming over the
//   polygon, first admissible split; such a diagonal would lie in the face and be shared by
//   the triangles of both cells, four in all): then every diagonal is inside the cell and
//   used by two triangles of its polygon, and every segment by one triangle on each side of
//   its face, so the mesh is a closed 2-manifold away from the grid border. On a face shared
//   by two cells the segment has opposite directions, so the triangles are consistently
//   oriented across cells: counter-clockwise seen from the above side (the right-hand normal
//   points towards larger values, like the gradient).
//
// The table is built by a function (`make_table`, into `mc_table`); tests check that every one of the
// 256 cases closes its polygons. Vertices: one per crossing grid edge, shared by all cells
// around it, at the root of the linear interpolant along the edge,
// p = p0 + t (p1 - p0), t = (ρ - f0) / (f1 - f0) (double, rounded to float once); normals: the
// central-difference gradient of the samples (one-sided at the border), linearly interpolated
// with the same t and normalised (zero where it vanishes).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "quadcast/linalg.hpp"
#include "quadcast/spline/grid.hpp"

namespace quadcast::spline {

/// The polygons and triangles of one marching-cubes case (edge numbers as at the top of this file).
struct McCase {
    int polygon_count = 0;
    std::array<std::array<std::int8_t, 12>, 4> polygon{};  ///< edges of each closed polygon, in order
    std::array<int, 4> polygon_size{};
    int triangle_count = 0;
    std::array<std::array<std::int8_t, 3>, 12> triangle{};  ///< the polygons, triangulated
    bool closed = true;  ///< every segment chain closed and triangulated (the tests check all 256 cases)
};

namespace mc_detail {

/// Corner c of the unit cell scaled by 6 (so centroids of up to 3 corners stay integers).
constexpr std::array<int, 3> corner6(int c) { return {6 * (c & 1), 6 * ((c >> 1) & 1), 6 * ((c >> 2) & 1)}; }

/// The two corners of edge e (lower end first).
constexpr std::array<int, 2> edge_corners(int e) {
    const int a = e / 4, r = e % 4;
    const int u = a == 0 ? 1 : 0, v = a == 2 ? 1 : 2;  // the free axes, lower first
    const int base = ((r & 1) << u) | ((r >> 1) << v);
    return {base, base | (1 << a)};
}

/// The edge joining corners c0 and c1 (adjacent), or -1.
constexpr int edge_of(int c0, int c1) {
    for (int e = 0; e < 12; ++e) {
        const auto k = edge_corners(e);
        if ((k[0] == c0 && k[1] == c1) || (k[0] == c1 && k[1] == c0)) return e;
    }
    return -1;
}

/// Face f (0..5) = axis f/2 at side f%2: its corners in cyclic order and its outward normal.
struct Face {
    std::array<int, 4> corner;
    std::array<int, 3> normal;
};

constexpr Face face(int f) {
    const int a = f / 2, s = f % 2;
    const int u = a == 0 ? 1 : 0, v = a == 2 ? 1 : 2;
    const int side = s << a;
    Face r{};
    r.corner = {side, side | (1 << u), side | (1 << u) | (1 << v), side | (1 << v)};
    r.normal = {0, 0, 0};
    r.normal[static_cast<std::size_t>(a)] = s ? 1 : -1;
    return r;
}

/// Midpoint of edge e, scaled by 6.
constexpr std::array<int, 3> edge_mid6(int e) {
    const auto k = edge_corners(e);
    const auto p = corner6(k[0]), q = corner6(k[1]);
    return {(p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2};
}

/// The segment (e0 -> e1) directed so that the point `above` lies on its left seen along the
/// outward normal n: ((m1 - m0) x (above - m0)) . n > 0; otherwise reversed.
constexpr std::array<int, 2> directed(int e0, int e1, const std::array<int, 3>& above, const std::array<int, 3>& n) {
    const auto m0 = edge_mid6(e0), m1 = edge_mid6(e1);
    const int d[3] = {m1[0] - m0[0], m1[1] - m0[1], m1[2] - m0[2]};
    const int w[3] = {above[0] - m0[0], above[1] - m0[1], above[2] - m0[2]};
    const int c[3] = {d[1] * w[2] - d[2] * w[1], d[2] * w[0] - d[0] * w[2], d[0] * w[1] - d[1] * w[0]};
    const int s = c[0] * n[0] + c[1] * n[1] + c[2] * n[2];
    return s > 0 ? std::array<int, 2>{e0, e1} : std::array<int, 2>{e1, e0};
}

/// Do grid edges e and f lie on a common face of the cell?
constexpr bool share_face(int e, int f) {
    const auto a = edge_corners(e), b = edge_corners(f);
    for (int ax = 0; ax < 3; ++ax) {
        const int s = (a[0] >> ax) & 1;
        if (((a[1] >> ax) & 1) == s && ((b[0] >> ax) & 1) == s && ((b[1] >> ax) & 1) == s) return true;
    }
    return false;
}

/// Triangulates polygon p of `c` (appending to c.triangle) with diagonals between crossings on
/// no common face: split[i][j] = a vertex k of the sub-polygon i..j with admissible chords
/// (i, k) and (k, j) and triangulable sub-polygons; triangles (i, k, j) keep the polygon's
/// orientation. Returns false if no such triangulation exists.
constexpr bool triangulate(McCase& c, int p) {
    const int n = c.polygon_size[p];
    const auto& v = c.polygon[p];
    auto chord_ok = [&](int i, int j) { return j == i + 1 || (i == 0 && j == n - 1) || !share_face(v[i], v[j]); };
    int split[12][12] = {};
    for (int len = 1; len < n; ++len)
        for (int i = 0; i + len < n; ++i) {
            const int j = i + len;
            split[i][j] = len == 1 ? 0 : -1;
            for (int k = i + 1; k < j && split[i][j] < 0; ++k)
                if (chord_ok(i, k) && chord_ok(k, j) && (k == i + 1 || split[i][k] > 0) && (j == k + 1 || split[k][j] > 0))
                    split[i][j] = k;
        }
    if (split[0][n - 1] <= 0) return false;
    int stack[24][2] = {}, top = 0;
    stack[top][0] = 0;
    stack[top++][1] = n - 1;
    while (top > 0) {
        --top;
        const int i = stack[top][0], j = stack[top][1];
        if (j == i + 1) continue;
        const int k = split[i][j];
        c.triangle[c.triangle_count++] = {v[i], v[k], v[j]};
        stack[top][0] = i;
        stack[top++][1] = k;
        stack[top][0] = k;
        stack[top++][1] = j;
    }
    return true;
}

constexpr McCase make_case(int code) {
    McCase out{};
    auto above = [code](int c) { return ((code >> c) & 1) != 0; };
    int next[12];  // next[e] = edge the segment leaving e goes to, -1 if none
    int in_count[12] = {};
    for (int e = 0; e < 12; ++e) next[e] = -1;
    bool ok = true;
    auto add = [&](const std::array<int, 2>& s) {
        if (next[s[0]] != -1) ok = false;
        next[s[0]] = s[1];
        ++in_count[s[1]];
    };
    for (int f = 0; f < 6; ++f) {
        const Face F = face(f);
        int cross[4], nc = 0;  // face edge i joins corner i and i+1
        for (int i = 0; i < 4; ++i)
            if (above(F.corner[i]) != above(F.corner[(i + 1) % 4])) cross[nc++] = i;
        if (nc == 2) {
            // The centroid of the face's above corners is strictly on the above side of the segment
            std::array<int, 3> sum{0, 0, 0};
            int na = 0;
            for (int i = 0; i < 4; ++i)
                if (above(F.corner[i])) {
                    const auto p = corner6(F.corner[i]);
                    for (int a = 0; a < 3; ++a) sum[a] += p[a];
                    ++na;
                }
            for (int a = 0; a < 3; ++a) sum[a] /= na;
            const int e0 = edge_of(F.corner[cross[0]], F.corner[(cross[0] + 1) % 4]);
            const int e1 = edge_of(F.corner[cross[1]], F.corner[(cross[1] + 1) % 4]);
            add(directed(e0, e1, sum, F.normal));
        } else if (nc == 4) {
            // Ambiguous face: cut off each above corner on its own
            for (int i = 0; i < 4; ++i) {
                if (!above(F.corner[i])) continue;
                const int prev = F.corner[(i + 3) % 4], c = F.corner[i], nxt = F.corner[(i + 1) % 4];
                add(directed(edge_of(prev, c), edge_of(c, nxt), corner6(c), F.normal));
            }
        }
    }
    // Chain the segments into polygons
    bool used[12] = {};
    for (int e = 0; e < 12; ++e) {
        if (next[e] < 0 || used[e]) continue;
        if (in_count[e] != 1) ok = false;
        const int p = out.polygon_count;
        if (p >= 4) {
            ok = false;
            break;
        }
        int n = 0, cur = e;
        while (!used[cur]) {
            used[cur] = true;
            out.polygon[p][n++] = static_cast<std::int8_t>(cur);
            cur = next[cur];
            if (cur < 0) {
                ok = false;
                break;
            }
        }
        if (cur != e) ok = false;  // the chain must return to its start
        out.polygon_size[p] = n;
        ++out.polygon_count;
        if (!triangulate(out, p)) ok = false;
    }
    for (int e = 0; e < 12; ++e)
        if (in_count[e] > 1) ok = false;
    out.closed = ok;
    return out;
}

constexpr std::array<McCase, 256> make_table() {
    std::array<McCase, 256> t{};
    for (int c = 0; c < 256; ++c) t[static_cast<std::size_t>(c)] = make_case(c);
    return t;
}

}  // namespace mc_detail

/// The 256 cases, generated from the face rule at the top of this file (by the constexpr
/// `make_table`, evaluated once at static initialisation: at compile time it exceeds Clang's
/// default constexpr step limit).
inline const std::array<McCase, 256> mc_table = mc_detail::make_table();

/// Edge e of a cell: its two corners (lower end first), corner c = (c&1, (c>>1)&1, (c>>2)&1).
constexpr std::array<int, 2> mc_edge_corners(int e) { return mc_detail::edge_corners(e); }

/// An indexed triangle mesh in the INDEX space of the samples (sample (i,j,k) at (i,j,k)).
struct McMesh {
    std::vector<Vec3<float>> positions;
    std::vector<Vec3<float>> normals;                 ///< unit central-difference gradients (towards larger values)
    std::vector<std::array<std::int32_t, 3>> triangles;  ///< counter-clockwise seen from the above side
    /// The cell of each triangle, ascending: cell (i,j,k) = [i, i+1] x [j, j+1] x [k, k+1] has
    /// number i + (nx-1) (j + (ny-1) k); every triangle lies inside its cell.
    std::vector<std::int32_t> triangle_cell;
    /// Per vertex, the grid edge it lies on: its lower sample (i fastest index) and axis.
    std::vector<std::int64_t> vertex_sample;
    std::vector<std::int8_t> vertex_axis;
};

/// The marching-cubes isosurface ρ of `vol` (see the top of this file). Cells are processed slab
/// by slab along z with two slices of edge-vertex indices, so memory is O(nx ny) besides the mesh.
/// Throws std::invalid_argument for a non-finite ρ, a non-finite sample (naming its (i,j,k)) or a
/// volume with fewer than 2 samples along an axis.
inline McMesh marching_cubes(const Volume<float>& vol, float rho) {
    if (!std::isfinite(rho)) throw std::invalid_argument("quadcast::spline::marching_cubes: isovalue is not finite");
    if (vol.nx < 2 || vol.ny < 2 || vol.nz < 2)
        throw std::invalid_argument("quadcast::spline::marching_cubes: needs at least 2 samples per axis");
    for (std::size_t n = 0; n < vol.data.size(); ++n)
        if (!std::isfinite(vol.data[n])) {
            const std::size_t i = n % static_cast<std::size_t>(vol.nx), j = (n / static_cast<std::size_t>(vol.nx)) % static_cast<std::size_t>(vol.ny),
                              k = n / (static_cast<std::size_t>(vol.nx) * static_cast<std::size_t>(vol.ny));
            throw std::invalid_argument("quadcast::spline::marching_cubes: sample (" + std::to_string(i) + "," + std::to_string(j) + "," +
                                        std::to_string(k) + ") is not finite");
        }
    const int nx = vol.nx, ny = vol.ny, nz = vol.nz;
    McMesh mesh;
    // Central differences (one-sided at the border), in index units
    auto gradient = [&](int i, int j, int k) {
        auto diff = [&](int a) {
            int lo[3] = {i, j, k}, hi[3] = {i, j, k};
            const int n[3] = {nx, ny, nz};
            lo[a] = std::max(0, lo[a] - 1);
            hi[a] = std::min(n[a] - 1, hi[a] + 1);
            return (double(vol.at(hi[0], hi[1], hi[2])) - double(vol.at(lo[0], lo[1], lo[2]))) / double(hi[a] - lo[a]);
        };
        return Vec3<double>{{diff(0), diff(1), diff(2)}};
    };
    const std::size_t slice = static_cast<std::size_t>(nx) * ny;
    // Vertex indices of the x and y edges of the even and odd slices (slab k uses slices k and
    // k+1, one of each parity), and of the z edges of the current slab
    std::vector<std::int32_t> ex_even(slice, -1), ey_even(slice, -1), ex_odd(slice, -1), ey_odd(slice, -1), ez(slice, -1);
    auto vertex = [&](int i, int j, int k, int axis) -> std::int32_t {
        std::vector<std::int32_t>& slot = axis == 2 ? ez : axis == 0 ? (k & 1 ? ex_odd : ex_even) : (k & 1 ? ey_odd : ey_even);
        std::int32_t& v = slot[static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * j];
        if (v >= 0) return v;
        const int i1 = i + (axis == 0), j1 = j + (axis == 1), k1 = k + (axis == 2);
        const double f0 = vol.at(i, j, k), f1 = vol.at(i1, j1, k1);
        const double t = (double(rho) - f0) / (f1 - f0);
        const double p0[3] = {double(i), double(j), double(k)};
        Vec3<float> p{};
        for (int a = 0; a < 3; ++a) p[a] = float(p0[a] + (a == axis ? t : 0.0));
        const Vec3<double> g = gradient(i, j, k) * (1.0 - t) + gradient(i1, j1, k1) * t;
        const double len = std::sqrt(dot(g, g));
        v = static_cast<std::int32_t>(mesh.positions.size());
        mesh.positions.push_back(p);
        mesh.normals.push_back(len > 0 ? cast<float>(g / len) : Vec3<float>{{0.0f, 0.0f, 0.0f}});
        mesh.vertex_sample.push_back(static_cast<std::int64_t>(vol.index(i, j, k)));
        mesh.vertex_axis.push_back(static_cast<std::int8_t>(axis));
        return v;
    };
    for (int k = 0; k + 1 < nz; ++k) {
        // Slice k keeps its vertices from the previous slab; slice k+1 reuses the buffers of k-1
        std::vector<std::int32_t>& x_next = (k + 1) & 1 ? ex_odd : ex_even;
        std::vector<std::int32_t>& y_next = (k + 1) & 1 ? ey_odd : ey_even;
        std::fill(x_next.begin(), x_next.end(), -1);
        std::fill(y_next.begin(), y_next.end(), -1);
        std::fill(ez.begin(), ez.end(), -1);
        for (int j = 0; j + 1 < ny; ++j)
            for (int i = 0; i + 1 < nx; ++i) {
                int code = 0;
                for (int c = 0; c < 8; ++c)
                    if (vol.at(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1)) > rho) code |= 1 << c;
                const McCase& mc = mc_table[static_cast<std::size_t>(code)];
                if (mc.triangle_count == 0) continue;
                std::int32_t ev[12];
                for (int e = 0; e < 12; ++e) ev[e] = -1;
                const std::int32_t cell = i + (nx - 1) * (j + (ny - 1) * k);
                for (int t = 0; t < mc.triangle_count; ++t) {
                    std::array<std::int32_t, 3> tri{};
                    for (int s = 0; s < 3; ++s) {
                        const int e = mc.triangle[t][s];
                        if (ev[e] < 0) {
                            const int c0 = mc_detail::edge_corners(e)[0];
                            ev[e] = vertex(i + (c0 & 1), j + ((c0 >> 1) & 1), k + ((c0 >> 2) & 1), e / 4);
                        }
                        tri[s] = ev[e];
                    }
                    mesh.triangles.push_back(tri);
                    mesh.triangle_cell.push_back(cell);
                }
            }
    }
    return mesh;
}

}  // namespace quadcast::spline
