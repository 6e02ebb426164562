// src/gl/validate.cpp -- the renderers' input checks (quadcast/render/validate.hpp), compiled once
#include "quadcast/gl/validate.hpp"

#include "quadcast/render/validate.hpp"

namespace quadcast::gl {

void validate_primitives(const std::vector<render::Primitive>& prims) { render::validate_primitives(prims); }

}  // namespace quadcast::gl
