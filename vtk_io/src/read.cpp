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
#include <vtkSmartPointer.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string_view>
#include <unordered_map>

#include "input_file.hpp"
#include "io_common.hpp"
#include "parsers.hpp"
#include "rgb_state_io.hpp"
#include "rgbmesh/vtk_io.hpp"
#include "vtk_messages.hpp"
#include "xml_check.hpp"

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

// VTK's XML readers, behind check_vtk_xml: they crash or allocate without limit on files that it
// refuses.
PolygonSoup read_vtk_xml(const fs::path& path, std::string_view bytes, const std::string& ext,
                         const detail::ReadOptions& options) {
  if (ext == ".vtp") {
    check_vtk_xml(bytes, path.string(), "PolyData");
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(path.c_str());
    run_reader(*reader, path);
    if (options.saved_state != nullptr) read_rgb_state(*reader->GetOutput(), path, *options.saved_state);
    return soup_of(*reader->GetOutput(), path, options);
  }
  check_vtk_xml(bytes, path.string(), "UnstructuredGrid");
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  run_reader(*reader, path);
  if (options.saved_state != nullptr) read_rgb_state(*reader->GetOutput(), path, *options.saved_state);
  return soup_of(*reader->GetOutput(), path, options);
}

// The checks and the dispatch by extension shared by mesh and point-cloud reading.
template <std::size_t N>
PolygonSoup read_soup(const fs::path& path, const char* const (&extensions)[N], const char* kind,
                      const detail::ReadOptions& options, std::vector<Vec3>& xyz_normals) {
  const std::string ext = lowercase_extension(path);
  if (std::find(std::begin(extensions), std::end(extensions), ext) == std::end(extensions))
    throw InputError(path.string() + ": unknown " + kind + " format '" + ext +
                     "' (supported: " + joined(std::begin(extensions), std::end(extensions)) + ")");
  // Refuses anything but a regular file, and maps it: nothing is read before it is needed.
  const InputFile file(path);
  const std::string name = path.string();
  if (file.size() == 0)
    throw InputError(name + (std::string_view(kind) == "point-cloud" ? ": no points (the file is empty)"
                                                                     : ": the file is empty"));
  if (ext == ".stl") {
    PolygonSoup soup = detail::parse_stl(file.bytes(), name);
    merge_equal_points(soup);
    soup.numbered_vertices = false;  // the numbers are the merge's, not the file's
    return soup;
  }
  if (ext == ".vtp" || ext == ".vtu") return read_vtk_xml(path, file.bytes(), ext, options);
  if (ext == ".3mf") return detail::parse_3mf(file.bytes(), name);
  const std::string_view text = without_utf8_bom(file.bytes());
  if (ext == ".off") return detail::parse_off(text, name);
  if (ext == ".obj") return detail::parse_obj(text, name, options);
  if (ext == ".ply") return detail::parse_ply(text, name, options);
  if (ext == ".xyz" || ext == ".pwn") return detail::parse_xyz(text, name, xyz_normals);
  return detail::parse_legacy_vtk(text, name, options);
}

}  // namespace

std::string supported_input_extensions() {
  return joined(std::begin(input_extensions), std::end(input_extensions));
}

PolygonSoup read_polygon_soup(const fs::path& path) {
  std::vector<Vec3> unused;
  return read_soup(path, input_extensions, "mesh", {}, unused);
}

PolygonSoup detail::read_mesh_soup(const fs::path& path, const detail::ReadOptions& options) {
  std::vector<Vec3> unused;
  return read_soup(path, input_extensions, "mesh", options, unused);
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
  cloud.numbered_vertices = soup.numbered_vertices;
  for (const std::string& note : soup.notes) cloud.notes.push_back(path.string() + ": " + note);
  if (cloud.points.empty()) throw InputError(path.string() + ": no points");
  for (std::size_t i = 0; i < cloud.points.size(); ++i)
    if (!is_finite(cloud.points[i]))
      throw InputError(path.string() + ": point " + std::to_string(i) + " is not finite");
  // Some tools write placeholder normals (all zero), or a few zero or broken ones among good
  // ones. They are kept, one per point, for the user of normals to skip the unusable ones (the
  // reconstruction leaves those points out of its equation, and says so); only a set with no
  // usable normal at all is dropped.
  if (!cloud.normals.empty()) {
    std::size_t unusable = 0;
    for (const Vec3& n : cloud.normals) unusable += !is_finite(n) || norm(n) == 0;
    if (cloud.normals.size() != cloud.points.size() || unusable == cloud.normals.size()) {
      cloud.notes.push_back(path.string() + ": " + (unusable == cloud.normals.size() ? "all " : "") +
                            std::to_string(unusable) + " of " + std::to_string(cloud.normals.size()) +
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
    detail::rethrow_for_file(path, e);
  }
}

}  // namespace rgbmesh
