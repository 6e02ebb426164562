// tests/core/exact_tet.hpp -- point in tetrahedron in long double: the independent containment test
// of the tests of tetrahedral bounds, clip tetrahedra and their refinement
#pragma once

#include <array>

#include "quadcast/linalg.hpp"

namespace qc_exact {

using LD = long double;

/// v in long double.
template <class T>
quadcast::Vec3<LD> to_ld(const quadcast::Vec3<T>& v) {
    return quadcast::vec3(LD(v[0]), LD(v[1]), LD(v[2]));
}

/// det[a, b, c] (six times the signed volume of the tetrahedron 0, a, b, c), in long double.
inline LD det3(const quadcast::Vec3<LD>& a, const quadcast::Vec3<LD>& b, const quadcast::Vec3<LD>& c) {
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}

/// Six times the signed volume of the tetrahedron p0 p1 p2 p3, in long double (the corners are
/// converted before any arithmetic).
template <class T>
LD volume6(const quadcast::Vec3<T>& p0, const quadcast::Vec3<T>& p1, const quadcast::Vec3<T>& p2, const quadcast::Vec3<T>& p3) {
    const auto a = to_ld(p0);
    return det3(to_ld(p1) - a, to_ld(p2) - a, to_ld(p3) - a);
}

/// The barycentric coordinates of x in the tetrahedron p[0..3] (ratios of volumes, long double).
/// `P` is anything indexed by 0..3 giving a Vec3 (a C array, std::array, BoundingTet::p).
template <class P, class T>
std::array<LD, 4> barycentric(const P& p, const quadcast::Vec3<T>& x) {
    const LD v = volume6(p[0], p[1], p[2], p[3]);
    std::array<LD, 4> l{};
    for (int i = 0; i < 4; ++i) {
        quadcast::Vec3<T> q[4] = {p[0], p[1], p[2], p[3]};
        q[i] = x;
        l[static_cast<std::size_t>(i)] = volume6(q[0], q[1], q[2], q[3]) / v;
    }
    return l;
}

/// x lies in the tetrahedron p[0..3]: every barycentric coordinate >= -slack.
template <class P, class T>
bool in_tetrahedron(const P& p, const quadcast::Vec3<T>& x, LD slack = 0) {
    for (const LD l : barycentric(p, x))
        if (l < -slack) return false;
    return true;
}

}  // namespace qc_exact
