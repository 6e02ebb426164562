// quadcast/scene/json_reader.hpp -- checked access to a JSON document with pointer + line/column errors
#pragma once

// nlohmann::json keeps no source positions, so JsonDocument scans the (already validated) text
// once more and records the line and column of every value and every object key under its
// JSON pointer (RFC 6901). JsonNode is a value plus its pointer; its accessors check types,
// finiteness, ranges, array lengths and unknown keys, and throw ParseError naming
// file:line:column and the pointer, e.g.
//     scene.json:14:23: /objects/3/sphere/radius: expected a number > 0, got -1

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <nlohmann/json.hpp>

#include "quadcast/scene/diagnostics.hpp"
#include "quadcast/scene/scene.hpp"

namespace quadcast::scene {

using Json = nlohmann::ordered_json;

/// Deepest nesting of arrays and objects accepted in a JSON text (the README's "Limits"): the
/// position scanner recurses once per level, so deeper texts are an error at the first bracket
/// too many, before any parsing.
inline constexpr int max_json_depth = 256;

struct TextPosition {
    int line = 0, column = 0;  ///< 1-based; column counts characters (UTF-8 code points)
};

class JsonNode;

/// Positions of the values (and keys) of a JSON text: node 0 is the root; `children` maps
/// (parent id, escaped key or array index) to a node id.
struct PositionTree {
    struct Node {
        TextPosition value, key;
    };
    std::vector<Node> nodes;
    std::unordered_map<std::string, std::uint32_t> children;
    static std::string child_key(std::uint32_t parent, std::string_view segment);
    /// The JSON pointer of a node (slow; for messages).
    std::string pointer(std::uint32_t node) const;
};

/// A parsed JSON text with the position of every value and key.
class JsonDocument {
public:
    /// Parses `text`. Syntax errors (and duplicate keys) throw ParseError with the line and
    /// column; the field is empty for syntax errors and the pointer for duplicate keys.
    JsonDocument(std::string text, std::string file_name);

    JsonNode root() const;
    const std::string& file() const { return file_; }
    /// Position of the value at `pointer` (of its key when `key` is true); {0,0} if unknown.
    TextPosition position(const std::string& pointer, bool key = false) const;
    Location location(const std::string& pointer, bool key = false) const;

private:
    std::string file_;
    std::string text_;
    Json json_;
    PositionTree tree_;
    friend class JsonNode;
};

/// Escapes a key for a JSON pointer: '~' -> "~0", '/' -> "~1".
std::string json_pointer_escape(std::string_view key);

enum class Range { any, positive, nonnegative, unit };  ///< unit = [0, 1]

/// A value in a JsonDocument, with its pointer. Cheap to copy (two pointers and a string).
class JsonNode {
public:
    JsonNode(const JsonDocument& doc, const Json& value, std::string pointer)
        : doc_(&doc), value_(&value), pointer_(std::move(pointer)) {}

    const Json& json() const { return *value_; }
    const std::string& pointer() const { return pointer_; }
    const JsonDocument& document() const { return *doc_; }
    Location location() const { return doc_->location(pointer_); }

    /// Throws ParseError at this value (at its key when `at_key`).
    [[noreturn]] void fail(const std::string& message, bool at_key = false) const;
    Warning warning(const std::string& message) const { return {location(), message}; }

    // Objects -----------------------------------------------------------------------------
    /// Fails unless this is an object whose keys are all in `allowed` (typo protection: the
    /// error names the first unknown key, suggests a close allowed one, and lists them all).
    void expect_keys(const std::vector<std::string_view>& allowed) const;
    bool has(std::string_view key) const;
    /// The member `key`; fails when it is missing (`what` says what the object is).
    JsonNode at(std::string_view key) const;
    std::optional<JsonNode> get(std::string_view key) const;

    // Arrays ------------------------------------------------------------------------------
    /// Fails unless this is an array of exactly `n` elements (any length when n == npos);
    /// returns the elements.
    std::vector<JsonNode> array(std::size_t n = npos, std::string_view element_kind = "values") const;
    static constexpr std::size_t npos = std::size_t(-1);

    // Values ------------------------------------------------------------------------------
    /// A finite number within `range`.
    double number(Range range = Range::any) const;
    bool boolean() const;
    std::string string() const;
    /// One of `choices`.
    std::string choice(std::initializer_list<std::string_view> choices) const;
    /// [x, y, z] of finite numbers.
    Vec3d vec3() const;
    /// [x, y, z] of finite numbers, not all zero.
    Vec3d direction() const;
    /// [r, g, b] in [0, 1].
    Vec3d color() const;

    /// A short description of the value for messages: `string "abc"`, `number -1`, `array of 2`.
    std::string describe() const;

private:
    const JsonDocument* doc_;
    const Json* value_;
    std::string pointer_;
};

}  // namespace quadcast::scene
