// PLY (the Stanford polygon format), ASCII and binary in both byte orders.

#include "parse_common.hpp"
#include "parsers.hpp"

namespace rgbmesh::detail {
namespace {

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
  std::vector<std::string> notes;  // free-text lines read as comments
};

// At most `limit` single-character edits between a and b (Levenshtein, cut off early).
bool within_edits(std::string_view a, std::string_view b, std::size_t limit) {
  if (a.size() > b.size() + limit || b.size() > a.size() + limit) return false;
  std::vector<std::size_t> row(b.size() + 1), next(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    next[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      next[j] = std::min({row[j] + 1, next[j - 1] + 1, row[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    row.swap(next);
  }
  return row[b.size()] <= limit;
}

// Whether a header line that is no PLY keyword is free text that an old exporter wrote without
// 'comment' ("Created by Blender 2.49", read by VTK's reader too) rather than a damaged
// declaration. A damaged 'element' or 'property' line skipped would shift every value after it,
// so anything that looks like one is refused: a single word ("bogus"), a first word a couple of
// letters away from a keyword ("propery float x"), a PLY type or 'list' as the second word.
bool is_free_text(const std::vector<std::string_view>& tokens) {
  if (tokens.size() < 2) return false;
  for (const std::string_view keyword : {"element", "property", "format", "comment", "obj_info", "end_header"})
    if (within_edits(tokens[0], keyword, 2)) return false;
  Scalar type;
  return tokens[1] != "list" && !ply_scalar(tokens[1], type);
}

PlyHeader parse_ply_header(Cursor& c, const std::string& path) {
  if ((!c.starts_with("ply\n") && !c.starts_with("ply\r\n")) || c.line() != "ply")
    throw InputError(path + ": not a PLY file (it does not start with 'ply')");
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
    } else if (is_free_text(tokens)) {
      if (header.notes.empty())
        header.notes.push_back("line " + std::to_string(c.line_number()) + ": free text '" + printable(keyword) +
                               " ...' in the PLY header read as a comment (old exporters wrote such lines without "
                               "'comment')");
    } else {
      throw c.error("unexpected '" + printable(keyword) + "' in the PLY header");
    }
  }
  if (!have_format) throw InputError(path + ": the PLY header has no 'format' line");
  return header;
}

// Which element and properties hold the geometry.
struct PlyLayout {
  int vertex = -1, face = -1;    // element indices
  int xyz[3] = {-1, -1, -1};     // property indices in the vertex element
  int indices = -1;              // property index of the face's vertex list
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
  // Bytes per item: exact without lists; with lists the least an item can take (its scalars and
  // the length of each list, all lists empty).
  std::size_t row = 0;
  bool has_list = false;
  for (const PlyProperty& p : element.properties) {
    has_list = has_list || p.is_list;
    row += p.is_list ? size_of(p.count_type) : size_of(p.type);
  }
  // A count that the bytes left cannot hold is reported before anything is reserved for it.
  if (row > 0 && static_cast<std::uint64_t>(element.count) > c.remaining() / row) {
    if (!has_list) throw ply_truncated(path, element, static_cast<std::int64_t>(c.remaining() / row));
    throw InputError(path + ": the header announces " + std::to_string(element.count) +
                     " items of element '" + element.name + "' (at least " + std::to_string(row) +
                     " bytes each), the " + std::to_string(c.remaining()) +
                     " bytes left in the file hold at most " + std::to_string(c.remaining() / row) +
                     ": it is truncated or the count is damaged");
  }
  if (!has_list && !is_vertex) {
    // Fixed-size items that are not the points: skipped at once.
    c.take(row * static_cast<std::size_t>(element.count));
    return;
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

}  // namespace

PolygonSoup parse_ply(std::string_view data, const std::string& path, const ReadOptions& options) {
  Cursor c(data, path);
  const PlyHeader header = parse_ply_header(c, path);
  const PlyLayout layout = ply_layout(header, path);
  PolygonSoup soup;
  soup.notes = header.notes;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    if (header.ascii)
      read_ascii_element(c, header, layout, static_cast<int>(e), path, soup, options.normals);
    else
      read_binary_element(c, header, layout, static_cast<int>(e), path, soup, options.normals);
  }
  return soup;
}

}  // namespace rgbmesh::detail
