// quadcast/gl/compute.hpp -- run a compute shader over uint32 words: SSBO in, SSBO out, read back
#pragma once
// Host-only. The harness the GPU-vs-CPU tests use: the caller writes the whole compute shader
// (or starts it with ComputeRunner::prologue()); the runner uploads the input words, dispatches
// enough work groups for `invocations` (split over several dispatches when the count exceeds
// GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]) and reads the output words back.
//
// Shader contract:
//   layout(std430, binding = 0) readonly  buffer ... { uint ...[]; };   // input words
//   layout(std430, binding = 1) writeonly buffer ... { uint ...[]; };   // output words
//   uniform uint qc_count;   // number of invocations requested
//   uniform uint qc_offset;  // index of this dispatch's first invocation
//   invocation index i = qc_offset + gl_GlobalInvocationID.x; return when i >= qc_count.
// Only local_size_x may exceed 1. qc_offset is required only when one dispatch is not enough.

#include "quadcast/gl/program.hpp"

#include <chrono>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace quadcast::gl {

/// Wall-clock seconds of the phases of one ComputeRunner::run.
struct ComputeTiming {
    double upload_s = 0;    ///< buffer (re)allocation, input upload, clearing the output
    double dispatch_s = 0;  ///< all dispatches + glFinish
    double readback_s = 0;  ///< glGetBufferSubData of the output
    /// GL_TIME_ELAPSED around the dispatches, -1 when not available. Meaningless on llvmpipe
    /// (measured ~2e-7 s: it times submission, not execution); use dispatch_s there.
    double gpu_s = -1;
    int dispatches = 0;     ///< number of glDispatchCompute calls
};

struct ComputeResult {
    std::vector<std::uint32_t> output;
    ComputeTiming timing;
};

/// Owns one compute program and its two SSBOs. Construct and use with the context current;
/// destroy it before the context. Not thread-safe (the GL context is not).
class ComputeRunner {
public:
    /// `source` is a complete compute shader following the contract above; `name` appears in
    /// compile errors. Throws ShaderCompileError / ProgramLinkError / std::runtime_error.
    ComputeRunner(const Api& api, std::string_view source, std::string_view name)
        : api_(&api), program_(make_compute_program(api, source, name)) {
        GLint size[3] = {0, 0, 0};
        api.GetProgramiv(program_.id(), GL_COMPUTE_WORK_GROUP_SIZE, size);
        if (size[0] < 1 || size[1] != 1 || size[2] != 1)
            throw std::runtime_error("quadcast::gl::ComputeRunner: \"" + std::string(name) +
                                     "\" must declare layout(local_size_x = N) with local_size_y = local_size_z = 1");
        local_size_ = static_cast<GLuint>(size[0]);
        GLint max_groups = 0;
        api.GetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &max_groups);
        max_groups_ = static_cast<GLuint>(max_groups > 0 ? max_groups : 65535);
        GLint max_block = 0;
        api.GetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
        max_block_bytes_ = static_cast<std::uint64_t>(max_block > 0 ? max_block : 1 << 27);
        loc_count_ = program_.uniform_location("qc_count");
        loc_offset_ = program_.uniform_location("qc_offset");
        api.GenBuffers(2, buffers_);
        api.GenQueries(1, &query_);
        check_errors(api, "ComputeRunner(\"" + std::string(name) + "\")");
    }

    ~ComputeRunner() {
        if (api_ == nullptr) return;
        if (buffers_[0] != 0) api_->DeleteBuffers(2, buffers_);
        if (query_ != 0) api_->DeleteQueries(1, &query_);
    }
    ComputeRunner(const ComputeRunner&) = delete;
    ComputeRunner& operator=(const ComputeRunner&) = delete;

    /// Standard start of a harness kernel: `#version 430 core`, the local size, `qc_in[]`
    /// (binding 0), `qc_out[]` (binding 1), the two uniforms and
    /// `bool qc_index(out uint i)` (false past the end). Append helper functions and `main`.
    static std::string prologue(unsigned local_size_x = 64) {
        return "#version 430 core\n"
               "layout(local_size_x = " +
               std::to_string(local_size_x) +
               ") in;\n"
               "layout(std430, binding = 0) readonly buffer QcIn { uint qc_in[]; };\n"
               "layout(std430, binding = 1) writeonly buffer QcOut { uint qc_out[]; };\n"
               "uniform uint qc_count;\n"
               "uniform uint qc_offset;\n"
               "bool qc_index(out uint i) { i = qc_offset + gl_GlobalInvocationID.x; return i < qc_count; }\n";
    }

    /// Runs `invocations` invocations over `input`, returns `output_words` words of binding 1
    /// (zeroed before the run, so words no invocation writes read as 0).
    ComputeResult run(std::span<const std::uint32_t> input, std::uint64_t invocations, std::size_t output_words) {
        ComputeResult r;
        r.output.resize(output_words);
        r.timing = run_into(input, invocations, r.output);
        return r;
    }

    /// As run(), into caller storage (output.size() words).
    ComputeTiming run_into(std::span<const std::uint32_t> input, std::uint64_t invocations,
                           std::span<std::uint32_t> output) {
        using clock = std::chrono::steady_clock;
        const Api& gl = *api_;
        ComputeTiming t;
        if (invocations > 0xFFFFFFFFull)
            throw std::invalid_argument("quadcast::gl::ComputeRunner: more than 2^32-1 invocations (qc_count is a uint)");
        const std::uint64_t in_bytes = std::max<std::uint64_t>(4, input.size_bytes());
        const std::uint64_t out_bytes = std::max<std::uint64_t>(4, output.size_bytes());
        if (in_bytes > max_block_bytes_ || out_bytes > max_block_bytes_)
            throw std::invalid_argument("quadcast::gl::ComputeRunner \"" + program_.name() + "\": buffer of " +
                                        std::to_string(std::max(in_bytes, out_bytes)) +
                                        " bytes exceeds GL_MAX_SHADER_STORAGE_BLOCK_SIZE = " +
                                        std::to_string(max_block_bytes_) + "; split the run");
        const std::uint64_t groups = (invocations + local_size_ - 1) / local_size_;
        if (groups > max_groups_ && loc_offset_ < 0)
            throw std::runtime_error("quadcast::gl::ComputeRunner \"" + program_.name() + "\": " +
                                     std::to_string(invocations) + " invocations need " +
                                     std::to_string((groups + max_groups_ - 1) / max_groups_) +
                                     " dispatches, but the shader has no active `uniform uint qc_offset`");

        auto t0 = clock::now();
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, buffers_[0]);
        if (in_bytes > in_capacity_) {
            gl.BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(in_bytes), nullptr, GL_DYNAMIC_DRAW);
            in_capacity_ = in_bytes;
        }
        if (!input.empty())
            gl.BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(input.size_bytes()), input.data());
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, buffers_[1]);
        if (out_bytes > out_capacity_) {
            gl.BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(out_bytes), nullptr, GL_DYNAMIC_READ);
            out_capacity_ = out_bytes;
        }
        const GLuint zero = 0;
        gl.ClearBufferSubData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, 0, static_cast<GLsizeiptr>(out_bytes),
                              GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        auto t1 = clock::now();

        gl.UseProgram(program_.id());
        gl.BindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, buffers_[0], 0, static_cast<GLsizeiptr>(in_bytes));
        gl.BindBufferRange(GL_SHADER_STORAGE_BUFFER, 1, buffers_[1], 0, static_cast<GLsizeiptr>(out_bytes));
        if (loc_count_ >= 0) gl.Uniform1ui(loc_count_, static_cast<GLuint>(invocations));
        gl.BeginQuery(GL_TIME_ELAPSED, query_);
        for (std::uint64_t done = 0; done < groups;) {
            const std::uint64_t n = std::min<std::uint64_t>(groups - done, max_groups_);
            if (loc_offset_ >= 0) gl.Uniform1ui(loc_offset_, static_cast<GLuint>(done * local_size_));
            gl.DispatchCompute(static_cast<GLuint>(n), 1, 1);
            ++t.dispatches;
            done += n;
        }
        gl.EndQuery(GL_TIME_ELAPSED);
        gl.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        gl.Finish();
        auto t2 = clock::now();
        GLuint64 ns = 0;
        GLint available = 0;
        gl.GetQueryObjectiv(query_, GL_QUERY_RESULT_AVAILABLE, &available);
        if (available) {
            gl.GetQueryObjectui64v(query_, GL_QUERY_RESULT, &ns);
            t.gpu_s = static_cast<double>(ns) * 1e-9;
        }

        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
        gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, 0);
        gl.UseProgram(0);
        if (!output.empty()) {
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, buffers_[1]);
            gl.GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(output.size_bytes()),
                                output.data());
            gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        }
        auto t3 = clock::now();
        check_errors(gl, "ComputeRunner::run(\"" + program_.name() + "\")");

        auto sec = [](auto d) { return std::chrono::duration<double>(d).count(); };
        t.upload_s = sec(t1 - t0);
        t.dispatch_s = sec(t2 - t1);
        t.readback_s = sec(t3 - t2);
        return t;
    }

    const Program& program() const noexcept { return program_; }
    GLuint local_size_x() const noexcept { return local_size_; }
    /// GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]: work groups per dispatch.
    GLuint max_groups_per_dispatch() const noexcept { return max_groups_; }
    /// GL_MAX_SHADER_STORAGE_BLOCK_SIZE: the largest input or output in bytes.
    std::uint64_t max_buffer_bytes() const noexcept { return max_block_bytes_; }

private:
    const Api* api_;
    Program program_;
    GLuint local_size_ = 0;
    GLuint max_groups_ = 0;
    std::uint64_t max_block_bytes_ = 0;
    GLint loc_count_ = -1;
    GLint loc_offset_ = -1;
    GLuint buffers_[2] = {0, 0};
    GLuint query_ = 0;
    std::uint64_t in_capacity_ = 0;
    std::uint64_t out_capacity_ = 0;
};

}  // namespace quadcast::gl
