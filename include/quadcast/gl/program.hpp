// quadcast/gl/program.hpp -- compile and link GLSL programs; errors quote the offending source lines
#pragma once
// Host-only.

#include "quadcast/gl/loader.hpp"

#include <algorithm>
#include <cstdio>
#include <initializer_list>
#include <regex>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace quadcast::gl {

/// "compute shader", "fragment shader" ...
inline std::string stage_name(GLenum stage) {
    switch (stage) {
    case GL_VERTEX_SHADER: return "vertex shader";
    case GL_FRAGMENT_SHADER: return "fragment shader";
    case GL_GEOMETRY_SHADER: return "geometry shader";
    case GL_TESS_CONTROL_SHADER: return "tessellation control shader";
    case GL_TESS_EVALUATION_SHADER: return "tessellation evaluation shader";
    case GL_COMPUTE_SHADER: return "compute shader";
    default: return "shader (stage " + std::to_string(stage) + ")";
    }
}

/// One "error" line of an info log with the source position it names.
struct LogDiagnostic {
    int line = 0;     ///< 1-based source line, 0 when the log line names none
    int column = -1;  ///< column when the driver gives one (Mesa does), else -1
    bool error = true;  ///< error (true) or warning
    std::string text;   ///< the whole log line
};

/// Parses the positions out of a compiler info log. Understands Mesa ("0:12(5): error: ..."),
/// NVIDIA ("0(12) : error C0000: ...") and AMD/Intel/glslang ("ERROR: 0:12: ...").
inline std::vector<LogDiagnostic> parse_info_log(std::string_view log) {
    static const std::regex mesa(R"(^\s*\d+:(\d+)\((\d+)\):\s*(error|warning))", std::regex::icase);
    static const std::regex nvidia(R"(^\s*\d+\((\d+)\)\s*:\s*(error|warning))", std::regex::icase);
    static const std::regex khronos(R"(^\s*(error|warning):\s*\d+:(\d+):)", std::regex::icase);
    std::vector<LogDiagnostic> out;
    std::size_t pos = 0;
    while (pos < log.size()) {
        std::size_t eol = log.find('\n', pos);
        if (eol == std::string_view::npos) eol = log.size();
        std::string line(log.substr(pos, eol - pos));
        pos = eol + 1;
        if (line.empty()) continue;
        std::smatch m;
        LogDiagnostic d;
        d.text = line;
        auto is_error = [](const std::string& s) { return s[0] == 'e' || s[0] == 'E'; };
        if (std::regex_search(line, m, mesa)) {
            d.line = std::stoi(m[1]);
            d.column = std::stoi(m[2]);
            d.error = is_error(m[3]);
        } else if (std::regex_search(line, m, nvidia)) {
            d.line = std::stoi(m[1]);
            d.error = is_error(m[2]);
        } else if (std::regex_search(line, m, khronos)) {
            d.line = std::stoi(m[2]);
            d.error = is_error(m[1]);
        } else {
            continue;
        }
        out.push_back(std::move(d));
    }
    return out;
}

/// Lines `lines` of `source` (1-based) with `context` lines around each, numbered; the named
/// lines are marked with '>':
///       4 | void main() {
///   >   5 |     uint x = = 3;
inline std::string quote_source_lines(std::string_view source, const std::set<int>& lines, int context = 1) {
    std::vector<std::string_view> src;
    for (std::size_t pos = 0; pos <= source.size();) {
        std::size_t eol = source.find('\n', pos);
        if (eol == std::string_view::npos) eol = source.size();
        src.push_back(source.substr(pos, eol - pos));
        pos = eol + 1;
    }
    std::set<int> shown;
    for (int l : lines)
        for (int k = l - context; k <= l + context; ++k)
            if (k >= 1 && k <= static_cast<int>(src.size())) shown.insert(k);
    std::string out;
    int prev = 0;
    for (int k : shown) {
        if (prev != 0 && k != prev + 1) out += "        ...\n";
        char num[32];
        std::snprintf(num, sizeof num, "%s %5d | ", lines.count(k) ? ">" : " ", k);
        out += num;
        out += src[static_cast<std::size_t>(k - 1)];
        out += '\n';
        prev = k;
    }
    for (int l : lines)
        if (l > static_cast<int>(src.size()))
            out += "  (line " + std::to_string(l) + " is past the end of the " + std::to_string(src.size()) +
                   "-line source)\n";
    return out;
}

/// A shader failed to compile. what() holds the caller's name for the shader, the info log
/// and the offending source lines quoted with their numbers.
class ShaderCompileError : public std::runtime_error {
public:
    ShaderCompileError(std::string name, GLenum stage, std::string log, std::vector<LogDiagnostic> diagnostics,
                       const std::string& message)
        : std::runtime_error(message), name_(std::move(name)), stage_(stage), log_(std::move(log)),
          diagnostics_(std::move(diagnostics)) {}
    const std::string& name() const noexcept { return name_; }
    GLenum stage() const noexcept { return stage_; }
    const std::string& log() const noexcept { return log_; }
    const std::vector<LogDiagnostic>& diagnostics() const noexcept { return diagnostics_; }

private:
    std::string name_;
    GLenum stage_;
    std::string log_;
    std::vector<LogDiagnostic> diagnostics_;
};

/// A program failed to link (or a requested uniform does not exist).
class ProgramLinkError : public std::runtime_error {
public:
    ProgramLinkError(std::string name, std::string log, const std::string& message)
        : std::runtime_error(message), name_(std::move(name)), log_(std::move(log)) {}
    const std::string& name() const noexcept { return name_; }
    const std::string& log() const noexcept { return log_; }

private:
    std::string name_;
    std::string log_;
};

namespace detail {
inline std::string shader_log(const Api& api, GLuint shader) {
    GLint len = 0;
    api.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<std::size_t>(std::max(len, 1)), '\0');
    GLsizei written = 0;
    api.GetShaderInfoLog(shader, static_cast<GLsizei>(log.size()), &written, log.data());
    log.resize(static_cast<std::size_t>(std::max(written, 0)));
    return log;
}
inline std::string program_log(const Api& api, GLuint program) {
    GLint len = 0;
    api.GetProgramiv(program, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<std::size_t>(std::max(len, 1)), '\0');
    GLsizei written = 0;
    api.GetProgramInfoLog(program, static_cast<GLsizei>(log.size()), &written, log.data());
    log.resize(static_cast<std::size_t>(std::max(written, 0)));
    return log;
}
}  // namespace detail

/// An owned shader object.
class Shader {
public:
    Shader() = default;
    Shader(const Api& api, GLuint id) : api_(&api), id_(id) {}
    ~Shader() { reset(); }
    Shader(const Shader&) = delete;
    Shader& operator=(const Shader&) = delete;
    Shader(Shader&& o) noexcept : api_(o.api_), id_(std::exchange(o.id_, 0u)) {}
    Shader& operator=(Shader&& o) noexcept {
        if (this != &o) {
            reset();
            api_ = o.api_;
            id_ = std::exchange(o.id_, 0u);
        }
        return *this;
    }
    GLuint id() const noexcept { return id_; }
    void reset() noexcept {
        if (id_ != 0 && api_ != nullptr) api_->DeleteShader(id_);
        id_ = 0;
    }

private:
    const Api* api_ = nullptr;
    GLuint id_ = 0;
};

/// Compiles one shader from a single source string. `name` (the caller's, e.g. the kernel or
/// file name) appears in errors. Throws ShaderCompileError with the log and quoted lines.
inline Shader compile_shader(const Api& api, GLenum stage, std::string_view source, std::string_view name) {
    Shader shader(api, api.CreateShader(stage));
    if (shader.id() == 0)
        throw std::runtime_error("quadcast::gl: glCreateShader(" + stage_name(stage) + ") failed for \"" +
                                 std::string(name) + "\" (" + error_name(api.GetError()) + ")");
    const GLchar* text = source.data();
    const GLint len = static_cast<GLint>(source.size());
    api.ShaderSource(shader.id(), 1, &text, &len);
    api.CompileShader(shader.id());
    GLint ok = GL_FALSE;
    api.GetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        std::string log = detail::shader_log(api, shader.id());
        std::vector<LogDiagnostic> diags = parse_info_log(log);
        std::set<int> bad;
        for (const auto& d : diags)
            if (d.error && d.line > 0) bad.insert(d.line);
        std::string msg = "quadcast::gl: cannot compile " + stage_name(stage) + " \"" + std::string(name) + "\":\n" + log;
        if (!log.empty() && log.back() != '\n') msg += '\n';
        if (!bad.empty())
            msg += "in \"" + std::string(name) + "\":\n" + quote_source_lines(source, bad);
        else
            msg += "(the log names no source line)\n";
        throw ShaderCompileError(std::string(name), stage, std::move(log), std::move(diags), msg);
    }
    return shader;
}

/// An owned, linked program object.
class Program {
public:
    Program() = default;
    Program(const Api& api, GLuint id, std::string name) : api_(&api), id_(id), name_(std::move(name)) {}
    ~Program() { reset(); }
    Program(const Program&) = delete;
    Program& operator=(const Program&) = delete;
    Program(Program&& o) noexcept : api_(o.api_), id_(std::exchange(o.id_, 0u)), name_(std::move(o.name_)) {}
    Program& operator=(Program&& o) noexcept {
        if (this != &o) {
            reset();
            api_ = o.api_;
            id_ = std::exchange(o.id_, 0u);
            name_ = std::move(o.name_);
        }
        return *this;
    }
    GLuint id() const noexcept { return id_; }
    const std::string& name() const noexcept { return name_; }
    explicit operator bool() const noexcept { return id_ != 0; }

    /// glGetUniformLocation; -1 when the uniform does not exist or was optimised away.
    GLint uniform_location(const char* uniform) const { return api_->GetUniformLocation(id_, uniform); }
    /// Like uniform_location, but throws ProgramLinkError naming the program when absent.
    GLint require_uniform(const char* uniform) const {
        GLint loc = uniform_location(uniform);
        if (loc < 0)
            throw ProgramLinkError(name_, "",
                                   "quadcast::gl: program \"" + name_ + "\" has no active uniform \"" + uniform + "\"");
        return loc;
    }

    void reset() noexcept {
        if (id_ != 0 && api_ != nullptr) api_->DeleteProgram(id_);
        id_ = 0;
    }

private:
    const Api* api_ = nullptr;
    GLuint id_ = 0;
    std::string name_;
};

namespace detail {
inline Program link_ids(const Api& api, const std::vector<GLuint>& shaders, std::string_view name) {
    Program program(api, api.CreateProgram(), std::string(name));
    if (program.id() == 0)
        throw std::runtime_error("quadcast::gl: glCreateProgram failed for \"" + std::string(name) + "\"");
    for (GLuint s : shaders) api.AttachShader(program.id(), s);
    api.LinkProgram(program.id());
    for (GLuint s : shaders) api.DetachShader(program.id(), s);
    GLint ok = GL_FALSE;
    api.GetProgramiv(program.id(), GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        std::string log = program_log(api, program.id());
        throw ProgramLinkError(std::string(name), log,
                               "quadcast::gl: cannot link program \"" + std::string(name) + "\":\n" + log);
    }
    return program;
}
}  // namespace detail

/// Links compiled shaders into a program (the shaders may be deleted afterwards). Throws
/// ProgramLinkError with the log.
inline Program link_program(const Api& api, std::initializer_list<const Shader*> shaders, std::string_view name) {
    std::vector<GLuint> ids;
    for (const Shader* s : shaders) ids.push_back(s->id());
    return detail::link_ids(api, ids, name);
}

/// One stage's source for make_program.
struct StageSource {
    GLenum stage;
    std::string_view source;
};

/// Compiles every stage and links them. Shader names in errors are "<name> (<stage>)".
inline Program make_program(const Api& api, std::string_view name, std::initializer_list<StageSource> stages) {
    std::vector<Shader> shaders;
    shaders.reserve(stages.size());
    for (const StageSource& s : stages)
        shaders.push_back(compile_shader(api, s.stage, s.source, std::string(name) + " (" + stage_name(s.stage) + ")"));
    std::vector<GLuint> ids;
    for (const Shader& s : shaders) ids.push_back(s.id());
    return detail::link_ids(api, ids, name);
}

/// A compute program from one source string.
inline Program make_compute_program(const Api& api, std::string_view source, std::string_view name) {
    Shader cs = compile_shader(api, GL_COMPUTE_SHADER, source, name);
    return link_program(api, {&cs}, name);
}

}  // namespace quadcast::gl
