// quadcast/codegen/stages.hpp -- complete stage shaders assembled around traced kernels
#pragma once

#include <string>
#include <vector>

namespace quadcast::codegen {

/// One complete shader: its name (also the lookup key in the embedded table), its path under
/// generated/ and its text.
struct StageShader {
    std::string name, path, text;
};

/// The vertex and fragment shaders of the quadric renderer: one vertex shader per camera model,
/// one fragment shader per (variant, culling, camera model).
std::vector<StageShader> render_stage_shaders();

}  // namespace quadcast::codegen
