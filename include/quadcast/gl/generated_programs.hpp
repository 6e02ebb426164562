// quadcast/gl/generated_programs.hpp -- programs of generated shaders by variant key, compiled on first use and kept
#pragma once

#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "quadcast/gl/loader.hpp"
#include "quadcast/gl/program.hpp"
#include "quadcast/gl/stages.hpp"
#include "quadcast/render/variant_key.hpp"

namespace quadcast::gl {

/// The programs a renderer builds from the stages of variant keys (quadcast::gl::program_stages);
/// each is assembled, compiled and linked on first use. `owner` names the renderer in errors.
class GeneratedPrograms {
public:
    GeneratedPrograms(const Api& api, std::string owner) : api_(&api), owner_(std::move(owner)) {}

    const Program& get(const render::QuadricKey& k) {
        try {
            render::check(k);
        } catch (const std::invalid_argument& e) {
            throw std::runtime_error(owner_ + ": " + e.what());
        }
        const render::QuadricKey c = render::canonical(k);
        return cached(render::key_name(c), [&] { return program_stages(c); });
    }
    const Program& get(const render::DeferredKey& k) {
        return cached(render::key_name(k), [&] { return program_stages(k); });
    }
    const Program& get(const render::IsoKey& k) {
        return cached(render::key_name(k), [&] { return program_stages(k); });
    }
    const Program& get(const render::SlimKey& k) {
        render::SlimKey c = k;
        if (c.pass == render::SlimPass::resolve) c.cull = true;
        return cached(render::key_name(c), [&] { return program_stages(c); });
    }
    const Program& get(const render::OcclusionKey& k) {
        return cached(render::key_name(k), [&] { return program_stages(k); });
    }
    /// The compute pre-pass of the precomputed isosurface stages.
    const Program& compute(render::VolumeScheme s) {
        return cached(std::string("iso-coefficients:") + render::volume_scheme_name(s), [&] { return std::vector<StageText>{coefficient_stage(s)}; });
    }
    /// The passes of the isosurface renderer's occlusion culling.
    const Program& occlusion_bounds(bool ortho, bool cells) {
        return cached(std::string("iso-occlusion-bounds:") + (cells ? "cells:" : "") + (ortho ? "ortho" : "perspective"),
                      [&] { return std::vector<StageText>{occlusion_bound_stage(ortho, cells)}; });
    }
    const Program& pyramid_base() {
        return cached("iso-pyramid-base", [&] { return std::vector<StageText>{pyramid_base_stage()}; });
    }

private:
    template <class Stages>
    const Program& cached(const std::string& key, Stages stages) {
        if (auto it = programs_.find(key); it != programs_.end()) return *it->second;
        const std::vector<StageText> st = stages();
        std::vector<Shader> shaders;
        shaders.reserve(st.size());
        std::string name;
        for (const StageText& s : st) {
            const GLenum kind = s.kind == StageText::Kind::vertex ? GL_VERTEX_SHADER : s.kind == StageText::Kind::fragment ? GL_FRAGMENT_SHADER : GL_COMPUTE_SHADER;
            shaders.push_back(compile_shader(*api_, kind, s.text, s.name));
            name += (name.empty() ? "" : "+") + s.name;
        }
        std::vector<GLuint> ids;
        for (const Shader& s : shaders) ids.push_back(s.id());
        return *programs_.emplace(key, std::make_unique<Program>(detail::link_ids(*api_, ids, name))).first->second;
    }

    const Api* api_;
    std::string owner_;
    std::map<std::string, std::unique_ptr<Program>> programs_;
};

}  // namespace quadcast::gl
