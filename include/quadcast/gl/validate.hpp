// quadcast/gl/validate.hpp -- the renderers' input checks, compiled once in the quadcast::gl library
#pragma once
// quadcast/render/validate.hpp needs Eigen (eigen-decompositions in double); a renderer header
// that included it would cost every includer most of its compile time, so the GL renderers call
// it through the library.

#include <vector>

#include "quadcast/render/types.hpp"

namespace quadcast::gl {

/// quadcast::render::validate_primitives: throws std::invalid_argument naming the first primitive
/// that cannot be drawn as it says, and why.
void validate_primitives(const std::vector<render::Primitive>& prims);

}  // namespace quadcast::gl
