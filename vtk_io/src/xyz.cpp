// The text point-cloud formats (.xyz, .pwn): no header, one point per line. The column count of
// the first point decides whether the file carries normals; every later line must agree, so that
// a damaged line is reported instead of being read as a point with a shifted normal.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <system_error>

#include "parsers.hpp"

namespace rgbmesh::detail {
namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Locale-independent, like the mesh parsers; rejects trailing garbage ("1.5x").
bool parse_coordinate(std::string_view token, double& value) {
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);
  const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
  return result.ec == std::errc() && result.ptr == token.data() + token.size();
}

std::string shown(std::string_view token) {
  std::string text;
  for (const char c : token.substr(0, 40)) text += (c >= 32 && c < 127) ? c : '?';
  return token.size() > 40 ? text + "..." : text;
}

}  // namespace

PolygonSoup parse_xyz(std::string_view text, const std::string& path, std::vector<Vec3>& normals) {
  if (text.find('\0') != std::string_view::npos)
    throw InputError(path + ": not a text file (it contains NUL bytes)");
  PolygonSoup soup;
  normals.clear();
  std::size_t columns = 0;  // of the first point line: 3, or 6 with normals
  std::size_t first_line = 0;
  std::vector<std::string_view> tokens;
  std::size_t line_number = 0;
  for (std::size_t pos = 0; pos < text.size();) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_number;
    line = line.substr(0, std::min(line.find('#'), line.size()));
    tokens.clear();
    for (std::size_t i = 0; i < line.size();) {
      while (i < line.size() && is_blank(line[i])) ++i;
      const std::size_t start = i;
      while (i < line.size() && !is_blank(line[i])) ++i;
      if (i > start) tokens.push_back(line.substr(start, i - start));
    }
    if (tokens.empty()) continue;
    const auto error = [&](const std::string& what) {
      return InputError(path + ":" + std::to_string(line_number) + ": " + what);
    };
    if (columns == 0) {
      if (tokens.size() != 3 && tokens.size() != 6)
        throw error("expected 3 numbers (x y z) or 6 (x y z nx ny nz), found " +
                    std::to_string(tokens.size()));
      columns = tokens.size();
      first_line = line_number;
    } else if (tokens.size() != columns) {
      throw error("expected " + std::to_string(columns) + " numbers like the first point (line " +
                  std::to_string(first_line) + "), found " + std::to_string(tokens.size()));
    }
    double values[6];
    for (std::size_t k = 0; k < columns; ++k) {
      if (!parse_coordinate(tokens[k], values[k])) throw error("'" + shown(tokens[k]) + "' is not a number");
      if (!std::isfinite(values[k])) throw error("'" + shown(tokens[k]) + "' is not a finite number");
    }
    soup.points.emplace_back(values[0], values[1], values[2]);
    if (columns == 6) normals.emplace_back(values[3], values[4], values[5]);
  }
  return soup;
}

}  // namespace rgbmesh::detail
