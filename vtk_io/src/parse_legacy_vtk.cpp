// Legacy VTK (.vtk): POLYDATA and UNSTRUCTURED_GRID data sets, ASCII or binary, both cell
// layouts (before and from file version 5).

#include "parse_common.hpp"
#include "parsers.hpp"

namespace rgbmesh::detail {
namespace {

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
    constexpr std::string_view signature = "# vtk DataFile Version ";
    const bool signed_file = c_.starts_with(signature);
    const std::string_view first = signed_file ? c_.line() : std::string_view();
    if (!signed_file)
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

}  // namespace

PolygonSoup parse_legacy_vtk(std::string_view data, const std::string& path, const ReadOptions& options) {
  return LegacyReader(data, path, options).read();
}

}  // namespace rgbmesh::detail
