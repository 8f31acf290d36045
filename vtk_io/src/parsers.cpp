// Hand-written readers: each checks every count, length and index it uses against the data
// actually present, so that truncated or corrupt files become InputErrors instead of reads past
// the end. Indices into the point list are passed through unchecked: prepare_triangle_mesh names
// the face that has a bad one.

#include "parsers.hpp"

#include <vtkCellType.h>
#include <vtkCellTypes.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstring>
#include <limits>
#include <system_error>
#include <utility>

namespace rgbmesh::detail {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

void split(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
}

std::string lowercase(std::string_view s) {
  std::string lower(s);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  return lower;
}

// from_chars is locale-independent (strtod would read "1,5" in some locales) and reads
// "nan"/"inf", which prepare_triangle_mesh then reports with the vertex index.
bool parse_number(std::string_view token, double& value) {
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);
  const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
  return result.ec == std::errc() && result.ptr == token.data() + token.size();
}

bool parse_integer(std::string_view token, std::int64_t& value) {
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);
  const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
  return result.ec == std::errc() && result.ptr == token.data() + token.size();
}

// Text that should be shown in a message but may be binary garbage.
std::string printable(std::string_view s) {
  std::string text;
  for (const char c : s.substr(0, 40)) text += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
  return s.size() > 40 ? text + "..." : text;
}

// ---------------------------------------------------------------------------------------------
// Binary scalars (PLY, legacy VTK)

enum class Scalar { int8, uint8, int16, uint16, int32, uint32, int64, uint64, float32, float64 };

std::size_t size_of(Scalar s) {
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

bool is_integer(Scalar s) { return s != Scalar::float32 && s != Scalar::float64; }

bool host_is_big_endian() {
  const std::uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  return first == 0;
}

template <class T>
T load(const char* p, bool swap) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (swap) std::reverse(bytes, bytes + sizeof(T));
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

double load_double(const char* p, Scalar s, bool swap) {
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
bool load_integer(const char* p, Scalar s, bool swap, std::int64_t& value) {
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

  std::size_t position() const { return pos_; }
  void rewind(std::size_t pos) { pos_ = pos; }

  InputError error(const std::string& what) const {
    const auto line = 1 + std::count(data_.begin(), data_.begin() + static_cast<std::ptrdiff_t>(mark_), '\n');
    return InputError(path_ + ": line " + std::to_string(line) + ": " + what);
  }

 private:
  std::string_view data_;
  const std::string& path_;
  std::size_t pos_ = 0, mark_ = 0;
};

// ---------------------------------------------------------------------------------------------
// OFF and OBJ: line-oriented text with '#' comments

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
  // tokens of the next line; false at the end of the text.
  bool continue_line() {
    std::vector<std::string_view> kept = tokens_;
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

void check_text(std::string_view text, const std::string& path) {
  if (text.find('\0') != std::string_view::npos)
    throw InputError(path + ": not a text file (it contains NUL bytes)");
}

Vec3 parse_point(const TokenLines& lines, std::size_t first) {
  const auto& tokens = lines.tokens();
  if (tokens.size() < first + 3)
    throw lines.error("expected 3 vertex coordinates, found " + std::to_string(tokens.size() - first));
  double c[3];
  for (std::size_t k = 0; k < 3; ++k)
    if (!parse_number(tokens[first + k], c[k]))
      throw lines.error("'" + printable(tokens[first + k]) + "' is not a number");
  return {c[0], c[1], c[2]};
}

// "[ST][C][N]OFF": the 3D variants, whose extra per-vertex values are ignored.
bool is_off_header(std::string_view token) {
  for (const std::string_view prefix : {"ST", "C", "N"})
    if (token.substr(0, prefix.size()) == prefix) token.remove_prefix(prefix.size());
  return token == "OFF";
}

// ---------------------------------------------------------------------------------------------
// PLY

struct PlyProperty {
  std::string name;
  Scalar type = Scalar::float32;  // of the value, or of the list items
  bool is_list = false;
  Scalar count_type = Scalar::uint8;
};

struct PlyElement {
  std::string name;
  std::int64_t count = 0;
  std::vector<PlyProperty> properties;
};

bool ply_scalar(std::string_view name, Scalar& type) {
  static const std::pair<std::string_view, Scalar> names[] = {
      {"char", Scalar::int8},      {"int8", Scalar::int8},       {"uchar", Scalar::uint8},
      {"uint8", Scalar::uint8},    {"short", Scalar::int16},     {"int16", Scalar::int16},
      {"ushort", Scalar::uint16},  {"uint16", Scalar::uint16},   {"int", Scalar::int32},
      {"int32", Scalar::int32},    {"uint", Scalar::uint32},     {"uint32", Scalar::uint32},
      {"float", Scalar::float32},  {"float32", Scalar::float32}, {"double", Scalar::float64},
      {"float64", Scalar::float64}};
  for (const auto& [n, s] : names)
    if (n == name) {
      type = s;
      return true;
    }
  return false;
}

int property_index(const PlyElement& element, std::string_view name) {
  for (std::size_t i = 0; i < element.properties.size(); ++i)
    if (element.properties[i].name == name) return static_cast<int>(i);
  return -1;
}

struct PlyHeader {
  bool ascii = true, swap = false;
  std::vector<PlyElement> elements;
};

PlyHeader parse_ply_header(Cursor& c, const std::string& path) {
  if (c.line() != "ply") throw InputError(path + ": not a PLY file (it does not start with 'ply')");
  PlyHeader header;
  bool have_format = false;
  std::vector<std::string_view> tokens;
  for (;;) {
    if (c.at_end()) throw InputError(path + ": the PLY header has no 'end_header' line");
    split(c.line(), tokens);
    if (tokens.empty() || tokens[0] == "comment" || tokens[0] == "obj_info") continue;
    const std::string_view keyword = tokens[0];
    if (keyword == "end_header") break;
    if (keyword == "format") {
      const std::string_view format = tokens.size() > 1 ? tokens[1] : "";
      if (format == "binary_little_endian" || format == "binary_big_endian") {
        header.ascii = false;
        header.swap = (format == "binary_big_endian") != host_is_big_endian();
      } else if (format != "ascii") {
        throw c.error("unknown PLY format '" + printable(format) + "'");
      }
      have_format = true;
    } else if (keyword == "element") {
      PlyElement element;
      if (tokens.size() != 3 || !parse_integer(tokens[2], element.count) || element.count < 0)
        throw c.error("expected 'element <name> <count>'");
      element.name = tokens[1];
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) throw c.error("a property before any element");
      PlyProperty property;
      const bool list = tokens.size() > 1 && tokens[1] == "list";
      if (list ? tokens.size() != 5 || !ply_scalar(tokens[2], property.count_type) ||
                     !is_integer(property.count_type) || !ply_scalar(tokens[3], property.type)
               : tokens.size() != 3 || !ply_scalar(tokens[1], property.type))
        throw c.error("expected 'property <type> <name>' or 'property list <integer type> <type> <name>'");
      property.is_list = list;
      property.name = tokens.back();
      header.elements.back().properties.push_back(std::move(property));
    } else {
      throw c.error("unexpected '" + printable(keyword) + "' in the PLY header");
    }
  }
  if (!have_format) throw InputError(path + ": the PLY header has no 'format' line");
  return header;
}

// Which element and properties hold the geometry.
struct PlyLayout {
  int vertex = -1, face = -1;  // element indices
  int xyz[3] = {-1, -1, -1};   // property indices in the vertex element
  int indices = -1;            // property index of the face's vertex list
  int normal[3] = {-1, -1, -1};  // nx, ny, nz in the vertex element, when all three are scalars
};

PlyLayout ply_layout(const PlyHeader& header, const std::string& path) {
  PlyLayout layout;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    if (header.elements[e].name == "vertex" && layout.vertex < 0) layout.vertex = static_cast<int>(e);
    if (header.elements[e].name == "face" && layout.face < 0) layout.face = static_cast<int>(e);
  }
  if (layout.vertex < 0) throw InputError(path + ": the PLY file has no 'vertex' element");
  const PlyElement& vertex = header.elements[layout.vertex];
  for (int k = 0; k < 3; ++k) {
    const char* name = k == 0 ? "x" : k == 1 ? "y" : "z";
    layout.xyz[k] = property_index(vertex, name);
    if (layout.xyz[k] < 0 || vertex.properties[layout.xyz[k]].is_list)
      throw InputError(path + ": the PLY 'vertex' element has no scalar property '" + name + "'");
  }
  int normal[3];
  bool has_normals = true;
  for (int k = 0; k < 3; ++k) {
    normal[k] = property_index(vertex, k == 0 ? "nx" : k == 1 ? "ny" : "nz");
    has_normals = has_normals && normal[k] >= 0 && !vertex.properties[normal[k]].is_list;
  }
  if (has_normals) std::copy(normal, normal + 3, layout.normal);
  if (layout.face >= 0) {
    const PlyElement& face = header.elements[layout.face];
    layout.indices = property_index(face, "vertex_indices");
    if (layout.indices < 0) layout.indices = property_index(face, "vertex_index");
    if (layout.indices < 0 || !face.properties[layout.indices].is_list ||
        !is_integer(face.properties[layout.indices].type))
      throw InputError(path + ": the PLY 'face' element has no integer list 'vertex_indices'");
  }
  return layout;
}

InputError ply_truncated(const std::string& path, const PlyElement& element, std::int64_t item) {
  return InputError(path + ": the file ends inside element '" + element.name + "' (item " +
                    std::to_string(item) + " of " + std::to_string(element.count) + "): it is truncated");
}

void read_binary_element(Cursor& c, const PlyHeader& header, const PlyLayout& layout, int e,
                         const std::string& path, PolygonSoup& soup, std::vector<Vec3>* normals) {
  const PlyElement& element = header.elements[e];
  const bool is_vertex = e == layout.vertex, is_face = e == layout.face;
  std::size_t row = 0;  // bytes per item when there are no lists
  bool has_list = false;
  for (const PlyProperty& p : element.properties) {
    has_list = has_list || p.is_list;
    row += size_of(p.type);
  }
  if (!has_list) {
    // Fixed-size items: the whole element is checked at once, and skipped unless it holds the
    // points.
    if (row > 0 && static_cast<std::uint64_t>(element.count) > c.remaining() / row)
      throw ply_truncated(path, element, static_cast<std::int64_t>(c.remaining() / row));
    if (!is_vertex) {
      c.take(row * static_cast<std::size_t>(element.count));
      return;
    }
  }
  if (is_vertex) soup.points.reserve(static_cast<std::size_t>(element.count));
  for (std::int64_t item = 0; item < element.count; ++item) {
    double xyz[3] = {0, 0, 0}, normal[3] = {0, 0, 0};
    std::vector<std::int64_t> face;
    for (std::size_t k = 0; k < element.properties.size(); ++k) {
      const PlyProperty& p = element.properties[k];
      if (!p.is_list) {
        const char* value = c.take(size_of(p.type));
        if (value == nullptr) throw ply_truncated(path, element, item);
        if (is_vertex)
          for (int axis = 0; axis < 3; ++axis) {
            if (layout.xyz[axis] == static_cast<int>(k)) xyz[axis] = load_double(value, p.type, header.swap);
            if (layout.normal[axis] == static_cast<int>(k))
              normal[axis] = load_double(value, p.type, header.swap);
          }
        continue;
      }
      const char* count_bytes = c.take(size_of(p.count_type));
      if (count_bytes == nullptr) throw ply_truncated(path, element, item);
      std::int64_t n = 0;
      if (!load_integer(count_bytes, p.count_type, header.swap, n) || n < 0)
        throw InputError(path + ": element '" + element.name + "' item " + std::to_string(item) +
                         " has a negative list length");
      if (static_cast<std::uint64_t>(n) > c.remaining() / size_of(p.type))
        throw ply_truncated(path, element, item);
      const char* items = c.take(static_cast<std::size_t>(n) * size_of(p.type));
      if (is_face && static_cast<int>(k) == layout.indices) {
        face.resize(static_cast<std::size_t>(n));
        for (std::int64_t i = 0; i < n; ++i)
          if (!load_integer(items + i * size_of(p.type), p.type, header.swap, face[i]))
            throw InputError(path + ": face " + std::to_string(item) +
                             " has a vertex index beyond the 64-bit range");
      }
    }
    if (is_vertex) soup.points.emplace_back(xyz[0], xyz[1], xyz[2]);
    if (is_vertex && normals != nullptr && layout.normal[0] >= 0)
      normals->emplace_back(normal[0], normal[1], normal[2]);
    if (is_face) soup.faces.push_back(std::move(face));
  }
}

// ASCII PLY has one item per line.
void read_ascii_element(Cursor& c, const PlyHeader& header, const PlyLayout& layout, int e,
                        const std::string& path, PolygonSoup& soup, std::vector<Vec3>* normals) {
  const PlyElement& element = header.elements[e];
  if (element.properties.empty()) return;
  const bool is_vertex = e == layout.vertex, is_face = e == layout.face;
  std::vector<std::string_view> tokens;
  for (std::int64_t item = 0; item < element.count; ++item) {
    do {
      if (c.at_end()) throw ply_truncated(path, element, item);
      split(c.line(), tokens);
    } while (tokens.empty());
    std::size_t next = 0;
    const auto token = [&]() {
      if (next >= tokens.size()) throw c.error("too few values for element '" + element.name + "'");
      return tokens[next++];
    };
    double xyz[3] = {0, 0, 0}, normal[3] = {0, 0, 0};
    std::vector<std::int64_t> face;
    for (std::size_t k = 0; k < element.properties.size(); ++k) {
      const PlyProperty& p = element.properties[k];
      if (!p.is_list) {
        const std::string_view value = token();
        if (is_vertex)
          for (int axis = 0; axis < 3; ++axis)
            if ((layout.xyz[axis] == static_cast<int>(k) && !parse_number(value, xyz[axis])) ||
                (layout.normal[axis] == static_cast<int>(k) && !parse_number(value, normal[axis])))
              throw c.error("'" + printable(value) + "' is not a number");
        continue;
      }
      const std::string_view count = token();
      std::int64_t n = 0;
      if (!parse_integer(count, n) || n < 0) throw c.error("'" + printable(count) + "' is not a list length");
      if (static_cast<std::uint64_t>(n) > tokens.size() - next)
        throw c.error("expected " + std::to_string(n) + " list values, found " +
                      std::to_string(tokens.size() - next));
      const bool keep = is_face && static_cast<int>(k) == layout.indices;
      for (std::int64_t i = 0; i < n; ++i) {
        const std::string_view value = token();
        std::int64_t index = 0;
        if (keep && !parse_integer(value, index))
          throw c.error("'" + printable(value) + "' is not a vertex index");
        if (keep) face.push_back(index);
      }
    }
    if (is_vertex) soup.points.emplace_back(xyz[0], xyz[1], xyz[2]);
    if (is_vertex && normals != nullptr && layout.normal[0] >= 0)
      normals->emplace_back(normal[0], normal[1], normal[2]);
    if (is_face) soup.faces.push_back(std::move(face));
  }
}

// ---------------------------------------------------------------------------------------------
// Legacy VTK

bool legacy_scalar(std::string_view name, Scalar& type) {
  static const std::pair<std::string_view, Scalar> names[] = {
      {"char", Scalar::int8},
      {"signed_char", Scalar::int8},
      {"unsigned_char", Scalar::uint8},
      {"short", Scalar::int16},
      {"unsigned_short", Scalar::uint16},
      {"int", Scalar::int32},
      {"unsigned_int", Scalar::uint32},
      {"long", Scalar::int64},
      {"unsigned_long", Scalar::uint64},
      {"vtkidtype", Scalar::int32},  // legacy files store ids as 32-bit
      {"vtktypeint8", Scalar::int8},
      {"vtktypeuint8", Scalar::uint8},
      {"vtktypeint16", Scalar::int16},
      {"vtktypeuint16", Scalar::uint16},
      {"vtktypeint32", Scalar::int32},
      {"vtktypeuint32", Scalar::uint32},
      {"vtktypeint64", Scalar::int64},
      {"vtktypeuint64", Scalar::uint64},
      {"float", Scalar::float32},
      {"double", Scalar::float64}};
  const std::string lower = lowercase(name);
  for (const auto& [n, s] : names)
    if (n == lower) {
      type = s;
      return true;
    }
  return false;
}

class LegacyReader {
 public:
  LegacyReader(std::string_view data, const std::string& path, const ReadOptions& options)
      : c_(data, path), path_(path), options_(options) {}

  PolygonSoup read() {
    const std::string_view first = c_.line();
    constexpr std::string_view signature = "# vtk DataFile Version ";
    if (first.substr(0, signature.size()) != signature)
      throw InputError(path_ +
                       ": not a legacy VTK file (the first line is not '# vtk DataFile Version x.y')");
    std::int64_t major = 0;
    const std::string_view version = first.substr(signature.size());
    std::from_chars(version.data(), version.data() + version.size(), major);
    c_.line();  // title
    const std::string mode = lowercase(c_.line());
    if (mode.rfind("binary", 0) == 0)
      binary_ = true;
    else if (mode.rfind("ascii", 0) != 0)
      throw c_.error("expected ASCII or BINARY");
    if (lowercase(c_.word()) != "dataset") throw c_.error("expected 'DATASET'");
    const std::string_view dataset = c_.word();
    const std::string kind = lowercase(dataset);
    if (kind != "polydata" && kind != "unstructured_grid")
      throw InputError(path_ + ": holds a " + printable(dataset) +
                       " data set, not a polygonal mesh or unstructured grid");

    PolygonSoup soup;
    CellList verts, lines, polys, strips, cells;
    std::vector<int> types;
    for (std::string keyword = lowercase(c_.word()); !keyword.empty(); keyword = lowercase(c_.word())) {
      if (keyword == "points") {
        const std::int64_t n = count();
        if (static_cast<std::uint64_t>(n) > c_.remaining()) throw truncated();
        const std::vector<double> xyz = doubles(3 * n, scalar_type());
        for (std::int64_t i = 0; i < n; ++i)
          soup.points.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
      } else if (keyword == "vertices" && kind == "polydata") {
        verts = cell_list(major);
      } else if (keyword == "lines" && kind == "polydata") {
        lines = cell_list(major);
      } else if (keyword == "polygons" && kind == "polydata") {
        polys = cell_list(major);
      } else if (keyword == "triangle_strips" && kind == "polydata") {
        strips = cell_list(major);
      } else if (keyword == "cells" && kind == "unstructured_grid") {
        cells = cell_list(major);
      } else if (keyword == "cell_types" && kind == "unstructured_grid") {
        const std::vector<std::int64_t> values = integers(count(), Scalar::int32);
        types.assign(values.begin(), values.end());
      } else if (keyword == "field") {
        skip_field();
      } else if (keyword == "metadata") {
        skip_metadata();
      } else if (keyword == "point_data" || keyword == "cell_data") {
        break;  // attributes: not needed
      } else {
        throw c_.error("unexpected '" + printable(keyword) + "' in a " + kind + " data set");
      }
    }
    if (kind == "polydata") {
      append_poly_data_cells(verts, lines, polys, strips, path_, soup, options_);
    } else {
      if (types.size() != cells.size())
        throw InputError(path_ + ": " + std::to_string(cells.size()) + " cells but " +
                         std::to_string(types.size()) + " cell types");
      append_grid_cells(cells, types, path_, soup, options_);
    }
    return soup;
  }

 private:
  std::int64_t count() {
    const std::string_view word = c_.word();
    std::int64_t n = 0;
    if (!parse_integer(word, n) || n < 0) throw c_.error("'" + printable(word) + "' is not a count");
    return n;
  }

  Scalar scalar_type() {
    const std::string_view word = c_.word();
    Scalar type;
    if (!legacy_scalar(word, type)) throw c_.error("unsupported data type '" + printable(word) + "'");
    return type;
  }

  // The raw bytes of n binary values, which start on the line after their header.
  const char* binary_block(std::int64_t n, Scalar type) {
    c_.line();
    if (static_cast<std::uint64_t>(n) > c_.remaining() / size_of(type)) throw truncated();
    return c_.take(static_cast<std::size_t>(n) * size_of(type));
  }

  InputError truncated() const { return c_.error("the data ends early: the file is truncated"); }

  std::vector<double> doubles(std::int64_t n, Scalar type) {
    std::vector<double> values;
    values.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(n, c_.remaining())));
    if (binary_) {
      const char* p = binary_block(n, type);
      for (std::int64_t i = 0; i < n; ++i) values.push_back(load_double(p + i * size_of(type), type, swap_));
      return values;
    }
    for (std::int64_t i = 0; i < n; ++i) {
      const std::string_view word = c_.word();
      if (word.empty()) throw truncated();
      double value = 0;
      if (!parse_number(word, value)) throw c_.error("'" + printable(word) + "' is not a number");
      values.push_back(value);
    }
    return values;
  }

  std::vector<std::int64_t> integers(std::int64_t n, Scalar type) {
    if (!is_integer(type)) throw c_.error("cell data must have an integer type");
    std::vector<std::int64_t> values;
    values.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(n, c_.remaining())));
    if (binary_) {
      const char* p = binary_block(n, type);
      for (std::int64_t i = 0; i < n; ++i) {
        std::int64_t value = 0;
        if (!load_integer(p + i * size_of(type), type, swap_, value))
          throw c_.error("an id beyond the 64-bit range");
        values.push_back(value);
      }
      return values;
    }
    for (std::int64_t i = 0; i < n; ++i) {
      const std::string_view word = c_.word();
      if (word.empty()) throw truncated();
      std::int64_t value = 0;
      if (!parse_integer(word, value)) throw c_.error("'" + printable(word) + "' is not an integer");
      values.push_back(value);
    }
    return values;
  }

  // "<KEYWORD> a b" followed by, up to version 4, b integers "n id_1 ... id_n" per cell (a cells);
  // from version 5 on, "OFFSETS <type>" with a values and "CONNECTIVITY <type>" with b values.
  CellList cell_list(std::int64_t major) {
    const std::int64_t a = count(), b = count();
    CellList cells;
    if (major >= 5) {
      if (lowercase(c_.word()) != "offsets") throw c_.error("expected 'OFFSETS'");
      const std::vector<std::int64_t> offsets = integers(a, scalar_type());
      if (lowercase(c_.word()) != "connectivity") throw c_.error("expected 'CONNECTIVITY'");
      const std::vector<std::int64_t> ids = integers(b, scalar_type());
      if (offsets.empty()) return cells;
      if (offsets.front() != 0 || offsets.back() != b)
        throw c_.error("the cell offsets do not match the connectivity");
      for (std::size_t i = 0; i + 1 < offsets.size(); ++i) {
        if (offsets[i + 1] < offsets[i] || offsets[i + 1] > b)
          throw c_.error("the cell offsets are out of order at cell " + std::to_string(i));
        cells.emplace_back(ids.begin() + offsets[i], ids.begin() + offsets[i + 1]);
      }
      return cells;
    }
    const std::vector<std::int64_t> values = integers(b, Scalar::int32);
    std::size_t pos = 0;
    for (std::int64_t cell = 0; cell < a; ++cell) {
      const std::int64_t n = pos < values.size() ? values[pos++] : -1;
      if (n < 0 || static_cast<std::uint64_t>(n) > values.size() - pos)
        throw c_.error("cell " + std::to_string(cell) + " does not fit in the " + std::to_string(b) +
                       " values the section announces");
      cells.emplace_back(values.begin() + static_cast<std::ptrdiff_t>(pos),
                         values.begin() + static_cast<std::ptrdiff_t>(pos + n));
      pos += static_cast<std::size_t>(n);
    }
    if (pos != values.size()) throw c_.error("the cells use fewer values than the section announces");
    return cells;
  }

  // "FIELD <name> <n>", then n arrays "<name> <components> <tuples> <type>" with their values.
  void skip_field() {
    c_.word();
    const std::int64_t arrays = count();
    for (std::int64_t i = 0; i < arrays; ++i) {
      const std::string_view name = c_.word();
      if (name == "NULL_ARRAY") continue;
      const std::int64_t components = count(), tuples = count();
      const Scalar type = scalar_type();
      if (components > 0 && tuples > std::numeric_limits<std::int64_t>::max() / components) throw truncated();
      doubles(components * tuples, type);
      const std::size_t before = c_.position();
      if (lowercase(c_.word()) == "metadata")
        skip_metadata();
      else
        c_.rewind(before);
    }
  }

  // METADATA blocks end with an empty line.
  void skip_metadata() {
    c_.line();
    while (!c_.at_end() && !c_.line().empty()) {
    }
  }

  Cursor c_;
  const std::string& path_;
  const ReadOptions& options_;
  bool binary_ = false;
  const bool swap_ = !host_is_big_endian();  // legacy binary data is big-endian
};

// ---------------------------------------------------------------------------------------------
// Cells

std::string cell_type_name(int type) {
  switch (type) {
    case VTK_EMPTY_CELL:
      return "an empty cell";
    case VTK_VERTEX:
      return "a vertex";
    case VTK_POLY_VERTEX:
      return "a poly-vertex";
    case VTK_LINE:
      return "a line";
    case VTK_POLY_LINE:
      return "a polyline";
    case VTK_TETRA:
      return "a tetrahedron";
    case VTK_VOXEL:
      return "a voxel";
    case VTK_HEXAHEDRON:
      return "a hexahedron";
    case VTK_WEDGE:
      return "a wedge";
    case VTK_PYRAMID:
      return "a pyramid";
    case VTK_POLYHEDRON:
      return "a polyhedron";
    default: {
      const char* name = vtkCellTypes::GetClassNameFromTypeId(type);
      return "a cell of VTK type " + std::to_string(type) +
             (name != nullptr && std::strcmp(name, "UnknownClass") != 0 ? std::string(" (") + name + ")"
                                                                        : "");
    }
  }
}

InputError not_a_surface_cell(const std::string& path, std::size_t cell, int type) {
  return InputError(path + ": cell " + std::to_string(cell) + " is " + cell_type_name(type) +
                    ", not a surface polygon");
}

// Triangle strip -> triangles, every second one reversed so that all share the strip's
// orientation (VTK's convention). Triangles with a repeated id are the zero-area joints that
// stitch several strips into one and are skipped.
void append_strip(const std::vector<std::int64_t>& strip, PolygonSoup& soup) {
  for (std::size_t i = 0; i + 2 < strip.size(); ++i) {
    const std::int64_t a = strip[i], b = strip[i + 1], c = strip[i + 2];
    if (a == b || b == c || a == c) continue;
    if (i % 2 == 0)
      soup.faces.push_back({a, b, c});
    else
      soup.faces.push_back({b, a, c});
  }
}

}  // namespace

PolygonSoup parse_off(std::string_view text, const std::string& path) {
  check_text(text, path);
  TokenLines lines(text, path);
  PolygonSoup soup;
  if (!lines.next_nonempty()) throw InputError(path + ": the file is empty");

  // The header is optional; the counts may follow it on the same line.
  std::size_t counts_at = 0;
  const std::string_view first = lines.tokens()[0];
  if (first.find("OFF") != std::string_view::npos) {
    if (!is_off_header(first))
      throw lines.error("unsupported OFF variant '" + printable(first) +
                        "' (only OFF, COFF, NOFF and STOFF are read)");
    if (lines.tokens().size() > 1 && lines.tokens()[1] == "BINARY")
      throw lines.error("binary OFF files are not supported");
    counts_at = 1;
    if (lines.tokens().size() == 1) {
      if (!lines.next_nonempty()) throw lines.error("the file ends before the counts 'vertices faces edges'");
      counts_at = 0;
    }
  }
  const auto& counts = lines.tokens();
  std::int64_t n_vertices = -1, n_faces = -1;
  if (counts.size() < counts_at + 2 || !parse_integer(counts[counts_at], n_vertices) ||
      !parse_integer(counts[counts_at + 1], n_faces) || n_vertices < 0 || n_faces < 0)
    throw lines.error("expected the counts 'vertices faces edges' as non-negative integers");

  // A corrupt count must not reserve more than the text could possibly hold.
  soup.points.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(n_vertices, text.size() / 6)));
  soup.faces.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(n_faces, text.size() / 8)));
  for (std::int64_t i = 0; i < n_vertices; ++i) {
    if (!lines.next_nonempty())
      throw lines.error("the file ends after " + std::to_string(i) + " of " + std::to_string(n_vertices) +
                        " vertices");
    soup.points.push_back(parse_point(lines, 0));
  }
  for (std::int64_t f = 0; f < n_faces; ++f) {
    if (!lines.next_nonempty())
      throw lines.error("the file ends after " + std::to_string(f) + " of " + std::to_string(n_faces) +
                        " faces");
    const auto& tokens = lines.tokens();
    std::int64_t n = 0;
    if (!parse_integer(tokens[0], n) || n < 0)
      throw lines.error("'" + printable(tokens[0]) + "' is not a vertex count");
    const auto found = static_cast<std::int64_t>(tokens.size()) - 1;
    if (found < n)
      throw lines.error("expected " + std::to_string(n) + " vertex indices, found " + std::to_string(found));
    std::vector<std::int64_t> face(static_cast<std::size_t>(n));
    for (std::int64_t k = 0; k < n; ++k)
      if (!parse_integer(tokens[k + 1], face[k]))
        throw lines.error("'" + printable(tokens[k + 1]) + "' is not a vertex index");
    soup.faces.push_back(std::move(face));
  }
  return soup;
}

PolygonSoup parse_obj(std::string_view text, const std::string& path, const ReadOptions& options) {
  check_text(text, path);
  TokenLines lines(text, path);
  PolygonSoup soup;
  // Faces may refer to vertices defined further down; those are checked once all are known.
  struct ForwardReference {
    std::int64_t line, index;
  };
  std::vector<ForwardReference> forward;
  while (lines.next_nonempty()) {
    while (!lines.tokens().empty() && lines.tokens().back().back() == '\\' && lines.continue_line()) {
    }
    if (lines.tokens().empty()) continue;
    const auto& tokens = lines.tokens();
    const std::string_view command = tokens[0];
    if (command == "v") {
      soup.points.push_back(parse_point(lines, 1));
    } else if (command == "f" || command == "fo") {
      std::vector<std::int64_t> face;
      face.reserve(tokens.size() - 1);
      const auto defined = static_cast<std::int64_t>(soup.points.size());
      for (std::size_t k = 1; k < tokens.size(); ++k) {
        // "v", "v/vt", "v//vn" or "v/vt/vn": only the vertex matters.
        const std::string_view vertex = tokens[k].substr(0, tokens[k].find('/'));
        std::int64_t index = 0;
        if (!parse_integer(vertex, index))
          throw lines.error("'" + printable(tokens[k]) + "' is not a vertex reference");
        if (index == 0) throw lines.error("vertex index 0 is invalid (OBJ counts vertices from 1)");
        if (index < 0) {
          if (-index > defined)
            throw lines.error("relative vertex index " + std::to_string(index) +
                              " points before the first vertex (" + std::to_string(defined) +
                              " defined so far)");
          index += defined;
        } else {
          --index;
          if (index >= defined) forward.push_back({lines.number(), index});
        }
        face.push_back(index);
      }
      soup.faces.push_back(std::move(face));
    } else if (command == "p" && options.skip_vertex_cells) {
      continue;
    } else if (command == "l" || command == "p" || command == "curv" || command == "curv2" ||
               command == "surf") {
      const char* what = command == "l" ? "polylines" : command == "p" ? "points" : "free-form geometry";
      throw lines.error("'" + std::string(command) + "' elements (" + what + ") are not surface polygons");
    }
  }
  const auto n = static_cast<std::int64_t>(soup.points.size());
  for (const auto& ref : forward)
    if (ref.index >= n)
      throw InputError(path + ": line " + std::to_string(ref.line) + ": vertex index " +
                       std::to_string(ref.index + 1) + " is out of range (the file has " + std::to_string(n) +
                       " vertices)");
  return soup;
}

PolygonSoup parse_ply(std::string_view data, const std::string& path, const ReadOptions& options) {
  Cursor c(data, path);
  const PlyHeader header = parse_ply_header(c, path);
  const PlyLayout layout = ply_layout(header, path);
  PolygonSoup soup;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    if (header.ascii)
      read_ascii_element(c, header, layout, static_cast<int>(e), path, soup, options.normals);
    else
      read_binary_element(c, header, layout, static_cast<int>(e), path, soup, options.normals);
  }
  return soup;
}

PolygonSoup parse_legacy_vtk(std::string_view data, const std::string& path, const ReadOptions& options) {
  return LegacyReader(data, path, options).read();
}

void append_poly_data_cells(const CellList& verts, const CellList& lines, const CellList& polys,
                            const CellList& strips, const std::string& path, PolygonSoup& soup,
                            const ReadOptions& options) {
  if (!verts.empty() && !options.skip_vertex_cells)
    throw not_a_surface_cell(path, 0, verts.front().size() <= 1 ? VTK_VERTEX : VTK_POLY_VERTEX);
  if (!lines.empty()) throw not_a_surface_cell(path, 0, lines.front().size() <= 2 ? VTK_LINE : VTK_POLY_LINE);
  soup.faces.insert(soup.faces.end(), polys.begin(), polys.end());
  for (const auto& strip : strips) append_strip(strip, soup);
}

void append_grid_cells(const CellList& cells, const std::vector<int>& types, const std::string& path,
                       PolygonSoup& soup, const ReadOptions& options) {
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const auto& ids = cells[c];
    switch (types[c]) {
      case VTK_TRIANGLE:
      case VTK_QUAD:
      case VTK_POLYGON:
        soup.faces.push_back(ids);
        break;
      case VTK_PIXEL:  // a quad with its last two corners swapped
        if (ids.size() == 4)
          soup.faces.push_back({ids[0], ids[1], ids[3], ids[2]});
        else
          soup.faces.push_back(ids);
        break;
      case VTK_TRIANGLE_STRIP:
        append_strip(ids, soup);
        break;
      case VTK_VERTEX:
      case VTK_POLY_VERTEX:
        if (!options.skip_vertex_cells) throw not_a_surface_cell(path, c, types[c]);
        break;
      default:
        throw not_a_surface_cell(path, c, types[c]);
    }
  }
}

}  // namespace rgbmesh::detail
