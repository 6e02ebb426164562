// quadcast/gl/generated_programs.hpp -- programs of generated shaders, compiled on first use and kept
#pragma once

#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

#include "quadcast/generated/shaders.hpp"
#include "quadcast/gl/loader.hpp"
#include "quadcast/gl/program.hpp"

namespace quadcast::gl {

/// The programs a renderer builds from quadcast/generated/shaders.hpp, by shader name; each is
/// compiled and linked on first use. `owner` names the renderer in errors.
class GeneratedPrograms {
public:
    GeneratedPrograms(const Api& api, std::string owner) : api_(&api), owner_(std::move(owner)) {}

    /// The program of generated vertex shader `vs` and fragment shader `fs`.
    const Program& get(const std::string& vs, const std::string& fs) {
        const std::string key = vs + "+" + fs;
        if (auto it = programs_.find(key); it != programs_.end()) return *it->second;
        const std::string_view vsrc = source(vs), fsrc = source(fs);
        return keep(key, make_program(*api_, key, {{GL_VERTEX_SHADER, vsrc}, {GL_FRAGMENT_SHADER, fsrc}}));
    }

    /// The program of generated compute shader `cs`.
    const Program& compute(const std::string& cs) {
        if (auto it = programs_.find(cs); it != programs_.end()) return *it->second;
        return keep(cs, make_program(*api_, cs, {{GL_COMPUTE_SHADER, source(cs)}}));
    }

private:
    std::string_view source(const std::string& name) const {
        const std::string_view s = generated::find(name);
        if (s.empty()) throw std::runtime_error(owner_ + ": no generated shader " + name);
        return s;
    }
    const Program& keep(const std::string& key, Program p) {
        return *programs_.emplace(key, std::make_unique<Program>(std::move(p))).first->second;
    }

    const Api* api_;
    std::string owner_;
    std::map<std::string, std::unique_ptr<Program>> programs_;
};

}  // namespace quadcast::gl
