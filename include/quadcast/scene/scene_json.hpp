// quadcast/scene/scene_json.hpp -- the JSON scene format of `quadcast render` (see the README)
#pragma once

// load_scene reads a scene file; every problem is a ParseError naming the file, line:column and
// the JSON pointer (/objects/3/sphere/radius), or the PDB/OFF file:line:field it came from.
// Unknown keys are errors (typo protection); NaN cannot be written in JSON, and numbers that
// overflow a double are errors. Relative file paths ("pdb", "off") are resolved against the
// directory of the scene file.
//
// Object kinds are a table (object_kinds()): each entry of "objects" holds exactly one kind
// key, the kind's own extra keys, and the common keys "color", "material", "comment". Adding
// a kind is one loader function plus one line in that table, e.g. a volume:
//     void load_volume(ObjectContext& ctx) {
//         const auto path = ctx.file_path();                 // "volume": "data.raw"
//         const double iso = ctx.entry.at("iso").number();
//         const std::string scheme = ctx.entry.at("scheme").choice({"qss", "s31", "trilinear"});
//         ... push into ctx.scene ...
//     }
//     {"volume", {"iso", "scheme"}, load_volume},

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "quadcast/scene/json_reader.hpp"
#include "quadcast/scene/scene.hpp"

namespace quadcast::scene {

/// Largest scene file accepted (the README's "Limits"): loading holds the text and the scene
/// (the entries of "objects" are parsed one at a time), about 4 times the text for spheres.
inline constexpr std::uintmax_t max_scene_file_bytes = std::uintmax_t(64) << 20;

/// Reads and validates a scene file. Throws ParseErrors (every error found, in file order; as a
/// ParseError it is the first), or ParseError when the file cannot be read or parsed as JSON.
Scene load_scene(const std::filesystem::path& path);

/// Same from text: `file_name` is used in messages, `base_dir` resolves relative paths.
Scene parse_scene(std::string text, const std::string& file_name, const std::filesystem::path& base_dir);

/// What a kind's loader gets: the scene to append to, the object entry, and its material.
struct ObjectContext {
    Scene& scene;
    JsonNode entry;           ///< the whole entry, /objects/<i>
    JsonNode value;           ///< the value of the kind key, /objects/<i>/<kind>
    Material material;        ///< from "material" and "color" (defaults otherwise)
    bool color_given;         ///< "color" or "material"/"color" was written
    std::filesystem::path base_dir;

    /// `value` as a path to an existing regular file, resolved against base_dir.
    std::filesystem::path file_path() const;
};

using ObjectLoader = void (*)(ObjectContext&);

struct ObjectKind {
    std::string_view key;                   ///< e.g. "sphere"
    std::vector<std::string_view> options;  ///< extra keys allowed beside the kind key, e.g. "style"
    ObjectLoader load;
};

/// The registered object kinds: sphere, ellipsoid, cylinder, cone, quadric, quad, pdb, off, volume.
const std::vector<ObjectKind>& object_kinds();

}  // namespace quadcast::scene
