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

/// The vertex and fragment shaders of the isosurface renderer: per scheme (QSS, S31, trilinear)
/// and camera model one vertex shader, one forward and one geometry-buffer fragment shader.
std::vector<StageShader> spline_stage_shaders();

}  // namespace quadcast::codegen
