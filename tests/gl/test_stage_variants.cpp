// tests/gl/test_stage_variants.cpp -- every variant key's stages assemble and pass glslang
#include <doctest/doctest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <unistd.h>

#include "quadcast/codegen/emit.hpp"
#include "quadcast/codegen/generate.hpp"
#include "quadcast/generated/shaders.hpp"
#include "quadcast/gl/stages.hpp"
#include "quadcast/render/variant_key.hpp"

using namespace quadcast;
namespace fs = std::filesystem;

namespace {

/// Runs glslangValidator on `text` (written to `dir`/`name`); the log when it is rejected.
std::string glslang_errors(const fs::path& dir, const std::string& name, const std::string& text) {
    const fs::path file = dir / name;
    {
        std::ofstream out(file, std::ios::binary);
        out << text;
    }
    const fs::path log = dir / (name + ".log");
    const std::string cmd = "glslangValidator '" + file.string() + "' > '" + log.string() + "' 2>&1";
    if (std::system(cmd.c_str()) == 0) return {};
    std::ifstream in(log);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

struct TempDir {
    fs::path path = fs::temp_directory_path() / ("quadcast-stages-" + std::to_string(::getpid()));
    TempDir() { fs::create_directories(path); }
    ~TempDir() { fs::remove_all(path); }
};

const char* extension(gl::StageText::Kind k) {
    return k == gl::StageText::Kind::vertex ? "vert" : k == gl::StageText::Kind::fragment ? "frag" : "comp";
}

/// Validates each distinct stage of `stages` once (programs share vertex stages).
void validate(const TempDir& dir, const std::string& key, const std::vector<gl::StageText>& stages, std::set<std::string>& seen, int& count) {
    for (const gl::StageText& s : stages) {
        if (s.kind != gl::StageText::Kind::compute || s.name.find(".verify") == std::string::npos) CHECK(s.text.rfind("#version 450 core\n", 0) == 0);
        if (!seen.insert(s.text).second) continue;
        ++count;
        // glslang picks the stage from the extension.
        const std::string file = "s" + std::to_string(count) + "." + extension(s.kind);
        const std::string errors = glslang_errors(dir.path, file, s.text);
        INFO(key << ": " << s.name << "\n" << errors);
        CHECK(errors.empty());
    }
}

}  // namespace

TEST_CASE("glslang accepts the stages of every variant key the renderers can ask for") {
    if (std::system("glslangValidator --version > /dev/null 2>&1") != 0) {
        MESSAGE("glslangValidator not installed (Debian glslang-tools); skipped");
        return;
    }
    TempDir dir;
    std::set<std::string> seen;
    int count = 0;
    for (const render::QuadricKey& k : render::all_quadric_keys()) validate(dir, render::key_name(k), gl::program_stages(k), seen, count);
    for (const render::DeferredKey& k : render::all_deferred_keys()) validate(dir, render::key_name(k), gl::program_stages(k), seen, count);
    for (const render::OcclusionKey& k : render::all_occlusion_keys()) validate(dir, render::key_name(k), gl::program_stages(k), seen, count);
    for (const render::IsoKey& k : render::all_iso_keys()) validate(dir, render::key_name(k), gl::program_stages(k), seen, count);
    for (const render::SlimKey& k : render::all_slim_keys()) validate(dir, render::key_name(k), gl::program_stages(k), seen, count);
    for (render::VolumeScheme s : {render::VolumeScheme::qss, render::VolumeScheme::s31})
        validate(dir, "iso coefficients", {gl::coefficient_stage(s)}, seen, count);
    for (bool ortho : {false, true})
        for (bool cells : {false, true}) validate(dir, "iso occlusion bounds", {gl::occlusion_bound_stage(ortho, cells)}, seen, count);
    validate(dir, "iso pyramid base", {gl::pyramid_base_stage()}, seen, count);
    MESSAGE(count << " distinct stage shaders validated");
    CHECK(count > 100);
}

TEST_CASE("glslang accepts the verification harness of every generated kernel") {
    if (std::system("glslangValidator --version > /dev/null 2>&1") != 0) return;
    TempDir dir;
    std::set<std::string> seen;
    int count = 0;
    for (const codegen::KernelDef& k : codegen::registry()) {
        const codegen::EmittedKernel e = codegen::emit_kernel(k);
        const std::string_view embedded = generated::find(e.name);
        REQUIRE_MESSAGE(embedded == e.function, e.name << " differs from the templates: run `make regenerate`");
        validate(dir, e.name, {{gl::StageText::Kind::compute, e.name + ".verify.comp", codegen::verify_compute_shader(e, k, embedded)}}, seen, count);
    }
    CHECK(count == static_cast<int>(codegen::registry().size()));
}

TEST_CASE("keys name programs uniquely and canonical keys are fixed points") {
    std::set<std::string> names;
    for (const render::QuadricKey& k : render::all_quadric_keys()) {
        CHECK(render::canonical(k) == k);
        CHECK(names.insert(render::key_name(k)).second);
    }
    // Open slabs are never culled; the geometry buffer does not shade, so has no environment.
    CHECK(render::quadric_key(render::Variant::open_slab, true, false, false, false) == render::QuadricKey{render::FragmentShape::slab, false});
    CHECK(render::quadric_key(render::Variant::ellipsoid, true, true, true, true) == render::QuadricKey{render::FragmentShape::ellipsoid, true, true, true, false});
    CHECK_THROWS_WITH_AS(gl::program_stages(render::QuadricKey{render::FragmentShape::ellipsoid, true, true, false, false, render::FragmentStage::brute_force}),
                         "the brute-force fragment stage needs a perspective camera", std::invalid_argument);
}
