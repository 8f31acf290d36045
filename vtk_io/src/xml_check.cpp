// See xml_check.hpp for what is checked and why. The layout of VTK's binary data:
//
//   uncompressed:  [byte count] [bytes]
//   compressed:    [blocks] [block size] [last block size, 0 if full] [compressed size of each
//                  block...] [compressed blocks...]
//
// each header word a UInt32 or UInt64 (header_type) in the file's byte order. Appended raw data
// holds these bytes as they are, at the array's offset after the '_' that starts the section.
// Base64 data (inline "binary" arrays, appended base64) encodes an uncompressed array as one
// base64 run, a compressed one as two: the header, then the blocks.

#include "xml_check.hpp"

#include <vtkDataCompressor.h>
#include <vtkLZ4DataCompressor.h>
#include <vtkLZMADataCompressor.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkZLibDataCompressor.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "input_file.hpp"
#include "io_common.hpp"
#include "rgbmesh/errors.hpp"
#include "vtk_messages.hpp"

namespace rgbmesh::detail {
namespace {

constexpr std::size_t npos = std::string_view::npos;
using u64 = std::uint64_t;

// ---------------------------------------------------------------------------------------------
// The XML, up to the appended data (where VTK's own parser stops too)

struct Attribute {
  std::string_view name, value;
};

struct Element {
  std::string_view name;
  std::vector<Attribute> attributes;
  std::vector<Element> children;
  // The text right after the start tag, up to the next tag (inline array data).
  std::size_t text_begin = npos, text_end = npos;

  std::optional<std::string_view> attribute(std::string_view key) const {
    for (const Attribute& a : attributes)
      if (a.name == key) return a.value;
    return std::nullopt;
  }
};

bool is_xml_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

bool is_name_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == ':' ||
         c == '-' || c == '.' || static_cast<unsigned char>(c) >= 0x80;
}

std::string shown(std::string_view s) {
  std::string text;
  for (const char c : s.substr(0, 40)) text += (c >= 32 && c < 127) ? c : '?';
  return s.size() > 40 ? text + "..." : text;
}

struct Document {
  Element root;
  bool has_appended = false;
  bool appended_base64 = false;
  std::size_t appended_begin = npos;  // after the '_'
};

class XmlReader {
 public:
  XmlReader(std::string_view data, const std::string& path) : data_(data), path_(path) {}

  Document read() {
    Document doc;
    std::vector<Element*> open;
    bool root_seen = false;
    // The scan goes front to back and stops at the first problem, so that a large damaged file
    // is refused without reading it all.
    const std::size_t end = data_.size();
    pos_ = data_.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
    while (pos_ < end) {
      if (data_[pos_] != '<') {
        if (open.empty()) {
          if (!is_xml_space(data_[pos_]))
            throw error("text outside the XML elements at byte " + std::to_string(pos_));
          ++pos_;
          continue;
        }
        const std::size_t next = std::min(data_.find('<', pos_), end);
        if (open.back()->text_begin == npos) {
          open.back()->text_begin = pos_;
          open.back()->text_end = next;
        }
        pos_ = next;
        continue;
      }
      // VTK's parser stops at the first "<AppendedData", wherever it stands.
      if (starts_with("<AppendedData")) break;
      if (starts_with("<?")) {
        skip_past("?>", end);
      } else if (starts_with("<!--")) {
        skip_past("-->", end);
      } else if (starts_with("<!")) {
        throw error("unsupported XML markup at byte " + std::to_string(pos_));
      } else if (starts_with("</")) {
        pos_ += 2;
        const std::string_view name = read_name(end);
        skip_space(end);
        if (pos_ >= end || data_[pos_] != '>') throw error("a malformed end tag </" + shown(name) + ">");
        ++pos_;
        if (open.empty() || open.back()->name != name)
          throw error(
              "the end tag </" + shown(name) + "> does not match " +
              (open.empty() ? std::string("any open element") : "<" + std::string(open.back()->name) + ">"));
        open.pop_back();
      } else {
        if (root_seen && open.empty()) throw error("more than one root element");
        Element element;
        const bool empty = read_start_tag(element, end);
        Element* added;
        if (open.empty()) {
          doc.root = std::move(element);
          added = &doc.root;
          root_seen = true;
        } else {
          // A parent's children only grow while it is the innermost open element, so the
          // pointers kept in `open` stay valid.
          open.back()->children.push_back(std::move(element));
          added = &open.back()->children.back();
        }
        if (!empty) {
          if (open.size() >= 64) throw error("the XML elements are nested too deeply");
          open.push_back(added);
        }
      }
    }
    if (!root_seen) throw error("not a VTK XML file (no XML element found)");
    if (pos_ >= end) {
      if (!open.empty())
        throw error("the file ends inside <" + std::string(open.back()->name) + ">: it is truncated");
      return doc;
    }
    // <AppendedData encoding="..."> directly in <VTKFile>, then '_' and the data.
    if (open.size() != 1) throw error("<AppendedData> is not directly inside <VTKFile>");
    Element element;
    if (read_start_tag(element, data_.size())) throw error("<AppendedData/> holds no data");
    const std::string_view encoding = element.attribute("encoding").value_or("");
    if (encoding != "raw" && encoding != "base64")
      throw error("<AppendedData> has encoding=\"" + shown(encoding) + "\" (raw or base64 expected)");
    skip_space(data_.size());
    if (pos_ >= data_.size() || data_[pos_] != '_')
      throw error("the appended data does not start with '_': the file is damaged");
    doc.has_appended = true;
    doc.appended_base64 = encoding == "base64";
    doc.appended_begin = pos_ + 1;
    return doc;
  }

 private:
  bool starts_with(std::string_view s) const { return data_.substr(pos_, s.size()) == s; }

  void skip_past(std::string_view terminator, std::size_t end) {
    const std::size_t at = data_.substr(0, end).find(terminator, pos_);
    if (at == npos) throw error("the file ends inside XML markup: it is truncated");
    // VTK would stop there: what it reads would not be what is checked.
    if (data_.substr(pos_, at - pos_).find("<AppendedData") != npos)
      throw error("\"<AppendedData\" inside XML markup");
    pos_ = at + terminator.size();
  }

  void skip_space(std::size_t end) {
    while (pos_ < end && is_xml_space(data_[pos_])) ++pos_;
  }

  std::string_view read_name(std::size_t end) {
    const std::size_t start = pos_;
    while (pos_ < end && is_name_char(data_[pos_])) ++pos_;
    if (pos_ == start) {
      if (pos_ >= end) throw error("the file ends inside an XML tag: it is truncated");
      throw error("malformed XML at byte " + std::to_string(pos_));
    }
    return data_.substr(start, pos_ - start);
  }

  // At '<'. True for an empty element ("/>").
  bool read_start_tag(Element& element, std::size_t end) {
    ++pos_;
    element.name = read_name(end);
    for (;;) {
      const std::size_t before = pos_;
      skip_space(end);
      if (pos_ >= end) throw error("the file ends inside <" + shown(element.name) + ">: it is truncated");
      if (data_[pos_] == '>') {
        ++pos_;
        check_unique_attributes(element);
        return false;
      }
      if (starts_with("/>")) {
        pos_ += 2;
        check_unique_attributes(element);
        return true;
      }
      if (pos_ == before) throw error("malformed attributes in <" + shown(element.name) + ">");
      Attribute a;
      a.name = read_name(end);
      skip_space(end);
      if (pos_ >= end || data_[pos_] != '=')
        throw error("malformed attribute in <" + shown(element.name) + ">");
      ++pos_;
      skip_space(end);
      if (pos_ >= end || (data_[pos_] != '"' && data_[pos_] != '\''))
        throw error("malformed attribute in <" + shown(element.name) + ">");
      const char quote = data_[pos_++];
      const std::size_t close = data_.substr(0, end).find(quote, pos_);
      if (close == npos) throw error("the file ends inside <" + shown(element.name) + ">: it is truncated");
      a.value = data_.substr(pos_, close - pos_);
      if (a.value.find('<') != npos) throw error("malformed attribute in <" + shown(element.name) + ">");
      pos_ = close + 1;
      element.attributes.push_back(a);
    }
  }

  // An attribute given twice (VTK would take one of them, unchecked). Sorted, not compared pair
  // by pair: a tag with a million attributes would take hours. Names the attribute whose second
  // occurrence comes first, as a front-to-back scan would.
  void check_unique_attributes(const Element& element) const {
    std::vector<std::pair<std::string_view, std::size_t>> names;
    names.reserve(element.attributes.size());
    for (std::size_t i = 0; i < element.attributes.size(); ++i)
      names.emplace_back(element.attributes[i].name, i);
    std::sort(names.begin(), names.end());
    std::size_t repeated = npos;
    for (std::size_t i = 1; i < names.size(); ++i)
      if (names[i].first == names[i - 1].first) repeated = std::min(repeated, names[i].second);
    if (repeated != npos)
      throw error("<" + shown(element.name) + "> repeats the attribute " +
                  shown(element.attributes[repeated].name));
  }

  InputError error(const std::string& what) const { return InputError(path_ + ": cannot read: " + what); }

  std::string_view data_;
  const std::string& path_;
  std::size_t pos_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Numbers, base64, binary words

// A count as the header must write it: decimal digits only (VTK reads "-1" as a huge size).
bool parse_count(std::string_view text, u64& value) {
  if (text.empty() || text.size() > 19) return false;
  for (const char c : text)
    if (c < '0' || c > '9') return false;
  std::from_chars(text.data(), text.data() + text.size(), value);
  return true;
}

bool checked_multiply(u64 a, u64 b, u64& product) {
  if (a != 0 && b > std::numeric_limits<u64>::max() / a) return false;
  product = a * b;
  return true;
}

int base64_digit(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

// Characters that encode n bytes.
u64 base64_length(u64 bytes) { return (bytes + 2) / 3 * 4; }

// Decodes whole groups of 4 characters; '=' only as padding of the last group. False for any
// other character.
bool decode_base64(std::string_view text, std::string& out) {
  out.clear();
  out.reserve(text.size() / 4 * 3);
  for (std::size_t i = 0; i + 4 <= text.size(); i += 4) {
    int digits[4];
    int pad = 0;
    for (int k = 0; k < 4; ++k) {
      const char c = text[i + k];
      if (c == '=' && k >= 2 && i + 4 == text.size()) {
        digits[k] = 0;
        ++pad;
        continue;
      }
      if (pad > 0) return false;
      digits[k] = base64_digit(c);
      if (digits[k] < 0) return false;
    }
    const std::uint32_t group =
        static_cast<std::uint32_t>(digits[0] << 18 | digits[1] << 12 | digits[2] << 6 | digits[3]);
    out += static_cast<char>(group >> 16);
    if (pad < 2) out += static_cast<char>(group >> 8 & 0xFF);
    if (pad < 1) out += static_cast<char>(group & 0xFF);
  }
  return text.size() % 4 == 0;
}

enum class Compressor { none, zlib, lz4, lzma };

// How much larger than its compressed blocks an array can honestly be. zlib's deflate cannot
// expand by more than about 1032 to 1, LZ4's by about 255; LZMA in its xz container reaches a
// few thousand on uniform data. A block header announcing more is damaged.
u64 expansion_limit(Compressor c) {
  switch (c) {
    case Compressor::lz4:
      return 256;
    case Compressor::lzma:
      return 8192;
    default:
      return 1032;
  }
}

struct Word {
  std::string_view name;
  std::size_t size;  // bytes; 0 for String (variable), 1 for Bit (8 values a byte)
  bool is_integer;
  bool is_signed;
};

const Word* word_type(std::string_view name) {
  static const Word types[] = {
      {"Int8", 1, true, true},     {"UInt8", 1, true, false},   {"Int16", 2, true, true},
      {"UInt16", 2, true, false},  {"Int32", 4, true, true},    {"UInt32", 4, true, false},
      {"Int64", 8, true, true},    {"UInt64", 8, true, false},  {"Float32", 4, false, true},
      {"Float64", 8, false, true}, {"String", 0, false, false}, {"Bit", 1, true, false}};
  for (const Word& w : types)
    if (w.name == name) return &w;
  return nullptr;
}

// ---------------------------------------------------------------------------------------------
// The checks

// One array's data, where the file has it.
struct ArrayData {
  u64 values = 0;                      // how many values the data hold
  std::vector<std::int64_t> integers;  // decoded, when asked for
};

class Checker {
 public:
  Checker(std::string_view data, const std::string& path, const Document& doc)
      : data_(data), path_(path), doc_(doc) {}

  void check(std::string_view data_set) {
    const Element& root = doc_.root;
    if (root.name != "VTKFile")
      throw error("not a VTK XML file (the root element is <" + shown(root.name) + ">)");
    const std::string_view type = root.attribute("type").value_or("");
    if (type != data_set)
      throw error("the file holds VTK " + (type.empty() ? std::string("(no type)") : shown(type)) +
                  " data, not " + std::string(data_set));
    const std::string_view order =
        root.attribute("byte_order").value_or(host_is_big_endian() ? "BigEndian" : "LittleEndian");
    if (order != "LittleEndian" && order != "BigEndian")
      throw error("byte_order=\"" + shown(order) + "\" is neither LittleEndian nor BigEndian");
    swap_ = (order == "BigEndian") != host_is_big_endian();
    const std::string_view header = root.attribute("header_type").value_or("UInt32");
    if (header != "UInt32" && header != "UInt64")
      throw error("header_type=\"" + shown(header) + "\" is neither UInt32 nor UInt64");
    word_ = header == "UInt64" ? 8 : 4;
    const std::string_view compressor = root.attribute("compressor").value_or("");
    if (compressor.empty())
      compressor_ = Compressor::none;
    else if (compressor == "vtkZLibDataCompressor")
      compressor_ = Compressor::zlib;
    else if (compressor == "vtkLZ4DataCompressor")
      compressor_ = Compressor::lz4;
    else if (compressor == "vtkLZMADataCompressor")
      compressor_ = Compressor::lzma;
    else
      throw error("unknown compressor=\"" + shown(compressor) + "\"");

    const Element* set = nullptr;
    for (const Element& child : root.children)
      if (child.name == data_set) {
        if (set != nullptr) throw error("more than one <" + std::string(data_set) + "> element");
        set = &child;
      }
    if (set == nullptr) throw error("no <" + std::string(data_set) + "> element");
    int piece = 0;
    for (const Element& child : set->children) {
      if (child.name == "FieldData") check_field_data(child);
      if (child.name == "Piece") check_piece(child, piece++, data_set == "PolyData");
    }
  }

 private:
  InputError error(const std::string& what) const { return InputError(path_ + ": cannot read: " + what); }

  u64 count(const Element& piece, int index, std::string_view name) const {
    const std::optional<std::string_view> text = piece.attribute(name);
    if (!text) return 0;
    u64 value = 0;
    if (!parse_count(*text, value) || value > static_cast<u64>(std::numeric_limits<std::int64_t>::max()))
      throw error("piece " + std::to_string(index) + ": " + std::string(name) + "=\"" + shown(*text) +
                  "\" is not a count (a non-negative integer)");
    return value;
  }

  static const Element* child(const Element& parent, std::string_view name) {
    for (const Element& c : parent.children)
      if (c.name == name) return &c;
    return nullptr;
  }

  static bool is_array(const Element& e) { return e.name == "DataArray" || e.name == "Array"; }

  static const Element* array_named(const Element& parent, std::string_view name) {
    for (const Element& c : parent.children)
      if (is_array(c) && c.attribute("Name") == name) return &c;
    return nullptr;
  }

  // VTK's writers put nothing but arrays in these sections, and its readers take what they find
  // there for arrays without looking (see check_field_data).
  void only_arrays(const Element& section, const std::string& where) const {
    for (const Element& a : section.children)
      if (!is_array(a))
        throw error(where + " holds a <" + shown(a.name) + "> element, where only DataArray elements belong");
  }

  // VTK's attribute data hold one array per name: a second array of the same name replaces the
  // first while VTK's XML readers still read one array per element, by position, so that two
  // CellData arrays of the same name make vtkXMLPolyDataReader and
  // vtkXMLUnstructuredGridReader read through a null pointer (VTK 9.1). VTK's writers never
  // write two, so any section that has them is refused. Unnamed arrays are VTK's own error.
  void check_unique_names(const Element& data, const std::string& where) const {
    std::vector<std::string_view> names;
    for (const Element& a : data.children)
      if (is_array(a))
        if (const auto name = a.attribute("Name")) names.push_back(*name);
    std::sort(names.begin(), names.end());
    const auto repeated = std::adjacent_find(names.begin(), names.end());
    if (repeated != names.end()) throw error(where + " has two arrays named '" + shown(*repeated) + "'");
  }

  // VTK 9.1's readers make an array of every element inside FieldData, whatever its name, and
  // read through the null pointer they get for anything that is not an array (found by
  // fuzz_mesh_vtp once the tool's files carried field data).
  void check_field_data(const Element& field) {
    check_unique_names(field, "the field data");
    only_arrays(field, "the field data");
    for (const Element& a : field.children) {
      std::optional<u64> tuples;
      if (const auto text = a.attribute("NumberOfTuples")) {
        u64 n = 0;
        if (!parse_count(*text, n))
          throw error("field data array '" + shown(a.attribute("Name").value_or("")) +
                      "': NumberOfTuples=\"" + shown(*text) + "\" is not a count");
        tuples = n;
      }
      check_array(a, tuples, "field data array '" + shown(a.attribute("Name").value_or("")) + "'");
    }
  }

  void check_piece(const Element& piece, int index, bool poly_data) {
    const std::string where = "piece " + std::to_string(index);
    const u64 points = count(piece, index, "NumberOfPoints");
    static constexpr std::string_view kinds[] = {"Verts", "Lines", "Strips", "Polys"};
    u64 per_kind[4] = {0, 0, 0, 0};
    u64 cells = 0;
    if (poly_data) {
      for (int k = 0; k < 4; ++k) {
        per_kind[k] = count(piece, index, std::string("NumberOf") + std::string(kinds[k]));
        cells += per_kind[k];  // each at most 2^63: no overflow
      }
    } else {
      cells = count(piece, index, "NumberOfCells");
    }
    // Each count must be backed by an array the file holds, since VTK allocates by the counts
    // before it reads: the points by the Points array, the cells by their offsets.
    const Element* point_set = child(piece, "Points");
    const Element* coordinates = nullptr;
    if (point_set != nullptr) {
      // VTK reads the first element inside Points as the coordinates, whatever it is.
      only_arrays(*point_set, where + " Points");
      if (!point_set->children.empty()) coordinates = &point_set->children.front();
    }
    if (points > 0 && coordinates == nullptr)
      throw error(where + " has " + std::to_string(points) + " points but no Points array");
    if (coordinates != nullptr) {
      if (components(*coordinates, where + " points") != 3)
        throw error(where + ": the Points array has " + std::to_string(components(*coordinates, where)) +
                    " components instead of 3");
      check_array(*coordinates, points, where + " points");
    }
    for (const auto& [data_name, tuples] :
         {std::pair<std::string_view, u64>{"PointData", points}, {"CellData", cells}}) {
      if (const Element* data = child(piece, data_name)) {
        only_arrays(*data, where + " " + std::string(data_name));
        check_unique_names(*data, where + " " + std::string(data_name));
        for (const Element& a : data->children)
          if (is_array(a))
            check_array(a, tuples,
                        where + " " + std::string(data_name) + " array '" +
                            shown(a.attribute("Name").value_or("")) + "'");
      }
    }
    if (poly_data) {
      for (int k = 0; k < 4; ++k)
        check_cells(child(piece, kinds[k]), per_kind[k], where + " " + std::string(kinds[k]), false);
    } else {
      check_cells(child(piece, "Cells"), cells, where + " Cells", true);
    }
  }

  // A cell array: offsets (one per cell, or with a leading 0 one more), connectivity (as many
  // ids as the last offset says), and for unstructured grids the types (one per cell).
  void check_cells(const Element* cells, u64 n, const std::string& where, bool with_types) {
    if (n == 0 && cells == nullptr) return;
    if (cells == nullptr) throw error(where + ": " + std::to_string(n) + " cells but no cell arrays");
    const Element* offsets = array_named(*cells, "offsets");
    const Element* connectivity = array_named(*cells, "connectivity");
    if (n > 0 && (offsets == nullptr || connectivity == nullptr))
      throw error(where + ": " + std::to_string(n) + " cells but no " +
                  (offsets == nullptr ? "offsets" : "connectivity") + " array");
    if (offsets == nullptr || connectivity == nullptr) return;
    const ArrayData ids = check_array(*connectivity, std::nullopt, where + " connectivity");
    const ArrayData ends = check_array(*offsets, std::nullopt, where + " offsets", true);
    if (ends.values != n && ends.values != n + 1)
      throw error(where + ": the offsets array holds " + std::to_string(ends.values) + " values for " +
                  std::to_string(n) + " cells");
    std::int64_t previous = 0;
    for (std::size_t i = 0; i < ends.integers.size(); ++i) {
      const std::int64_t end = ends.integers[i];
      if (end < previous || static_cast<u64>(end) > ids.values)
        throw error(where + ": the cell offsets are corrupt at cell " + std::to_string(i) + " (offset " +
                    std::to_string(end) + ", " + std::to_string(ids.values) + " ids)");
      previous = end;
    }
    if (with_types) {
      const Element* types = array_named(*cells, "types");
      if (n > 0 && types == nullptr)
        throw error(where + ": " + std::to_string(n) + " cells but no types array");
      // Decoded (decompressed), not only measured: when VTK fails to read the types (a damaged
      // block), vtkXMLUnstructuredGridReader leaks the array it made for them (VTK 9.1).
      if (types != nullptr) check_array(*types, n, where + " types", true);
      // Polyhedra bring face arrays, whose layout VTK reads without checks; they are no surface
      // polygons anyway.
      if (array_named(*cells, "faces") != nullptr || array_named(*cells, "faceoffsets") != nullptr)
        throw error(where + ": polyhedron cells (faces arrays) are not surface polygons");
    }
  }

  u64 components(const Element& a, const std::string& what) const {
    const std::optional<std::string_view> text = a.attribute("NumberOfComponents");
    if (!text) return 1;
    u64 n = 0;
    if (!parse_count(*text, n) || n == 0 || n > (1u << 20))
      throw error(what + ": NumberOfComponents=\"" + shown(*text) + "\" is not a positive count");
    return n;
  }

  // Checks one array; `tuples` when the header says how many it must hold. With `decode`, the
  // values are returned as integers (cell offsets).
  ArrayData check_array(const Element& a, std::optional<u64> tuples, const std::string& what,
                        bool decode = false) {
    const std::string_view type_name = a.attribute("type").value_or("");
    const Word* type = word_type(type_name);
    if (type == nullptr) throw error(what + ": unsupported type=\"" + shown(type_name) + "\"");
    if (decode && !type->is_integer)
      throw error(what + ": type " + std::string(type_name) + " is not an integer type");
    const u64 n_components = components(a, what);
    std::optional<u64> expected;  // values
    if (tuples && type->size != 0) {
      u64 values = 0;
      if (!checked_multiply(*tuples, n_components, values))
        throw error(what + ": " + std::to_string(*tuples) + " tuples of " + std::to_string(n_components) +
                    " components are more than the file can hold");
      expected = values;
    }
    const std::string_view format = a.attribute("format").value_or("");
    ArrayData result;
    if (format == "ascii") {
      result = ascii_values(a, *type, what, decode);
    } else if (format == "binary" || format == "appended") {
      result = binary_values(a, *type, what, decode, format == "appended");
    } else {
      throw error(what + ": format=\"" + shown(format) + "\" is not ascii, binary or appended");
    }
    if (expected && result.values != *expected)
      throw error(what + ": the array holds " + std::to_string(result.values) +
                  " values, the header announces " + std::to_string(*expected));
    return result;
  }

  // VTK reads ASCII values with `stream >> value` until the first that does not parse, and is
  // content when it got as many as it needs: "1,5" was read as 1 (and ",5" dropped when it was
  // the last value), "0x10" as 0, "1.5" in an integer array as 1, 300 in a UInt8 array as 44;
  // where it got too few, vtkXMLUnstructuredGridReader leaked its cell types array (VTK 9.1). So
  // every value must be a number of the array's type, as the text readers of rgbmesh take
  // numbers (from_chars: decimal, "nan" and "inf" read, any overflow or underflow refused).
  ArrayData ascii_values(const Element& a, const Word& type, const std::string& what, bool decode) const {
    ArrayData result;
    if (a.text_begin == npos) return result;
    const std::string_view text = data_.substr(a.text_begin, a.text_end - a.text_begin);
    for (std::size_t i = 0; i < text.size();) {
      while (i < text.size() && is_xml_space(text[i])) ++i;
      const std::size_t start = i;
      while (i < text.size() && !is_xml_space(text[i])) ++i;
      if (i == start) break;
      ++result.values;
      const std::string_view token = text.substr(start, i - start);
      std::int64_t value = 0;
      if (!ascii_value(token, type, value)) {
        if (type.is_integer)
          throw error(what + ": '" + shown(token) + "' is not an integer in the range of " +
                      std::string(type.name));
        throw error(what + ": '" + shown(token) + "' is not a " + std::string(type.name) + " number");
      }
      if (decode) result.integers.push_back(value);
    }
    return result;
  }

  // Whether `token` is a value of `type`; integers are returned in `value` (a UInt64 beyond the
  // Int64 range as -1: a corrupt offset, as in binary data). Strings are character codes that
  // nothing here uses: not checked.
  static bool ascii_value(std::string_view token, const Word& type, std::int64_t& value) {
    if (type.size == 0) return true;
    if (!token.empty() && token[0] == '+') token.remove_prefix(1);
    const char* begin = token.data();
    const char* end = token.data() + token.size();
    if (type.is_integer) {
      if (type.is_signed) {
        const auto parsed = std::from_chars(begin, end, value);
        const std::int64_t limit = type.size == 8 ? 0 : std::int64_t{1} << (8 * type.size - 1);
        return parsed.ec == std::errc() && parsed.ptr == end &&
               (limit == 0 || (value >= -limit && value < limit));
      }
      u64 unsigned_value = 0;
      const auto parsed = std::from_chars(begin, end, unsigned_value);
      const u64 max = type.name == "Bit" ? 1
                      : type.size == 8   ? std::numeric_limits<u64>::max()
                                         : (u64{1} << (8 * type.size)) - 1;
      if (parsed.ec != std::errc() || parsed.ptr != end || unsigned_value > max) return false;
      value = unsigned_value > static_cast<u64>(std::numeric_limits<std::int64_t>::max())
                  ? -1
                  : static_cast<std::int64_t>(unsigned_value);
      return true;
    }
    // from_chars also takes "infinity" and "nan(...)", which VTK does not: past the sign, a
    // number starts with a digit or a point, or is "nan" or "inf" in any case.
    const std::string_view unsigned_part = token.substr(token.empty() || token[0] != '-' ? 0 : 1);
    const bool starts_number =
        !unsigned_part.empty() &&
        (std::isdigit(static_cast<unsigned char>(unsigned_part[0])) || unsigned_part[0] == '.');
    if (!starts_number && !equals_ignoring_case(unsigned_part, "nan") &&
        !equals_ignoring_case(unsigned_part, "inf"))
      return false;
    double number = 0;
    const auto parsed = std::from_chars(begin, end, number);
    if (parsed.ec != std::errc() || parsed.ptr != end) return false;
    // Beyond the float range, VTK's stream read fails.
    return type.size != 4 || !std::isfinite(number) || std::abs(number) <= std::numeric_limits<float>::max();
  }

  static bool equals_ignoring_case(std::string_view a, std::string_view lower) {
    if (a.size() != lower.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (std::tolower(static_cast<unsigned char>(a[i])) != lower[i]) return false;
    return true;
  }

  // Where the array's binary data start and end, and whether they are base64.
  struct Span {
    std::size_t begin, end;
    bool base64;
  };

  Span binary_span(const Element& a, const std::string& what, bool appended) const {
    if (!appended) {
      if (a.text_begin == npos) throw error(what + ": the inline binary array holds no data");
      std::size_t begin = a.text_begin, end = a.text_end;
      while (begin < end && is_xml_space(data_[begin])) ++begin;
      while (end > begin && is_xml_space(data_[end - 1])) --end;
      return {begin, end, true};
    }
    if (!doc_.has_appended) throw error(what + ": format=\"appended\" but the file has no appended data");
    const std::string_view text = a.attribute("offset").value_or("");
    u64 offset = 0;
    if (!parse_count(text, offset)) throw error(what + ": offset=\"" + shown(text) + "\" is not an offset");
    const u64 available = data_.size() - doc_.appended_begin;
    if (offset >= available)
      throw error(what + ": offset " + std::to_string(offset) + " is beyond the end of the file (" +
                  std::to_string(available) + " bytes of appended data)");
    return {doc_.appended_begin + static_cast<std::size_t>(offset), data_.size(), doc_.appended_base64};
  }

  // `count` header words from the start of span (base64: the run that starts there).
  bool header_words(const Span& span, std::size_t count, std::vector<u64>& words) const {
    const u64 bytes = static_cast<u64>(count) * word_;
    std::string decoded;
    std::string_view raw;
    if (span.base64) {
      const u64 chars = base64_length(bytes);
      if (chars > span.end - span.begin) return false;
      if (!decode_base64(data_.substr(span.begin, static_cast<std::size_t>(chars)), decoded) ||
          decoded.size() < bytes)
        return false;
      raw = decoded;
    } else {
      if (bytes > span.end - span.begin) return false;
      raw = data_.substr(span.begin, static_cast<std::size_t>(bytes));
    }
    words.clear();
    for (std::size_t w = 0; w < count; ++w) {
      unsigned char b[8] = {};
      std::memcpy(b, raw.data() + w * word_, word_);
      if (swap_) std::reverse(b, b + word_);
      u64 value = 0;
      for (std::size_t i = word_; i-- > 0;) value = value << 8 | b[i];
      words.push_back(value);
    }
    return true;
  }

  ArrayData binary_values(const Element& a, const Word& type, const std::string& what, bool decode,
                          bool appended) const {
    const Span span = binary_span(a, what, appended);
    const std::string damaged = what + ": the size header of the binary data is damaged or truncated";
    std::vector<u64> words;
    u64 bytes = 0;        // uncompressed
    std::string payload;  // the uncompressed bytes, when decoding
    if (compressor_ == Compressor::none) {
      if (!header_words(span, 1, words)) throw error(damaged);
      bytes = words[0];
      const u64 available = span.end - span.begin;
      const u64 needed = span.base64 ? base64_length(word_ + std::min<u64>(bytes, available)) : word_ + bytes;
      if (bytes > available || needed > available)
        throw error(what + ": the data announce " + std::to_string(bytes) +
                    " bytes, more than the file holds");
      if (decode) {
        if (span.base64) {
          std::string all;
          if (!decode_base64(data_.substr(span.begin, static_cast<std::size_t>(needed)), all) ||
              all.size() < word_ + bytes)
            throw error(what + ": the base64 data are damaged");
          payload = all.substr(word_, static_cast<std::size_t>(bytes));
        } else {
          payload.assign(data_.substr(span.begin + word_, static_cast<std::size_t>(bytes)));
        }
      }
    } else {
      if (!header_words(span, 3, words)) throw error(damaged);
      const u64 blocks = words[0], block_size = words[1], last_size = words[2];
      const u64 available = span.end - span.begin;
      if (blocks > available / word_)
        throw error(what + ": the compression header announces " + std::to_string(blocks) +
                    " blocks, more than the file holds");
      if (!header_words(span, static_cast<std::size_t>(3 + blocks), words)) throw error(damaged);
      const u64 header_bytes = (3 + blocks) * word_;
      const u64 data_begin = span.base64 ? base64_length(header_bytes) : header_bytes;
      u64 compressed = 0;
      for (u64 b = 0; b < blocks; ++b) {
        if (words[3 + b] == 0 || words[3 + b] > available - compressed)
          throw error(what + ": the compressed size of block " + std::to_string(b) + " is damaged");
        compressed += words[3 + b];
      }
      const u64 compressed_chars = span.base64 ? base64_length(compressed) : compressed;
      if (data_begin > available || compressed_chars > available - data_begin)
        throw error(what + ": the compressed blocks announce " + std::to_string(compressed) +
                    " bytes, more than the file holds");
      // VTK divides by the block size and indexes the blocks by it: 0 blocks or a last block
      // larger than the others would make it read outside its tables.
      if (blocks == 0) {
        if (last_size != 0)
          throw error(what + ": the compression header announces 0 blocks with a partial last block");
      } else {
        if (block_size == 0 || last_size > block_size)
          throw error(what + ": the compression header announces blocks of " + std::to_string(block_size) +
                      " bytes with a last one of " + std::to_string(last_size));
        u64 full = 0;
        if (!checked_multiply(last_size == 0 ? blocks : blocks - 1, block_size, full) ||
            full > std::numeric_limits<u64>::max() - last_size)
          throw error(what + ": the compression header announces more data than the file can hold");
        bytes = full + last_size;
        if (bytes / expansion_limit(compressor_) > compressed + 1024)
          throw error(what + ": the compression header announces " + std::to_string(bytes) + " bytes from " +
                      std::to_string(compressed) + " compressed bytes, more than the compressor can produce");
      }
      if (decode) payload = decompress(span, data_begin, words, block_size, last_size, what);
    }
    ArrayData result;
    if (type.size == 0) {  // String: variable length, nothing to count
      result.values = 0;
      return result;
    }
    result.values = type.name == "Bit" ? bytes * 8 : bytes / type.size;
    if (type.name != "Bit" && bytes % type.size != 0)
      throw error(what + ": the data hold " + std::to_string(bytes) + " bytes, not a whole number of " +
                  std::string(type.name) + " values");
    if (decode) result.integers = integers_of(payload, type);
    return result;
  }

  std::string decompress(const Span& span, u64 data_begin, const std::vector<u64>& words, u64 block_size,
                         u64 last_size, const std::string& what) const {
    // VTK's compressors report a damaged block on VTK's error output.
    CapturedVtkMessages quiet;
    vtkSmartPointer<vtkDataCompressor> compressor;
    switch (compressor_) {
      case Compressor::zlib:
        compressor = vtkSmartPointer<vtkZLibDataCompressor>::New();
        break;
      case Compressor::lz4:
        compressor = vtkSmartPointer<vtkLZ4DataCompressor>::New();
        break;
      default:
        compressor = vtkSmartPointer<vtkLZMADataCompressor>::New();
        break;
    }
    const u64 blocks = words[0];
    std::string compressed_bytes;
    u64 compressed = 0;
    for (u64 b = 0; b < blocks; ++b) compressed += words[3 + b];
    if (span.base64) {
      if (!decode_base64(data_.substr(span.begin + data_begin, base64_length(compressed)),
                         compressed_bytes) ||
          compressed_bytes.size() < compressed)
        throw error(what + ": the base64 data are damaged");
    } else {
      compressed_bytes.assign(data_.substr(span.begin + data_begin, compressed));
    }
    std::string out;
    std::size_t at = 0;
    for (u64 b = 0; b < blocks; ++b) {
      const u64 size = (b + 1 == blocks && last_size != 0) ? last_size : block_size;
      const std::size_t start = out.size();
      out.resize(start + size);
      const std::size_t produced =
          compressor->Uncompress(reinterpret_cast<const unsigned char*>(compressed_bytes.data() + at),
                                 words[3 + b], reinterpret_cast<unsigned char*>(out.data() + start), size);
      if (produced != size) throw error(what + ": compressed block " + std::to_string(b) + " is damaged");
      at += words[3 + b];
    }
    return out;
  }

  std::vector<std::int64_t> integers_of(const std::string& bytes, const Word& type) const {
    std::vector<std::int64_t> values;
    if (type.name == "Bit") return values;
    values.reserve(bytes.size() / type.size);
    for (std::size_t at = 0; at + type.size <= bytes.size(); at += type.size) {
      unsigned char b[8] = {};
      std::memcpy(b, bytes.data() + at, type.size);
      if (swap_) std::reverse(b, b + type.size);
      u64 raw = 0;
      for (std::size_t i = type.size; i-- > 0;) raw = raw << 8 | b[i];
      if (type.is_signed && type.size < 8 && (raw >> (8 * type.size - 1)) != 0)
        raw |= ~u64{0} << (8 * type.size);
      // An unsigned 64-bit value beyond the signed range reads as negative: a corrupt offset.
      values.push_back(static_cast<std::int64_t>(raw));
    }
    return values;
  }

  std::string_view data_;
  const std::string& path_;
  const Document& doc_;
  bool swap_ = false;
  std::size_t word_ = 4;
  Compressor compressor_ = Compressor::none;
};

}  // namespace

void check_vtk_xml(std::string_view data, const std::string& path, std::string_view data_set) {
  const Document doc = XmlReader(data, path).read();
  Checker(data, path, doc).check(data_set);
}

}  // namespace rgbmesh::detail
