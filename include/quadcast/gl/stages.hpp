// quadcast/gl/stages.hpp -- the stage shaders of a variant key, assembled from the generated kernels
#pragma once
// Each traced function is stored once (quadcast/generated/shaders.hpp); the stage plumbing
// (inputs, outputs, uniforms, fetches, main) is assembled around the kernels a key needs, here at
// run time. Compiled into the quadcast::gl library (src/gl/stages.cpp, src/gl/spline_stages.cpp).

#include <string>
#include <vector>

#include "quadcast/render/variant_key.hpp"

namespace quadcast::gl {

/// One stage shader of a program.
struct StageText {
    enum class Kind { vertex, fragment, compute };
    Kind kind;
    std::string name;  ///< a file-like name for messages, e.g. `qc_quadric_slab_nocull_ortho.frag`
    std::string text;  ///< the complete GLSL, `#version 450 core` first
};

/// The texture unit of the ids target in the quadric pass's stages that read it (QuadricKey::reshade).
inline constexpr unsigned reshade_ids_unit = 6;

/// The vertex and fragment stages of the quadric pass for `k` (canonical or not); throws
/// std::invalid_argument for a key without stages (render::check).
std::vector<StageText> program_stages(const render::QuadricKey& k);

/// The full-screen vertex stage and the fragment stage of the deferred pass.
std::vector<StageText> program_stages(const render::DeferredKey& k);

/// The vertex and fragment stages of the isosurface pass.
std::vector<StageText> program_stages(const render::IsoKey& k);

/// The stages of a SLIM pass (src/gl/slim_stages.cpp): the quadric renderer's vertex stage and
/// the ball's fragment stage, or the full-screen resolve.
std::vector<StageText> program_stages(const render::SlimKey& k);

/// The stages of an occlusion-culling pass: one compute stage, or (OcclusionPass::occluder_raster)
/// a vertex and a fragment stage.
std::vector<StageText> program_stages(const render::OcclusionKey& k);

/// The compute stage of a pass of the isosurface renderer's GPU element list
/// (OcclusionPass::element_cull_cubes, element_cull_tets, element_cull_cells, element_compact;
/// src/gl/spline_stages.cpp).
StageText element_list_stage(render::OcclusionPass pass);

/// The compute pre-pass of the `precomputed` isosurface stages (QSS and S31): the coefficients of
/// every drawn tetrahedron by repeated averaging.
StageText coefficient_stage(render::VolumeScheme s);

/// The isosurface renderer's occlusion culling: the pass that culls each element of a phase (a
/// tetrahedron, or with `cells` a trilinear cell) against the max-depth pyramid or gives its depth
/// floor (`spline::tet_occlusion_bound`, `cell_occlusion_bound`), and the pass that makes the
/// pyramid's level 0 from the copy of the depth buffer.
StageText occlusion_bound_stage(bool ortho, bool cells);
StageText pyramid_base_stage();

}  // namespace quadcast::gl
