// What toml++ is given of a scene or suite file. toml++ 3.3 (Debian 12's) tests characters
// outside ASCII for whitespace with a function that reaches __builtin_unreachable() for most
// of U+00A1..U+3147 (found by fuzz/scene and fuzz/suite), which is undefined behaviour
// wherever its lexer meets one: in a bad token, after a line-ending backslash in a string.
// So toml++ only ever sees ASCII: each byte outside it becomes '~', which is valid in
// comments and strings and nowhere else, at the same byte offset (lines and columns stay).
// Such characters mean nothing in these files but in comments; a string that had one is
// refused by its reader (nonAsciiBetween).
#pragma once
#include <algorithm>
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

// The byte offset of 1-based `line` and `column` as toml++ counts them in asciiForToml's
// text (one column a byte), capped at the end.
inline size_t offsetOf(std::string_view text, size_t line, size_t column) {
  size_t at = 0;
  for (size_t l = 1; l < line && at < text.size(); ++at)
    if (text[at] == '\n') ++l;
  return std::min(at + column - 1, text.size());
}

inline bool nonAscii(char c) { return static_cast<unsigned char>(c) >= 0x80; }

// Whether toml++'s error at `line`:`column`, described by `description`, is about a byte
// of the original text outside ASCII: at that place, or named there as the '~' it became.
inline bool errorIsNonAscii(std::string_view text, size_t line, size_t column,
                            std::string_view description) {
  const size_t at = offsetOf(text, line, column);
  if (at < text.size() && nonAscii(text[at])) return true;
  if (description.find(kNonAscii) == std::string_view::npos) return false;
  const size_t start = offsetOf(text, line, 1);
  const size_t end = std::min(text.find('\n', start), text.size());
  for (size_t k = start; k < end; ++k)
    if (nonAscii(text[k])) return true;
  return false;
}

// Whether the original text has a byte outside ASCII between two such positions.
inline bool nonAsciiBetween(std::string_view text, size_t line, size_t column, size_t endLine,
                            size_t endColumn) {
  const size_t end = offsetOf(text, endLine, endColumn);
  for (size_t k = offsetOf(text, line, column); k < end; ++k)
    if (nonAscii(text[k])) return true;
  return false;
}

}  // namespace lava::common
