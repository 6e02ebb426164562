// src/scene/json_reader.cpp -- checked access to a JSON document with pointer + line/column errors
#include "quadcast/scene/json_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

namespace quadcast::scene {

namespace {

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

/// True for the bytes JSON allows between tokens, and the separators (which have no SAX event).
bool between_tokens(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == ',' || c == ':'; }

/// Builds a JsonTree from SAX events: the values, and for each the byte offset given with it.
class TreeBuilder {
public:
    void reset(JsonTree& tree) {
        tree_ = &tree;
        tree.json = nullptr;
        tree.nodes.clear();
        stack_.clear();
        open_.clear();
        has_key_ = false;
    }
    bool done() const { return stack_.empty(); }
    std::size_t depth() const { return stack_.size(); }
    /// The innermost open container (nullptr at the top).
    const Json* top() const { return stack_.empty() ? nullptr : stack_.back(); }
    /// Sets the key of the next value of the open object; false when the object has it already.
    bool key(std::string&& k, std::size_t offset) {
        const auto& obj = *stack_.back()->get_ptr<const Json::object_t*>();
        if (obj.find(k) != obj.end()) return false;
        key_ = std::move(k);
        key_offset_ = offset;
        has_key_ = true;
        return true;
    }
    /// Adds a value (a container stays open until `close`).
    void value(Json&& v, std::size_t offset) {
        const bool container = v.is_object() || v.is_array();
        const auto id = static_cast<std::uint32_t>(tree_->nodes.size());
        tree_->nodes.push_back({offset, has_key_ ? key_offset_ : JsonTree::no_key, id + 1});
        Json* slot = nullptr;
        if (stack_.empty()) {
            tree_->json = std::move(v);
            slot = &tree_->json;
        } else if (stack_.back()->is_array()) {
            auto& arr = *stack_.back()->get_ptr<Json::array_t*>();
            arr.push_back(std::move(v));
            slot = &arr.back();
        } else {
            // (the key is known to be new: `key` checked it)
            auto& obj = *stack_.back()->get_ptr<Json::object_t*>();
            static_cast<std::vector<Json::object_t::value_type>&>(obj).emplace_back(std::move(key_), std::move(v));
            slot = &obj.back().second;
        }
        has_key_ = false;
        if (container) {
            stack_.push_back(slot);
            open_.push_back(id);
        }
    }
    void close() {
        tree_->nodes[open_.back()].end = static_cast<std::uint32_t>(tree_->nodes.size());
        stack_.pop_back();
        open_.pop_back();
    }

private:
    JsonTree* tree_ = nullptr;
    std::vector<Json*> stack_;
    std::vector<std::uint32_t> open_;
    std::string key_;
    std::size_t key_offset_ = 0;
    bool has_key_ = false;
};

/// nlohmann's SAX events -> the document's tree, or, for the elements of the streamed array, a
/// tree per element handed to the callback. Each event's value starts at the first byte after
/// the previous token that is no white space or separator (the lexer has checked the text up to
/// there), which gives its offset without a second parser. The first duplicate key stops all
/// building (only a syntax error can still come first); syntax errors remember where they were.
class SaxHandler {
public:
    using number_integer_t = Json::number_integer_t;
    using number_unsigned_t = Json::number_unsigned_t;
    using number_float_t = Json::number_float_t;
    using string_t = Json::string_t;
    using binary_t = Json::binary_t;

    SaxHandler(const JsonText& text, JsonTree& tree, std::string_view streamed_key, const JsonDocument::ElementFn& on_element)
        : text_(text), s_(text.text()), streamed_key_(streamed_key), on_element_(on_element) {
        main_.reset(tree);
        if (s_.substr(0, 3) == "\xEF\xBB\xBF") scan_ = 3;  // UTF-8 byte order mark, skipped like nlohmann does
    }

    std::size_t chars_read = 0;  ///< of the syntax error
    std::string token;           ///< the lexer's last token at the syntax error
    std::optional<std::pair<std::string, std::size_t>> duplicate;  ///< pointer and key offset

    bool null() { return scalar(Json(nullptr), Token::literal, 4); }
    bool boolean(bool b) { return scalar(Json(b), Token::literal, b ? 4 : 5); }
    bool number_integer(number_integer_t v) { return scalar(Json(v), Token::number); }
    bool number_unsigned(number_unsigned_t v) { return scalar(Json(v), Token::number); }
    bool number_float(number_float_t v, const string_t&) { return scalar(Json(v), Token::number); }
    bool string(string_t& v) { return scalar(Json(std::move(v)), Token::string); }
    bool binary(binary_t&) { return true; }  // (not produced by the JSON lexer)
    bool start_object(std::size_t) { return open(Json::object()); }
    bool start_array(std::size_t) { return open(Json::array()); }
    bool end_object() { return close(); }
    bool end_array() { return close(); }
    bool key(string_t& k) {
        const std::size_t at = start();
        scan_ = at + string_length();
        if (duplicate) return true;
        TreeBuilder& b = builder();
        if (in_stream_ && b.done()) return true;  // (cannot happen: the streamed array has no keys)
        std::string segment = json_pointer_escape(k);
        if (!in_stream_ && b.depth() == 1) top_key_ = k;
        if (!b.key(std::move(k), at)) {
            duplicate = std::make_pair(pointer_of(segment), at);
            return true;
        }
        segments_.back() = std::move(segment);
        return true;
    }
    template <class Exception>
    bool parse_error(std::size_t position, const std::string& last_token, const Exception& ex) {
        chars_read = position;
        token = last_token;
        throw ex;
    }

private:
    std::size_t start() {
        while (scan_ < s_.size() && between_tokens(s_[scan_])) ++scan_;
        return scan_;
    }
    std::size_t number_length() const {
        std::size_t i = scan_;
        while (i < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[i])) || std::strchr("+-.eE", s_[i]))) ++i;
        return i - scan_;
    }
    std::size_t string_length() const {
        std::size_t i = scan_ + 1;
        while (i < s_.size() && s_[i] != '"') i += s_[i] == '\\' ? 2 : 1;
        return i + 1 - scan_;
    }
    TreeBuilder& builder() { return in_stream_ ? element_ : main_; }

    /// The pointer of the current value of the innermost container, then `last`.
    std::string pointer_of(const std::string& last) const {
        std::string p;
        for (std::size_t i = 0; i + 1 < segments_.size(); ++i) p += "/" + segments_[i];
        return p + "/" + last;
    }
    /// Before a value: the segment of the innermost container's next value (arrays count).
    void next_segment() {
        if (segments_.empty()) return;
        if (array_index_.back() != npos) segments_.back() = std::to_string(array_index_.back()++);
    }

    enum class Token { literal, number, string };
    bool scalar(Json&& v, Token kind, std::size_t literal_length = 0) {
        const std::size_t at = start();
        scan_ = at + (kind == Token::number ? number_length() : kind == Token::string ? string_length() : literal_length);
        if (duplicate) return true;
        next_segment();
        TreeBuilder& b = builder();
        const bool element = in_stream_ && b.done();
        if (element) element_.reset(element_tree_);
        b.value(std::move(v), at);
        if (element) emit();
        return true;
    }
    bool open(Json&& v) {
        const std::size_t at = start();
        scan_ = at + 1;
        if (duplicate) return true;
        next_segment();
        const bool is_array = v.is_array();
        if (!in_stream_ && is_array && on_element_ && main_.depth() == 1 && main_.top()->is_object() && top_key_ == streamed_key_ &&
            !streamed_key_.empty()) {
            // The streamed array: empty in the document, its elements one by one.
            main_.value(Json::array(), at);
            main_.close();
            in_stream_ = true;
            stream_index_ = 0;
            segments_.emplace_back();
            array_index_.push_back(0);
            return true;
        }
        TreeBuilder& b = builder();
        if (in_stream_ && b.done()) element_.reset(element_tree_);
        b.value(std::move(v), at);
        segments_.emplace_back();
        array_index_.push_back(is_array ? 0 : npos);
        return true;
    }
    bool close() {
        const std::size_t at = start();
        scan_ = at + 1;
        if (duplicate) return true;
        TreeBuilder& b = builder();
        if (in_stream_ && b.done()) {  // the end of the streamed array
            in_stream_ = false;
            segments_.pop_back();
            array_index_.pop_back();
            return true;
        }
        b.close();
        segments_.pop_back();
        array_index_.pop_back();
        if (in_stream_ && b.done()) emit();
        return true;
    }
    void emit() {
        const std::size_t i = stream_index_++;
        if (on_element_)
            on_element_(JsonNode(text_, element_tree_, element_tree_.json, 0, "/" + json_pointer_escape(streamed_key_) + "/" + std::to_string(i)));
        element_tree_.json = nullptr;
    }

    static constexpr std::size_t npos = std::size_t(-1);
    const JsonText& text_;
    std::string_view s_;
    std::string_view streamed_key_;
    const JsonDocument::ElementFn& on_element_;
    std::size_t scan_ = 0;
    TreeBuilder main_, element_;
    JsonTree element_tree_;
    bool in_stream_ = false;
    std::size_t stream_index_ = 0;
    std::string top_key_;
    /// Per open container (in the document or in an element): the pointer segment of its current
    /// value, and for arrays the index of the next one (npos: an object).
    std::vector<std::string> segments_;
    std::vector<std::size_t> array_index_;
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

// JsonText -------------------------------------------------------------------------------------

JsonText::JsonText(std::string text, std::string file_name) : file_(std::move(file_name)), text_(std::move(text)) {
    checkpoints_.push_back({1, 1});
}

TextPosition JsonText::position(std::size_t offset) const {
    offset = std::min(offset, text_.size());
    const auto advance = [this](TextPosition& p, std::size_t from, std::size_t to) {
        for (std::size_t i = from; i < to; ++i) {
            const unsigned char c = static_cast<unsigned char>(text_[i]);
            if (c == '\n') {
                ++p.line;
                p.column = 1;
            } else if ((c & 0xC0) != 0x80) {  // not a UTF-8 continuation byte
                ++p.column;
            }
        }
    };
    // Checkpoints up to the offset's, then from the cursor when it is on the way, else from there.
    const std::size_t k = offset / checkpoint_bytes;
    while (checkpoints_.size() <= k) {
        TextPosition p = checkpoints_.back();
        const std::size_t from = (checkpoints_.size() - 1) * checkpoint_bytes;
        advance(p, from, from + checkpoint_bytes);
        checkpoints_.push_back(p);
    }
    if (!(cursor_offset_ <= offset && cursor_offset_ >= k * checkpoint_bytes)) {
        cursor_offset_ = k * checkpoint_bytes;
        cursor_ = checkpoints_[k];
    }
    advance(cursor_, cursor_offset_, offset);
    cursor_offset_ = offset;
    return cursor_;
}

Location JsonText::location(std::size_t offset, const std::string& pointer) const {
    const TextPosition p = position(offset);
    return {file_, p.line, p.column, pointer.empty() ? std::string("/") : pointer};
}

// JsonDocument ---------------------------------------------------------------------------------

JsonDocument::JsonDocument(std::string text, std::string file_name, std::string_view streamed_key, ElementFn on_element)
    : text_(std::move(text), std::move(file_name)) {
    const std::string& t = text_.text();
    // Bound the depth before anything is parsed (nlohmann's parser and the builders keep a stack per level).
    if (const auto deep = too_deep(t)) {
        const TextPosition p = text_.position(*deep);
        throw ParseError({file(), p.line, p.column, ""},
                         "nested deeper than " + std::to_string(max_json_depth) + " arrays/objects (the limit of a scene file)");
    }
    SaxHandler sax(text_, tree_, streamed_key, on_element);
    try {
        Json::sax_parse(t, &sax);
    } catch (const nlohmann::json::exception& e) {
        // Point at the last character read (syntax errors) or the start of the number (overflow).
        std::size_t index = sax.chars_read > 0 ? sax.chars_read - 1 : 0;
        std::string message = clean_message(e.what());
        if (e.id == 406) {
            index = sax.chars_read > sax.token.size() ? sax.chars_read - sax.token.size() : 0;
            // strtod overflow: the lexer read one character past the number.
            while (index > 0 && index < t.size() && t[index] != '-' && !std::isdigit(static_cast<unsigned char>(t[index])))
                --index;
            message += " (not representable as a finite double)";
        }
        // JSON has no NaN/Infinity literals; say so when that is what was written.
        for (std::size_t k = index >= 1 ? index - 1 : 0; k <= index && k < t.size(); ++k) {
            const std::string_view rest = std::string_view(t).substr(k, 8);
            for (std::string_view lit : {"NaN", "nan", "Infinity", "inf", "Inf"})
                if (rest.substr(0, lit.size()) == lit) {
                    message += " (JSON has no NaN or Infinity; write a finite number)";
                    k = index + 1;
                    break;
                }
        }
        const TextPosition p = text_.position(index);
        throw ParseError({file(), p.line, p.column, ""}, message);
    }
    if (sax.duplicate) {
        const TextPosition p = text_.position(sax.duplicate->second);
        throw ParseError({file(), p.line, p.column, sax.duplicate->first}, "duplicate key");
    }
}

JsonNode JsonDocument::root() const { return JsonNode(text_, tree_, tree_.json, 0, ""); }

// JsonNode -------------------------------------------------------------------------------------

std::size_t JsonNode::offset(bool key) const {
    if (node_ >= tree_->nodes.size()) return 0;
    const JsonTree::Node& n = tree_->nodes[node_];
    return key && n.key != JsonTree::no_key ? n.key : n.value;
}

std::uint32_t JsonNode::child_node(std::size_t k) const {
    std::uint32_t c = node_ + 1;
    for (std::size_t i = 0; i < k && c < tree_->nodes.size(); ++i) c = tree_->nodes[c].end;
    return c;
}

void JsonNode::fail(const std::string& message, bool at_key) const {
    throw ParseError(location(at_key), message);
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
    std::size_t index = 0;
    for (const auto& [key, val] : value_->items()) {
        const std::size_t k = index++;
        if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
        std::string msg = "unknown key " + quote_token(key);
        std::string_view best;
        std::size_t best_d = 3;  // suggest only close matches
        for (std::string_view a : allowed)
            if (const std::size_t d = edit_distance(key, a); d < best_d) best_d = d, best = a;
        if (!best.empty()) msg += " (did you mean '" + std::string(best) + "'?)";
        msg += "; allowed: " + join(allowed);
        child(val, k, json_pointer_escape(key)).fail(msg, true);
    }
}

bool JsonNode::has(std::string_view key) const { return value_->is_object() && value_->contains(key); }

std::optional<JsonNode> JsonNode::get(std::string_view key) const {
    if (!value_->is_object()) fail("expected an object, got " + describe());
    const auto& obj = *value_->get_ptr<const Json::object_t*>();
    std::size_t k = 0;
    for (auto it = obj.begin(); it != obj.end(); ++it, ++k)
        if (it->first == key) return child(it->second, k, json_pointer_escape(key));
    return std::nullopt;
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
    std::uint32_t c = node_ + 1;
    for (std::size_t i = 0; i < value_->size(); ++i) {
        r.emplace_back(*text_, *tree_, (*value_)[i], c, pointer_ + "/" + std::to_string(i));
        if (c < tree_->nodes.size()) c = tree_->nodes[c].end;
    }
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
