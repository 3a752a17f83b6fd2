// What toml++ is given of a scene or suite file. toml++ 3.3 (Debian 12's) tests characters
// outside ASCII for whitespace with a function that reaches __builtin_unreachable() for most
// of U+00A1..U+3147 (found by fuzz/scene and fuzz/suite), which is undefined behaviour
// wherever its lexer meets one: in a bad token, after a line-ending backslash in a string.
// So toml++ only ever sees ASCII: each byte outside it becomes '~', which is valid in
// comments and strings and nowhere else, at the same byte offset (lines and columns stay).
// Such characters mean nothing in these files but in comments; a string that had one is
// refused by its reader (see byteAt).
#pragma once
#include <cstddef>
#include <string>
#include <string_view>

namespace lava::common {

constexpr char kNonAscii = '~';

inline std::string asciiForToml(std::string_view text) {
  std::string out(text);
  for (char& c : out)
    if (static_cast<unsigned char>(c) >= 0x80) c = kNonAscii;
  return out;
}

// The byte at 1-based `line` and `column` (as toml++ counts them in asciiForToml's text), or
// '\0' past the end.
inline char byteAt(std::string_view text, size_t line, size_t column) {
  size_t at = 0;
  for (size_t l = 1; l < line && at < text.size(); ++at)
    if (text[at] == '\n') ++l;
  at += column - 1;
  return at < text.size() ? text[at] : '\0';
}

// Whether line `line` of the original text has a byte outside ASCII.
inline bool nonAsciiOnLine(std::string_view text, size_t line) {
  for (size_t at = 0, l = 1; at < text.size() && l <= line; ++at) {
    if (text[at] == '\n') ++l;
    else if (l == line && static_cast<unsigned char>(text[at]) >= 0x80) return true;
  }
  return false;
}

// Whether the original text has a byte outside ASCII between two such positions.
inline bool nonAsciiBetween(std::string_view text, size_t line, size_t column, size_t endLine,
                            size_t endColumn) {
  size_t at = 0;
  for (size_t l = 1; l < line && at < text.size(); ++at)
    if (text[at] == '\n') ++l;
  at += column - 1;
  for (size_t l = line, c = column; at < text.size() && (l < endLine || c < endColumn); ++at) {
    if (static_cast<unsigned char>(text[at]) >= 0x80) return true;
    if (text[at] == '\n') {
      ++l;
      c = 1;
    } else {
      ++c;
    }
  }
  return false;
}

}  // namespace lava::common
