// Reading mesh files and point clouds. See vtk_io.hpp for the contract; the notes here say why
// the code does what it does.

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkSmartPointer.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include "io_common.hpp"
#include "parsers.hpp"
#include "rgbmesh/vtk_io.hpp"
#include "vtk_messages.hpp"

namespace rgbmesh {
namespace {

namespace fs = std::filesystem;
using namespace detail;

// The cells of a vtkCellArray as id lists. The XML readers do not validate what they read, so the
// offsets are checked before they are used to index the connectivity.
template <class IdArray>
detail::CellList cells_of(IdArray* offsets, IdArray* connectivity, const fs::path& path) {
  detail::CellList cells;
  const vtkIdType n_offsets = offsets != nullptr ? offsets->GetNumberOfValues() : 0;
  if (n_offsets <= 1) return cells;
  const vtkIdType n_ids = connectivity != nullptr ? connectivity->GetNumberOfValues() : 0;
  const auto* offset = offsets->GetPointer(0);
  const auto* ids = n_ids > 0 ? connectivity->GetPointer(0) : nullptr;
  if (offset[0] != 0)
    throw InputError(path.string() + ": cannot read: corrupt cell offsets (the first is not 0)");
  cells.reserve(static_cast<std::size_t>(n_offsets - 1));
  for (vtkIdType c = 0; c + 1 < n_offsets; ++c) {
    if (offset[c + 1] < offset[c] || offset[c + 1] > n_ids)
      throw InputError(path.string() + ": cannot read: corrupt cell offsets at cell " + std::to_string(c));
    cells.emplace_back(ids + offset[c], ids + offset[c + 1]);
  }
  return cells;
}

detail::CellList cells_of(vtkCellArray* cells, const fs::path& path) {
  if (cells == nullptr) return {};
  if (cells->IsStorage64Bit())
    return cells_of(cells->GetOffsetsArray64(), cells->GetConnectivityArray64(), path);
  return cells_of(cells->GetOffsetsArray32(), cells->GetConnectivityArray32(), path);
}

void append_points(vtkPoints* points, PolygonSoup& soup) {
  if (points == nullptr) return;
  const vtkIdType n = points->GetNumberOfPoints();
  soup.points.reserve(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i) {
    double p[3];
    points->GetPoint(i, p);
    soup.points.emplace_back(p[0], p[1], p[2]);
  }
}

// The data set's point normals, when asked for and present with one 3-vector per point.
void append_normals(vtkDataSet& data, const PolygonSoup& soup, const detail::ReadOptions& options) {
  vtkDataArray* normals = data.GetPointData() != nullptr ? data.GetPointData()->GetNormals() : nullptr;
  if (options.normals == nullptr || normals == nullptr || normals->GetNumberOfComponents() != 3 ||
      normals->GetNumberOfTuples() != static_cast<vtkIdType>(soup.points.size()))
    return;
  for (vtkIdType i = 0; i < normals->GetNumberOfTuples(); ++i) {
    double n[3];
    normals->GetTuple(i, n);
    options.normals->emplace_back(n[0], n[1], n[2]);
  }
}

PolygonSoup soup_of(vtkPolyData& data, const fs::path& path, const detail::ReadOptions& options) {
  PolygonSoup soup;
  append_points(data.GetPoints(), soup);
  detail::append_poly_data_cells(cells_of(data.GetVerts(), path), cells_of(data.GetLines(), path),
                                 cells_of(data.GetPolys(), path), cells_of(data.GetStrips(), path),
                                 path.string(), soup, options);
  append_normals(data, soup, options);
  return soup;
}

PolygonSoup soup_of(vtkUnstructuredGrid& grid, const fs::path& path, const detail::ReadOptions& options) {
  PolygonSoup soup;
  append_points(grid.GetPoints(), soup);
  const detail::CellList cells = cells_of(grid.GetCells(), path);
  std::vector<int> types;
  if (vtkUnsignedCharArray* type_array = grid.GetCellTypesArray())
    for (vtkIdType c = 0; c < type_array->GetNumberOfValues(); ++c) types.push_back(type_array->GetValue(c));
  if (types.size() != cells.size())
    throw InputError(path.string() + ": cannot read: " + std::to_string(cells.size()) + " cells but " +
                     std::to_string(types.size()) + " cell types");
  detail::append_grid_cells(cells, types, path.string(), soup, options);
  append_normals(grid, soup, options);
  return soup;
}

// STL stores every triangle's corners separately: exactly equal points are one vertex.
// Non-finite points are never merged (prepare_triangle_mesh reports them).
void merge_equal_points(PolygonSoup& soup) {
  struct Hash {
    std::size_t operator()(const Vec3& p) const {
      std::size_t h = 0;
      for (const double c : {p.x, p.y, p.z}) {
        std::uint64_t bits;
        const double normalized = c + 0.0;  // -0 and +0 are equal and must hash alike
        std::memcpy(&bits, &normalized, sizeof bits);
        h = h * 0x9E3779B97F4A7C15ull + (bits ^ (bits >> 29));
      }
      return h;
    }
  };
  std::unordered_map<Vec3, std::int64_t, Hash> index_of;
  index_of.reserve(soup.points.size());
  std::vector<std::int64_t> new_index(soup.points.size());
  std::vector<Vec3> merged;
  for (std::size_t i = 0; i < soup.points.size(); ++i) {
    const Vec3& p = soup.points[i];
    const auto next = static_cast<std::int64_t>(merged.size());
    if (!is_finite(p)) {
      new_index[i] = next;
      merged.push_back(p);
      continue;
    }
    const auto [it, inserted] = index_of.try_emplace(p, next);
    if (inserted) merged.push_back(p);
    new_index[i] = it->second;
  }
  const auto n = static_cast<std::int64_t>(new_index.size());
  for (auto& face : soup.faces)
    for (auto& v : face)
      if (v >= 0 && v < n) v = new_index[v];
  soup.points = std::move(merged);
}

// vtkSTLReader 9.1 reads a truncated binary STL without complaint, returning the triangles that
// are complete. A binary file must be exactly as long as its triangle count says. (ASCII files
// start with "solid" and hold only text; VTK reports their truncation itself.)
void check_binary_stl_length(const fs::path& path) {
  constexpr std::size_t header_bytes = 84, triangle_bytes = 50;
  std::ifstream in(path, std::ios::binary);
  std::string start(1024, '\0');
  in.read(start.data(), static_cast<std::streamsize>(start.size()));
  start.resize(static_cast<std::size_t>(in.gcount()));
  const bool text = std::all_of(start.begin(), start.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u >= 32 || c == '\n' || c == '\r' || c == '\t' || c == '\f' || c == '\v';
  });
  const auto word = start.find_first_not_of(" \t\r\n");
  if (text && word != std::string::npos && start.compare(word, 5, "solid") == 0) return;
  const std::uintmax_t size = fs::file_size(path);
  if (size < header_bytes)
    throw InputError(path.string() +
                     ": cannot read: a binary STL file needs an 84-byte header, the file has " +
                     std::to_string(size) + " bytes");
  std::uint32_t count = 0;  // little-endian by the format
  for (int i = 3; i >= 0; --i) count = count << 8 | static_cast<unsigned char>(start[80 + i]);
  const std::uintmax_t expected = header_bytes + triangle_bytes * static_cast<std::uintmax_t>(count);
  if (size < expected)
    throw InputError(path.string() + ": cannot read: the binary STL header announces " +
                     std::to_string(count) + " triangles (" + std::to_string(expected) +
                     " bytes), the file has " + std::to_string(size) + " bytes: it is truncated");
}

std::string file_contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot open the file: " + std::strerror(errno));
  std::ostringstream contents;
  contents << in.rdbuf();
  if (in.bad()) throw InputError(path.string() + ": cannot read: " + std::strerror(errno));
  return contents.str();
}

// The value of attribute `name` in `text` ("" if absent).
std::string_view attribute(std::string_view text, std::string_view name) {
  const std::string key = " " + std::string(name) + "=\"";
  const auto at = text.find(key);
  if (at == std::string_view::npos) return {};
  const auto begin = at + key.size(), end = text.find('"', begin);
  return end == std::string_view::npos ? std::string_view() : text.substr(begin, end - begin);
}

// VTK's XML readers allocate what a file announces before reading the data: a damaged digit in
// the header's counts, or in the size header of a compressed array, made them take gigabytes
// (or throw bad_alloc) for a 3 kB file. Both are checked against the file here. Compressed data
// cannot expand by more than zlib's limit (about 1032 to 1).
void check_xml_sizes(const fs::path& path, std::string_view data) {
  constexpr std::uintmax_t expansion = 1032, slack = 1024;
  const auto damaged = [&](const std::string& what) {
    return InputError(path.string() + ": cannot read: " + what + ", more than the file can hold");
  };
  const std::size_t appended = data.find("<AppendedData");
  const std::string_view header = data.substr(0, appended);
  const std::uintmax_t limit = expansion * data.size() + slack;
  constexpr std::string_view count_attribute = " NumberOf";
  for (auto at = header.find(count_attribute); at != std::string_view::npos;
       at = header.find(count_attribute, at + 1)) {
    const auto quote = header.find('"', at);
    if (quote == std::string_view::npos) break;
    std::uintmax_t count = 0;
    const auto result = std::from_chars(header.data() + quote + 1, header.data() + header.size(), count);
    if (result.ec == std::errc::result_out_of_range || count > limit)
      throw damaged("the header announces " + std::string(header.substr(at + 1, quote - at)) + "...");
  }

  // Appended raw data starts after a '_'. Each array begins with its size header: its byte count
  // or, when compressed, [blocks, block size, last block size, compressed size of each block].
  const std::size_t underscore = appended == std::string_view::npos ? appended : data.find('_', appended);
  if (underscore == std::string_view::npos ||
      attribute(data.substr(appended, underscore - appended), "encoding") != "raw")
    return;
  const std::size_t start = underscore + 1;
  const std::size_t word_size = attribute(header, "header_type") == "UInt64" ? 8 : 4;
  const bool swap = (attribute(header, "byte_order") == "BigEndian") != host_is_big_endian();
  const bool compressed = !attribute(header, "compressor").empty();
  const auto word = [&](std::size_t at, std::uintmax_t& value) {
    if (at > data.size() || data.size() - at < word_size) return false;
    unsigned char bytes[8] = {};
    std::memcpy(bytes, data.data() + at, word_size);
    if (swap) std::reverse(bytes, bytes + word_size);
    value = 0;
    for (std::size_t i = word_size; i-- > 0;) value = value << 8 | bytes[i];
    return true;
  };
  constexpr std::string_view offset_attribute = " offset=\"";
  for (auto at = header.find(offset_attribute); at != std::string_view::npos;
       at = header.find(offset_attribute, at + 1)) {
    std::uintmax_t offset = 0;
    std::from_chars(header.data() + at + offset_attribute.size(), header.data() + header.size(), offset);
    const std::string where = "the size header of the array at offset " + std::to_string(offset);
    if (offset > data.size() - start) throw damaged("an array offset of " + std::to_string(offset));
    const std::size_t array = start + static_cast<std::size_t>(offset);
    std::uintmax_t first = 0;  // the byte count, or (compressed) the number of blocks
    if (!word(array, first)) throw damaged(where);
    const std::uintmax_t available = data.size() - array - word_size;
    if (!compressed) {
      if (first > available) throw damaged(where + " announces " + std::to_string(first) + " bytes");
      continue;
    }
    const std::uintmax_t blocks = first;
    std::uintmax_t block_size = 0, last_size = 0;
    if (blocks > available / word_size || !word(array + word_size, block_size) ||
        !word(array + 2 * word_size, last_size))
      throw damaged(where + " announces " + std::to_string(blocks) + " blocks");
    std::uintmax_t total = 0;
    for (std::uintmax_t b = 0; b < blocks; ++b) {
      std::uintmax_t size = 0;
      if (!word(array + (3 + b) * word_size, size) || size > available) throw damaged(where);
      total += size;
    }
    // The block size is nominal (32 kB from VTK's writers); the last block may be partial.
    const std::uintmax_t full_blocks = last_size == 0 ? blocks : blocks - (blocks > 0 ? 1 : 0);
    const bool sizes_fit = block_size <= limit && last_size <= block_size &&
                           (full_blocks == 0 || block_size <= limit / full_blocks) &&
                           full_blocks * block_size + last_size <= expansion * total + slack;
    if (total > available || !sizes_fit)
      throw damaged(where + " announces " + std::to_string(blocks) + " blocks of " +
                    std::to_string(block_size) + " bytes");
  }
}

PolygonSoup read_with_vtk(const fs::path& path, const std::string& ext, const detail::ReadOptions& options) {
  if (ext == ".stl") {
    check_binary_stl_length(path);
    vtkNew<vtkSTLReader> reader;
    reader->SetFileName(path.c_str());
    // VTK's merging uses a point locator, which is not safe with non-finite coordinates; exact
    // duplicates are merged below instead.
    reader->SetMerging(false);
    run_reader(*reader, path);
    PolygonSoup soup = soup_of(*reader->GetOutput(), path, options);
    merge_equal_points(soup);
    return soup;
  }
  check_xml_sizes(path, file_contents(path));
  if (ext == ".vtp") {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(path.c_str());
    run_reader(*reader, path);
    return soup_of(*reader->GetOutput(), path, options);
  }
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  run_reader(*reader, path);
  return soup_of(*reader->GetOutput(), path, options);
}

// The checks and the dispatch by extension shared by mesh and point-cloud reading.
template <std::size_t N>
PolygonSoup read_soup(const fs::path& path, const char* const (&extensions)[N], const char* kind,
                      const detail::ReadOptions& options, std::vector<Vec3>& xyz_normals) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw InputError(path.string() + ": file does not exist");
  if (fs::is_directory(status)) throw InputError(path.string() + ": is a directory, not a mesh file");
  const std::string ext = lowercase_extension(path);
  if (std::find(std::begin(extensions), std::end(extensions), ext) == std::end(extensions))
    throw InputError(path.string() + ": unknown " + kind + " format '" + ext +
                     "' (supported: " + joined(std::begin(extensions), std::end(extensions)) + ")");
  // VTK's readers report an unreadable file with a message that does not say why.
  if (!std::ifstream(path, std::ios::binary))
    throw InputError(path.string() + ": cannot open the file: " + std::strerror(errno));
  if (ext == ".stl" || ext == ".vtp" || ext == ".vtu") return read_with_vtk(path, ext, options);
  const std::string contents = file_contents(path);
  if (ext == ".off") return detail::parse_off(contents, path.string());
  if (ext == ".obj") return detail::parse_obj(contents, path.string(), options);
  if (ext == ".ply") return detail::parse_ply(contents, path.string(), options);
  if (ext == ".xyz" || ext == ".pwn") return detail::parse_xyz(contents, path.string(), xyz_normals);
  return detail::parse_legacy_vtk(contents, path.string(), options);
}

}  // namespace

std::string supported_input_extensions() {
  return joined(std::begin(input_extensions), std::end(input_extensions));
}

PolygonSoup read_polygon_soup(const fs::path& path) {
  std::vector<Vec3> unused;
  return read_soup(path, input_extensions, "mesh", {}, unused);
}

std::string supported_point_cloud_extensions() {
  return joined(std::begin(point_cloud_extensions), std::end(point_cloud_extensions));
}

PointCloud read_point_cloud(const fs::path& path) {
  PointCloud cloud;
  detail::ReadOptions options;
  options.skip_vertex_cells = true;
  options.normals = &cloud.normals;
  PolygonSoup soup = read_soup(path, point_cloud_extensions, "point-cloud", options, cloud.normals);
  cloud.points = std::move(soup.points);
  cloud.faces = std::move(soup.faces);
  if (cloud.points.empty()) throw InputError(path.string() + ": no points");
  for (std::size_t i = 0; i < cloud.points.size(); ++i)
    if (!is_finite(cloud.points[i]))
      throw InputError(path.string() + ": point " + std::to_string(i) + " is not finite");
  // Some tools write placeholder normals (all zero); a normal that gives no direction makes the
  // set unusable, since the users of normals need every point's.
  if (!cloud.normals.empty()) {
    std::size_t unusable = 0;
    for (const Vec3& n : cloud.normals) unusable += !is_finite(n) || norm(n) == 0;
    if (unusable > 0 || cloud.normals.size() != cloud.points.size()) {
      cloud.notes.push_back(path.string() + ": " + std::to_string(unusable) + " of " +
                            std::to_string(cloud.normals.size()) +
                            " normals are zero or not finite: the file's normals are ignored");
      cloud.normals.clear();
    }
  }
  return cloud;
}

TriangleMeshData read_mesh(const fs::path& path, const SoupOptions& options) {
  const PolygonSoup soup = read_polygon_soup(path);
  try {
    return prepare_triangle_mesh(soup, options);
  } catch (const InputError& e) {
    throw InputError(path.string() + ": " + e.what());
  }
}

}  // namespace rgbmesh
