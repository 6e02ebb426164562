// quadcast/scene/diagnostics.hpp -- errors and warnings that name the file, line and field
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace quadcast::scene {

/// Where something was found: `file:line:column: field`. `line`/`column` are 1-based, 0 = unknown.
/// `field` is a PDB/OFF field name ("x (columns 31-38)", "face 3 vertex 2") or a JSON pointer
/// ("/objects/3/sphere/radius").
struct Location {
    std::string file;
    int line = 0;
    int column = 0;
    std::string field;
};

/// "file:line:column: field: " (parts that are unknown are left out).
std::string format_location(const Location& where);

/// A problem that makes the input unusable. `what()` is the full message
/// `file:line[:column]: field: message`; the parts are kept for programs and tests.
class ParseError : public std::runtime_error {
public:
    ParseError(Location where, const std::string& message);
    const Location& where() const noexcept { return where_; }
    const std::string& file() const noexcept { return where_.file; }
    int line() const noexcept { return where_.line; }
    int column() const noexcept { return where_.column; }
    const std::string& field() const noexcept { return where_.field; }
    /// The message without the location prefix.
    const std::string& message() const noexcept { return message_; }

private:
    Location where_;
    std::string message_;
};

/// Every error of one input, sorted by position (file order), the first `max_reported` of them
/// in `what()` (one per line, then "... and N more errors"). As a ParseError it is the first
/// error, so code that wants one location gets the first in the file.
class ParseErrors : public ParseError {
public:
    static constexpr std::size_t max_reported = 20;
    explicit ParseErrors(std::vector<ParseError> errors);
    const std::vector<ParseError>& errors() const noexcept { return errors_; }
    const char* what() const noexcept override { return text_.c_str(); }

private:
    std::vector<ParseError> errors_;
    std::string text_;
};

/// `text` quoted for a message, cut to `max_token_chars` characters plus "..." (a 1 MB token
/// gives a short message, not a 1 MB one).
inline constexpr std::size_t max_token_chars = 64;
std::string quote_token(std::string_view text);

/// The whitespace-separated tokens of one line of a text format, up to a '#' when `comments`
/// (the line-oriented readers: OFF, point clouds, SLIM models).
std::vector<std::string> line_tokens(std::string_view line, bool comments = true);

/// A decimal number token (a leading '+' allowed, the whole token read); nullopt when it is not
/// one. NaN and infinities parse: the caller rejects them with its own message.
std::optional<double> parse_decimal(std::string_view token);

/// A problem handled in a documented way (a record skipped, a default used). Readers collect
/// them; the command prints them to stderr with `to_string()`.
struct Warning {
    Location where;
    std::string message;
    /// "file:line[:column]: warning: field: message".
    std::string to_string() const {
        Location file_only = where;
        file_only.field.clear();
        return format_location(file_only) + "warning: " + (where.field.empty() ? "" : where.field + ": ") + message;
    }
};

using Warnings = std::vector<Warning>;

}  // namespace quadcast::scene
