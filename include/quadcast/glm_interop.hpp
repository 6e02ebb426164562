// quadcast/glm_interop.hpp -- zero-cost conversions between GLM and quadcast's Vec / Mat
#pragma once

// GLM is the host-facing vocabulary (cameras, model matrices, the shapes API); quadcast's own
// Vec<T, N> / Mat<T, R, C> are what the traced templates take. Both store vectors as N
// contiguous scalars and matrices column by column (m[col][row]), so a conversion is a copy of
// the same bytes (std::bit_cast, checked at compile time).

#include <bit>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "quadcast/linalg.hpp"

namespace quadcast {

namespace glm_detail {
template <class A, class B>
constexpr B same_bytes(const A& a) {
    static_assert(sizeof(A) == sizeof(B), "quadcast/glm_interop.hpp: GLM and quadcast layouts differ");
    return std::bit_cast<B>(a);
}
}  // namespace glm_detail

template <class T> Vec<T, 2> from_glm(const glm::vec<2, T, glm::defaultp>& v) { return glm_detail::same_bytes<glm::vec<2, T, glm::defaultp>, Vec<T, 2>>(v); }
template <class T> Vec<T, 3> from_glm(const glm::vec<3, T, glm::defaultp>& v) { return glm_detail::same_bytes<glm::vec<3, T, glm::defaultp>, Vec<T, 3>>(v); }
template <class T> Vec<T, 4> from_glm(const glm::vec<4, T, glm::defaultp>& v) { return glm_detail::same_bytes<glm::vec<4, T, glm::defaultp>, Vec<T, 4>>(v); }
template <class T> Mat<T, 3, 3> from_glm(const glm::mat<3, 3, T, glm::defaultp>& m) { return glm_detail::same_bytes<glm::mat<3, 3, T, glm::defaultp>, Mat<T, 3, 3>>(m); }
template <class T> Mat<T, 4, 4> from_glm(const glm::mat<4, 4, T, glm::defaultp>& m) { return glm_detail::same_bytes<glm::mat<4, 4, T, glm::defaultp>, Mat<T, 4, 4>>(m); }

template <class T> glm::vec<2, T, glm::defaultp> to_glm(const Vec<T, 2>& v) { return glm_detail::same_bytes<Vec<T, 2>, glm::vec<2, T, glm::defaultp>>(v); }
template <class T> glm::vec<3, T, glm::defaultp> to_glm(const Vec<T, 3>& v) { return glm_detail::same_bytes<Vec<T, 3>, glm::vec<3, T, glm::defaultp>>(v); }
template <class T> glm::vec<4, T, glm::defaultp> to_glm(const Vec<T, 4>& v) { return glm_detail::same_bytes<Vec<T, 4>, glm::vec<4, T, glm::defaultp>>(v); }
template <class T> glm::mat<3, 3, T, glm::defaultp> to_glm(const Mat<T, 3, 3>& m) { return glm_detail::same_bytes<Mat<T, 3, 3>, glm::mat<3, 3, T, glm::defaultp>>(m); }
template <class T> glm::mat<4, 4, T, glm::defaultp> to_glm(const Mat<T, 4, 4>& m) { return glm_detail::same_bytes<Mat<T, 4, 4>, glm::mat<4, 4, T, glm::defaultp>>(m); }

}  // namespace quadcast
