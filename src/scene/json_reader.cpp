// src/scene/json_reader.cpp -- checked access to a JSON document with pointer + line/column errors
#include "quadcast/scene/json_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

namespace quadcast::scene {

namespace {

/// Line and column (code points, 1-based) of byte `index` in `text`.
TextPosition position_of(std::string_view text, std::size_t index) {
    index = std::min(index, text.size());
    TextPosition p{1, 1};
    for (std::size_t i = 0; i < index; ++i) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        if (c == '\n') {
            ++p.line;
            p.column = 1;
        } else if ((c & 0xC0) != 0x80) {  // not a UTF-8 continuation byte
            ++p.column;
        }
    }
    return p;
}

/// Byte offset of the first bracket that opens level max_json_depth + 1, if any. Brackets inside
/// strings do not count; the text need not be valid JSON (syntax errors are found later).
std::optional<std::size_t> too_deep(std::string_view text) {
    int depth = 0;
    bool in_string = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (in_string) {
            if (c == '\\') ++i;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > max_json_depth) return i;
        } else if (c == ']' || c == '}') {
            depth = std::max(depth - 1, 0);
        }
    }
    return std::nullopt;
}

/// The DOM builder of nlohmann::json, but remembering where a syntax error happened (the
/// library reports positions only through SAX; number overflow has none in the exception).
struct PositionedDomParser : nlohmann::detail::json_sax_dom_parser<Json> {
    using Base = nlohmann::detail::json_sax_dom_parser<Json>;
    explicit PositionedDomParser(Json& j) : Base(j, true) {}
    std::size_t chars_read = 0;
    std::string token;
    template <class Exception>
    bool parse_error(std::size_t position, const std::string& last_token, const Exception& ex) {
        chars_read = position;
        token = last_token;
        throw ex;
    }
};

/// Records the position of every value and key of a valid JSON text in a tree of pointer
/// segments (a node per value: its parent and its own escaped key or index), so the memory is
/// linear in the text -- a full pointer string per value would grow with depth x key length.
class PositionScanner {
public:
    PositionScanner(std::string_view text, PositionTree& tree) : s_(text), tree_(tree) {}

    /// Returns the pointer of the first duplicate key (and its byte offset), if any.
    std::optional<std::pair<std::string, std::size_t>> run() {
        if (s_.substr(0, 3) == "\xEF\xBB\xBF") i_ = 3;  // UTF-8 byte order mark, skipped like nlohmann does
        tree_.nodes.push_back({});
        value(0);
        return duplicate_;
    }

private:
    void ws() {
        while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r')) ++i_;
    }
    TextPosition here() {
        // Incremental position_of: the scanner only moves forward.
        for (; pos_index_ < i_; ++pos_index_) {
            const unsigned char c = static_cast<unsigned char>(s_[pos_index_]);
            if (c == '\n') {
                ++pos_.line;
                pos_.column = 1;
            } else if ((c & 0xC0) != 0x80) {
                ++pos_.column;
            }
        }
        return pos_;
    }
    std::string_view string_token() {
        const std::size_t b = i_++;
        while (i_ < s_.size() && s_[i_] != '"') i_ += s_[i_] == '\\' ? 2 : 1;
        ++i_;
        return s_.substr(b, i_ - b);
    }
    /// The child `segment` of node `parent` (created; false when it existed already).
    std::pair<std::uint32_t, bool> child(std::uint32_t parent, const std::string& segment) {
        const auto id = static_cast<std::uint32_t>(tree_.nodes.size());
        const auto [it, fresh] = tree_.children.emplace(PositionTree::child_key(parent, segment), id);
        if (fresh) tree_.nodes.push_back({});
        return {it->second, fresh};
    }
    /// The pointer of `node` (only built for a message).
    std::string pointer_of(std::uint32_t node, const std::string& last) const { return tree_.pointer(node) + "/" + last; }

    void value(std::uint32_t node) {
        ws();
        tree_.nodes[node].value = here();
        if (i_ >= s_.size()) return;
        const char c = s_[i_];
        if (c == '{') {
            ++i_;
            ws();
            if (i_ < s_.size() && s_[i_] == '}') {
                ++i_;
                return;
            }
            while (i_ < s_.size()) {
                ws();
                const std::size_t key_start = i_;
                const TextPosition kp = here();
                const std::string key = json_pointer_escape(Json::parse(string_token()).get<std::string>());
                const auto [id, fresh] = child(node, key);
                if (fresh) tree_.nodes[id].key = kp;
                else if (!duplicate_) duplicate_ = std::make_pair(pointer_of(node, key), key_start);
                ws();
                ++i_;  // ':'
                value(id);
                ws();
                if (i_ < s_.size() && s_[i_++] == '}') return;
            }
        } else if (c == '[') {
            ++i_;
            ws();
            if (i_ < s_.size() && s_[i_] == ']') {
                ++i_;
                return;
            }
            for (std::size_t k = 0; i_ < s_.size(); ++k) {
                value(child(node, std::to_string(k)).first);
                ws();
                if (i_ < s_.size() && s_[i_++] == ']') return;
            }
        } else if (c == '"') {
            string_token();
        } else {
            while (i_ < s_.size() && !std::strchr(",]} \t\r\n", s_[i_])) ++i_;
        }
    }

    std::string_view s_;
    std::size_t i_ = 0, pos_index_ = 0;
    TextPosition pos_{1, 1};
    PositionTree& tree_;
    std::optional<std::pair<std::string, std::size_t>> duplicate_;
};

/// The nlohmann message without its "[json.exception...] parse error at line L, column C: " prefix.
std::string clean_message(const std::string& what) {
    std::string m = what;
    if (m.rfind("[json.exception.", 0) == 0) {
        const auto close = m.find("] ");
        if (close != std::string::npos) m = m.substr(close + 2);
    }
    if (m.rfind("parse error", 0) == 0) {
        const auto colon = m.find(": ");
        if (colon != std::string::npos) m = m.substr(colon + 2);
    }
    return m;
}

std::string join(const std::vector<std::string_view>& v) {
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + std::string(v[i]);
    return s;
}

/// Levenshtein distance, for "did you mean" suggestions.
std::size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> d(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) d[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t prev = d[0];
        d[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t cur = d[j];
            d[j] = std::min({d[j] + 1, d[j - 1] + 1, prev + (a[i - 1] == b[j - 1] ? 0 : 1)});
            prev = cur;
        }
    }
    return d[b.size()];
}

}  // namespace

std::string json_pointer_escape(std::string_view key) {
    std::string r;
    for (char c : key) {
        if (c == '~') r += "~0";
        else if (c == '/') r += "~1";
        else r += c;
    }
    return r;
}

// JsonDocument ---------------------------------------------------------------------------------

JsonDocument::JsonDocument(std::string text, std::string file_name) : file_(std::move(file_name)), text_(std::move(text)) {
    // The position scanner recurses once per level: bound the depth before anything recurses.
    if (const auto deep = too_deep(text_)) {
        const TextPosition p = position_of(text_, *deep);
        throw ParseError({file_, p.line, p.column, ""},
                         "nested deeper than " + std::to_string(max_json_depth) + " arrays/objects (the limit of a scene file)");
    }
    PositionedDomParser dom(json_);
    try {
        Json::sax_parse(text_, &dom);
    } catch (const nlohmann::json::exception& e) {
        // Point at the last character read (syntax errors) or the start of the number (overflow).
        std::size_t index = dom.chars_read > 0 ? dom.chars_read - 1 : 0;
        std::string message = clean_message(e.what());
        if (e.id == 406) {
            index = dom.chars_read > dom.token.size() ? dom.chars_read - dom.token.size() : 0;
            // strtod overflow: the lexer read one character past the number.
            while (index > 0 && index < text_.size() && text_[index] != '-' && !std::isdigit(static_cast<unsigned char>(text_[index])))
                --index;
            message += " (not representable as a finite double)";
        }
        // JSON has no NaN/Infinity literals; say so when that is what was written.
        for (std::size_t k = index >= 1 ? index - 1 : 0; k <= index && k < text_.size(); ++k) {
            const std::string_view rest = std::string_view(text_).substr(k, 8);
            for (std::string_view lit : {"NaN", "nan", "Infinity", "inf", "Inf"})
                if (rest.substr(0, lit.size()) == lit) {
                    message += " (JSON has no NaN or Infinity; write a finite number)";
                    k = index + 1;
                    break;
                }
        }
        const TextPosition p = position_of(text_, index);
        throw ParseError({file_, p.line, p.column, ""}, message);
    }
    PositionScanner scanner(text_, tree_);
    if (const auto dup = scanner.run()) {
        const TextPosition p = position_of(text_, dup->second);
        throw ParseError({file_, p.line, p.column, dup->first}, "duplicate key");
    }
}

JsonNode JsonDocument::root() const { return JsonNode(*this, json_, ""); }

std::string PositionTree::child_key(std::uint32_t parent, std::string_view segment) {
    std::string k(sizeof parent, '\0');
    std::memcpy(k.data(), &parent, sizeof parent);
    k += segment;
    return k;
}

std::string PositionTree::pointer(std::uint32_t node) const {
    // Only for messages: a linear search for the parent of each level is fine.
    std::vector<std::string> segments;
    while (node != 0) {
        bool found = false;
        for (const auto& [k, id] : children)
            if (id == node) {
                std::uint32_t parent = 0;
                std::memcpy(&parent, k.data(), sizeof parent);
                segments.push_back(k.substr(sizeof parent));
                node = parent;
                found = true;
                break;
            }
        if (!found) break;
    }
    std::string p;
    for (auto it = segments.rbegin(); it != segments.rend(); ++it) p += "/" + *it;
    return p;
}

TextPosition JsonDocument::position(const std::string& pointer, bool key) const {
    // Walk the pointer's segments down the tree ("" is the root, "/a/0" = child "a", child "0").
    if (tree_.nodes.empty()) return {};
    std::uint32_t node = 0;
    std::size_t i = 0;
    while (i < pointer.size()) {
        const std::size_t b = i + 1, e = std::min(pointer.find('/', b), pointer.size());
        const auto it = tree_.children.find(PositionTree::child_key(node, std::string_view(pointer).substr(b, e - b)));
        if (it == tree_.children.end()) return {};
        node = it->second;
        i = e;
    }
    return key ? tree_.nodes[node].key : tree_.nodes[node].value;
}

Location JsonDocument::location(const std::string& pointer, bool key) const {
    const TextPosition p = position(pointer, key);
    return {file_, p.line, p.column, pointer.empty() ? std::string("/") : pointer};
}

// JsonNode -------------------------------------------------------------------------------------

void JsonNode::fail(const std::string& message, bool at_key) const {
    throw ParseError(doc_->location(pointer_, at_key), message);
}

std::string JsonNode::describe() const {
    const Json& v = *value_;
    switch (v.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::boolean: return v.get<bool>() ? "true" : "false";
    case Json::value_t::string: {
        std::string s = v.dump();
        if (s.size() > 40) s = s.substr(0, 37) + "...";
        return "string " + s;
    }
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float: return "number " + v.dump();
    case Json::value_t::array: return "an array of " + std::to_string(v.size());
    case Json::value_t::object: return "an object";
    default: return v.type_name();
    }
}

void JsonNode::expect_keys(const std::vector<std::string_view>& allowed) const {
    if (!value_->is_object()) fail("expected an object, got " + describe());
    for (const auto& [key, val] : value_->items()) {
        if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
        std::string msg = "unknown key " + quote_token(key);
        std::string_view best;
        std::size_t best_d = 3;  // suggest only close matches
        for (std::string_view a : allowed)
            if (const std::size_t d = edit_distance(key, a); d < best_d) best_d = d, best = a;
        if (!best.empty()) msg += " (did you mean '" + std::string(best) + "'?)";
        msg += "; allowed: " + join(allowed);
        JsonNode(*doc_, val, pointer_ + "/" + json_pointer_escape(key)).fail(msg, true);
    }
}

bool JsonNode::has(std::string_view key) const { return value_->is_object() && value_->contains(key); }

std::optional<JsonNode> JsonNode::get(std::string_view key) const {
    if (!value_->is_object()) fail("expected an object, got " + describe());
    const auto it = value_->find(key);
    if (it == value_->end()) return std::nullopt;
    return JsonNode(*doc_, *it, pointer_ + "/" + json_pointer_escape(key));
}

JsonNode JsonNode::at(std::string_view key) const {
    if (std::optional<JsonNode> n = get(key)) return *n;
    fail("missing required key '" + std::string(key) + "'");
}

std::vector<JsonNode> JsonNode::array(std::size_t n, std::string_view element_kind) const {
    if (!value_->is_array()) {
        if (n == npos) fail("expected an array, got " + describe());
        fail("expected an array of " + std::to_string(n) + " " + std::string(element_kind) + ", got " + describe());
    }
    if (n != npos && value_->size() != n)
        fail("expected an array of " + std::to_string(n) + " " + std::string(element_kind) + ", got " +
             std::to_string(value_->size()) + " elements");
    std::vector<JsonNode> r;
    r.reserve(value_->size());
    for (std::size_t i = 0; i < value_->size(); ++i) r.emplace_back(*doc_, (*value_)[i], pointer_ + "/" + std::to_string(i));
    return r;
}

double JsonNode::number(Range range) const {
    if (!value_->is_number()) fail("expected a number, got " + describe());
    const double v = value_->get<double>();
    if (!std::isfinite(v)) fail("expected a finite number, got " + describe());
    switch (range) {
    case Range::any: break;
    case Range::positive:
        if (!(v > 0.0)) fail("expected a number > 0, got " + value_->dump());
        break;
    case Range::nonnegative:
        if (!(v >= 0.0)) fail("expected a number >= 0, got " + value_->dump());
        break;
    case Range::unit:
        if (!(v >= 0.0 && v <= 1.0)) fail("expected a number in [0, 1], got " + value_->dump());
        break;
    }
    return v;
}

bool JsonNode::boolean() const {
    if (!value_->is_boolean()) fail("expected true or false, got " + describe());
    return value_->get<bool>();
}

std::string JsonNode::string() const {
    if (!value_->is_string()) fail("expected a string, got " + describe());
    return value_->get<std::string>();
}

std::string JsonNode::choice(std::initializer_list<std::string_view> choices) const {
    std::vector<std::string_view> list(choices);
    if (!value_->is_string()) fail("expected one of \"" + join(list) + "\", got " + describe());
    const std::string s = value_->get<std::string>();
    if (std::find(list.begin(), list.end(), s) == list.end()) fail(quote_token(s) + " is not one of: " + join(list));
    return s;
}

Vec3d JsonNode::vec3() const {
    const std::vector<JsonNode> a = array(3, "numbers");
    return {{a[0].number(), a[1].number(), a[2].number()}};
}

Vec3d JsonNode::direction() const {
    const Vec3d v = vec3();
    if (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0) fail("direction is the zero vector");
    return v;
}

Vec3d JsonNode::color() const {
    const std::vector<JsonNode> a = array(3, "numbers (r, g, b in [0, 1])");
    return {{a[0].number(Range::unit), a[1].number(Range::unit), a[2].number(Range::unit)}};
}

}  // namespace quadcast::scene
