// quadcast/scene/json_reader.hpp -- checked access to a JSON document with pointer + line/column errors
#pragma once

// nlohmann::json keeps no source positions, so JsonDocument parses through nlohmann's SAX
// interface and records the byte offset of every value and every object key beside the value
// (JsonTree: one small node per value, in document order); line and column are computed from
// the offset only when a message needs them. Large arrays need not be held: the elements of one
// top-level array (the scene's "objects") can be handed to a callback one by one as each is
// complete, and dropped. JsonNode is a value plus its pointer; its accessors check types,
// finiteness, ranges, array lengths and unknown keys, and throw ParseError naming
// file:line:column and the pointer, e.g.
//     scene.json:14:23: /objects/3/sphere/radius: expected a number > 0, got -1

#include <cstddef>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "quadcast/scene/diagnostics.hpp"
#include "quadcast/scene/scene.hpp"

namespace quadcast::scene {

using Json = nlohmann::ordered_json;

/// Deepest nesting of arrays and objects accepted in a JSON text (the README's "Limits"): checked
/// before parsing, so deeper texts are an error at the first bracket too many.
inline constexpr int max_json_depth = 256;

struct TextPosition {
    int line = 0, column = 0;  ///< 1-based; column counts characters (UTF-8 code points)
};

/// A text and the line and column of byte offsets in it. Queries in increasing order cost the
/// bytes between them; others start from a checkpoint every 4 KiB.
class JsonText {
public:
    JsonText(std::string text, std::string file_name);
    const std::string& text() const { return text_; }
    const std::string& file() const { return file_; }
    TextPosition position(std::size_t offset) const;
    /// file:line:column of `offset`, with `pointer` as the field ("/" for the root).
    Location location(std::size_t offset, const std::string& pointer) const;

private:
    static constexpr std::size_t checkpoint_bytes = 4096;
    std::string file_, text_;
    mutable std::vector<TextPosition> checkpoints_;  ///< of the offsets k * checkpoint_bytes
    mutable std::size_t cursor_offset_ = 0;
    mutable TextPosition cursor_{1, 1};
};

/// A parsed JSON value with the byte offset of every value (and key) in it: node 0 is the value
/// itself, then its descendants in document order; `end` is the node after a node's subtree, so
/// a container's children are node + 1, nodes[node + 1].end, ...
struct JsonTree {
    static constexpr std::size_t no_key = std::size_t(-1);
    struct Node {
        std::size_t value = 0, key = no_key;  ///< byte offsets of the value and of its key's quote
        std::uint32_t end = 0;
    };
    Json json;
    std::vector<Node> nodes;
};

class JsonNode;

/// A parsed JSON text with the position of every value and key.
class JsonDocument {
public:
    /// Called with each element of the streamed array (/`streamed_key`) once it is complete; the
    /// node is valid during the call only.
    using ElementFn = std::function<void(const JsonNode& element)>;

    /// Parses `text`. Syntax errors (and duplicate keys) throw ParseError with the line and
    /// column; the field is empty for syntax errors and the pointer for duplicate keys. They are
    /// found before anything is returned, but elements handed to `on_element` before them have
    /// been handed already: a caller that collects results from `on_element` discards them when
    /// the constructor throws. When the text is an object whose member `streamed_key` is an
    /// array, its elements go to `on_element` (in order, if it is set) and not into the document,
    /// where that member is an empty array.
    JsonDocument(std::string text, std::string file_name, std::string_view streamed_key = {}, ElementFn on_element = {});

    JsonNode root() const;
    const std::string& file() const { return text_.file(); }
    const JsonText& text() const { return text_; }

private:
    JsonText text_;
    JsonTree tree_;
};

/// Escapes a key for a JSON pointer: '~' -> "~0", '/' -> "~1".
std::string json_pointer_escape(std::string_view key);

enum class Range { any, positive, nonnegative, unit };  ///< unit = [0, 1]

/// A value in a parsed JSON text, with its pointer. Cheap to copy (three pointers, an index and a
/// string); valid while the tree it points into is.
class JsonNode {
public:
    JsonNode(const JsonText& text, const JsonTree& tree, const Json& value, std::uint32_t node, std::string pointer)
        : text_(&text), tree_(&tree), value_(&value), node_(node), pointer_(std::move(pointer)) {}

    const Json& json() const { return *value_; }
    const std::string& pointer() const { return pointer_; }
    const JsonText& text() const { return *text_; }
    /// Byte offset of the value (of its key when `key` is true and it has one) in the text.
    std::size_t offset(bool key = false) const;
    TextPosition position(bool key = false) const { return text_->position(offset(key)); }
    Location location(bool key = false) const { return text_->location(offset(key), pointer_); }

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
    /// The node of the k-th child of this container.
    std::uint32_t child_node(std::size_t k) const;
    JsonNode child(const Json& value, std::size_t k, std::string segment) const {
        return JsonNode(*text_, *tree_, value, child_node(k), pointer_ + "/" + segment);
    }

    const JsonText* text_;
    const JsonTree* tree_;
    const Json* value_;
    std::uint32_t node_;
    std::string pointer_;
};

}  // namespace quadcast::scene
