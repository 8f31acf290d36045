#pragma once
// What the hand-written parsers share: tokens and numbers in text, binary scalars, and two
// cursors over a file's bytes that name the line of an error.
//
// Every parser checks each count, length and index it uses against the data actually present, so
// that a truncated or corrupt file is an InputError instead of a read past the end, and reserves
// memory only for what the bytes left could hold. Indices into the point list are passed through
// unchecked: prepare_triangle_mesh names the face with a bad one.

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "io_common.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/vec3.hpp"

namespace rgbmesh::detail {

inline bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

inline void split(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
}

inline std::string lowercase(std::string_view s) {
  std::string lower(s);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  return lower;
}

// from_chars is locale-independent (strtod would read "1,5" in some locales) and reads
// "nan"/"inf", which prepare_triangle_mesh then reports with the vertex index.
inline bool parse_number(std::string_view token, double& value) {
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);
  const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
  return result.ec == std::errc() && result.ptr == token.data() + token.size();
}

inline bool parse_integer(std::string_view token, std::int64_t& value) {
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);
  const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
  return result.ec == std::errc() && result.ptr == token.data() + token.size();
}

// Text that should be shown in a message but may be binary garbage.
inline std::string printable(std::string_view s) {
  std::string text;
  for (const char c : s.substr(0, 40)) text += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
  return s.size() > 40 ? text + "..." : text;
}

// ---------------------------------------------------------------------------------------------
// Binary scalars (PLY, legacy VTK)

enum class Scalar { int8, uint8, int16, uint16, int32, uint32, int64, uint64, float32, float64 };

inline std::size_t size_of(Scalar s) {
  switch (s) {
    case Scalar::int8:
    case Scalar::uint8:
      return 1;
    case Scalar::int16:
    case Scalar::uint16:
      return 2;
    case Scalar::int32:
    case Scalar::uint32:
    case Scalar::float32:
      return 4;
    default:
      return 8;
  }
}

inline bool is_integer(Scalar s) { return s != Scalar::float32 && s != Scalar::float64; }

template <class T>
inline T load(const char* p, bool swap) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (swap) std::reverse(bytes, bytes + sizeof(T));
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

inline double load_double(const char* p, Scalar s, bool swap) {
  switch (s) {
    case Scalar::int8:
      return load<std::int8_t>(p, swap);
    case Scalar::uint8:
      return load<std::uint8_t>(p, swap);
    case Scalar::int16:
      return load<std::int16_t>(p, swap);
    case Scalar::uint16:
      return load<std::uint16_t>(p, swap);
    case Scalar::int32:
      return load<std::int32_t>(p, swap);
    case Scalar::uint32:
      return load<std::uint32_t>(p, swap);
    case Scalar::int64:
      return static_cast<double>(load<std::int64_t>(p, swap));
    case Scalar::uint64:
      return static_cast<double>(load<std::uint64_t>(p, swap));
    case Scalar::float32:
      return load<float>(p, swap);
    default:
      return load<double>(p, swap);
  }
}

// Only for integer types; false for a uint64 beyond the int64 range.
inline bool load_integer(const char* p, Scalar s, bool swap, std::int64_t& value) {
  switch (s) {
    case Scalar::int8:
      value = load<std::int8_t>(p, swap);
      return true;
    case Scalar::uint8:
      value = load<std::uint8_t>(p, swap);
      return true;
    case Scalar::int16:
      value = load<std::int16_t>(p, swap);
      return true;
    case Scalar::uint16:
      value = load<std::uint16_t>(p, swap);
      return true;
    case Scalar::int32:
      value = load<std::int32_t>(p, swap);
      return true;
    case Scalar::uint32:
      value = load<std::uint32_t>(p, swap);
      return true;
    case Scalar::int64:
      value = load<std::int64_t>(p, swap);
      return true;
    case Scalar::uint64: {
      const std::uint64_t u = load<std::uint64_t>(p, swap);
      value = static_cast<std::int64_t>(u);
      return u <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
    }
    default:
      return false;
  }
}

// A position in text with embedded binary blocks (PLY, legacy VTK). Errors name the line of the
// last word or line read.
class Cursor {
 public:
  Cursor(std::string_view data, const std::string& path) : data_(data), path_(path) {}

  bool at_end() const { return pos_ >= data_.size(); }
  std::size_t remaining() const { return data_.size() - pos_; }

  // The next whitespace-separated word, across lines; empty at the end.
  std::string_view word() {
    while (pos_ < data_.size() && is_space(data_[pos_])) ++pos_;
    mark_ = pos_;
    while (pos_ < data_.size() && !is_space(data_[pos_])) ++pos_;
    return data_.substr(mark_, pos_ - mark_);
  }

  // The rest of the current line without its line break; moves to the next line.
  std::string_view line() {
    mark_ = pos_;
    const std::size_t end = std::min(data_.find('\n', pos_), data_.size());
    std::string_view text = data_.substr(pos_, end - pos_);
    pos_ = std::min(end + 1, data_.size());
    if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
    return text;
  }

  // n raw bytes, or nullptr (and nothing taken) if fewer remain.
  const char* take(std::size_t n) {
    if (remaining() < n) return nullptr;
    const char* p = data_.data() + pos_;
    pos_ += n;
    return p;
  }

  // Whether the bytes at the position are `s`. Signatures are checked this way before reading
  // a line, which in a huge file without line breaks would scan all of it.
  bool starts_with(std::string_view s) const { return data_.substr(pos_, s.size()) == s; }

  std::size_t position() const { return pos_; }
  void rewind(std::size_t pos) { pos_ = pos; }

  // The number of the line last read (from 1).
  std::size_t line_number() const {
    return 1 + static_cast<std::size_t>(std::count(data_.begin(), data_.begin() + static_cast<std::ptrdiff_t>(mark_), '\n'));
  }

  InputError error(const std::string& what) const {
    return InputError(path_ + ": line " + std::to_string(line_number()) + ": " + what);
  }

 private:
  std::string_view data_;
  const std::string& path_;
  std::size_t pos_ = 0, mark_ = 0;
};

// Lines numbered from 1, '#' comments removed, split into tokens.
class TokenLines {
 public:
  TokenLines(std::string_view text, const std::string& path) : text_(text), path_(path) {}

  // The next line (possibly without tokens); false at the end of the text.
  bool next() {
    if (pos_ > text_.size()) return false;
    const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
    const std::string_view line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    ++number_;
    split(line.substr(0, std::min(line.find('#'), line.size())), tokens_);
    return true;
  }

  // Skips lines without tokens; false at the end of the text.
  bool next_nonempty() {
    while (next())
      if (!tokens_.empty()) return true;
    return false;
  }

  // OBJ's line continuation: drops the trailing backslash of the current line and appends the
  // tokens of the next line; false at the end of the text. The tokens so far are moved, not
  // copied: a statement continued over n lines costs O(n), not O(n^2) (a 240 kB file of
  // continued lines took 80 s).
  bool continue_line() {
    std::vector<std::string_view> kept = std::move(tokens_);
    kept.back().remove_suffix(1);
    if (kept.back().empty()) kept.pop_back();
    const bool more = next();
    if (more) kept.insert(kept.end(), tokens_.begin(), tokens_.end());
    tokens_ = std::move(kept);
    return more;
  }

  const std::vector<std::string_view>& tokens() const { return tokens_; }
  std::int64_t number() const { return number_; }

  InputError error(const std::string& what) const {
    return InputError(path_ + ": line " + std::to_string(number_) + ": " + what);
  }

 private:
  std::string_view text_;
  const std::string& path_;
  std::size_t pos_ = 0;
  std::int64_t number_ = 0;
  std::vector<std::string_view> tokens_;
};

inline void check_text(std::string_view text, const std::string& path) {
  if (text.find('\0') != std::string_view::npos)
    throw InputError(path + ": not a text file (it contains NUL bytes)");
}

inline Vec3 parse_point(const TokenLines& lines, std::size_t first) {
  const auto& tokens = lines.tokens();
  if (tokens.size() < first + 3)
    throw lines.error("expected 3 vertex coordinates, found " + std::to_string(tokens.size() - first));
  double c[3];
  for (std::size_t k = 0; k < 3; ++k)
    if (!parse_number(tokens[first + k], c[k]))
      throw lines.error("'" + printable(tokens[first + k]) + "' is not a number");
  return {c[0], c[1], c[2]};
}

}  // namespace rgbmesh::detail
