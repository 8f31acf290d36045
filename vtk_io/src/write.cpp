// Writing mesh files, point clouds and ParaView collections, atomically. See vtk_io.hpp for
// the contract.

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPLYWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSTLWriter.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>
#include <vtkXMLWriter.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "atomic_file.hpp"
#include "io_common.hpp"
#include "rgb_state_io.hpp"
#include "rgbmesh/vtk_io.hpp"
#include "vtk_messages.hpp"

namespace rgbmesh {
namespace {

namespace fs = std::filesystem;
using namespace detail;

// OFF and OBJ are written here: shortest round-trip numbers, and (unlike vtkOBJWriter, which
// ignores failed writes) every I/O error reported.
void write_off(const fs::path& file, const MeshSnapshot& mesh) {
  CheckedFile out(file);
  out.append("OFF\n" + std::to_string(mesh.points.size()) + " " + std::to_string(mesh.triangles.size()) +
             " 0\n");
  for (const Vec3& p : mesh.points)
    out.append(shortest(p.x) + " " + shortest(p.y) + " " + shortest(p.z) + "\n");
  for (const auto& t : mesh.triangles)
    out.append("3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n");
  out.close();
}

void write_obj(const fs::path& file, const MeshSnapshot& mesh) {
  CheckedFile out(file);
  out.append("# written by rgbmesh\n");
  for (const Vec3& p : mesh.points)
    out.append("v " + shortest(p.x) + " " + shortest(p.y) + " " + shortest(p.z) + "\n");
  for (const auto& t : mesh.triangles)  // OBJ counts vertices from 1
    out.append("f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " +
               std::to_string(t[2] + 1) + "\n");
  out.close();
}

// Programming errors in the snapshot are caught before anything is written.
void check_snapshot(const MeshSnapshot& mesh, const fs::path& path) {
  const auto fail = [&](const std::string& what) {
    throw std::invalid_argument(path.string() + ": inconsistent mesh snapshot: " + what);
  };
  const std::size_t n_points = mesh.points.size(), n_cells = mesh.triangles.size();
  for (std::size_t t = 0; t < n_cells; ++t)
    for (const std::int32_t v : mesh.triangles[t])
      if (v < 0 || static_cast<std::size_t>(v) >= n_points)
        fail("triangle " + std::to_string(t) + " references point " + std::to_string(v) + " of " +
             std::to_string(n_points));
  if (!mesh.vertex_level.empty() && mesh.vertex_level.size() != n_points)
    fail("vertex_level has the wrong size");
  if (!mesh.triangle_level.empty() && mesh.triangle_level.size() != n_cells)
    fail("triangle_level has the wrong size");
  if (!mesh.triangle_color.empty() && mesh.triangle_color.size() != n_cells)
    fail("triangle_color has the wrong size");
  const auto check_arrays = [&](const std::vector<NamedArray>& arrays, std::size_t n) {
    for (const NamedArray& a : arrays)
      if (a.name.empty() || a.components < 1 || a.values.size() != n * static_cast<std::size_t>(a.components))
        fail("array '" + a.name + "' needs a name and " + std::to_string(a.components) + " x " +
             std::to_string(n) + " values");
  };
  check_arrays(mesh.point_data, n_points);
  check_arrays(mesh.cell_data, n_cells);
}

vtkSmartPointer<vtkPoints> vtk_points(const MeshSnapshot& mesh) {
  // Double precision, so that VTP/VTU round trips are exact.
  vtkNew<vtkDoubleArray> coordinates;
  coordinates->SetNumberOfComponents(3);
  coordinates->SetNumberOfTuples(static_cast<vtkIdType>(mesh.points.size()));
  double* out = coordinates->GetPointer(0);
  for (const Vec3& p : mesh.points) {
    *out++ = p.x;
    *out++ = p.y;
    *out++ = p.z;
  }
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetData(coordinates);
  return points;
}

vtkSmartPointer<vtkCellArray> vtk_triangles(const MeshSnapshot& mesh) {
  const auto n = static_cast<vtkIdType>(mesh.triangles.size());
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(n + 1);
  connectivity->SetNumberOfValues(3 * n);
  for (vtkIdType t = 0; t <= n; ++t) offsets->SetValue(t, 3 * t);
  for (vtkIdType t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) connectivity->SetValue(3 * t + k, mesh.triangles[t][k]);
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->SetData(offsets, connectivity);
  return cells;
}

template <class T>
vtkSmartPointer<vtkUnsignedCharArray> uint8_array(const char* name, const std::vector<T>& values) {
  auto array = vtkSmartPointer<vtkUnsignedCharArray>::New();
  array->SetName(name);
  array->SetNumberOfValues(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
    array->SetValue(static_cast<vtkIdType>(i), static_cast<unsigned char>(values[i]));
  return array;
}

vtkSmartPointer<vtkDoubleArray> float64_array(const NamedArray& named) {
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(named.name.c_str());
  array->SetNumberOfComponents(named.components);
  array->SetNumberOfTuples(static_cast<vtkIdType>(named.values.size() / named.components));
  std::copy(named.values.begin(), named.values.end(), array->GetPointer(0));
  return array;
}

void add_arrays(vtkDataSet& data, const MeshSnapshot& mesh) {
  if (!mesh.vertex_level.empty()) data.GetPointData()->AddArray(uint8_array("level", mesh.vertex_level));
  if (!mesh.triangle_level.empty()) data.GetCellData()->AddArray(uint8_array("level", mesh.triangle_level));
  if (!mesh.triangle_color.empty()) data.GetCellData()->AddArray(uint8_array("color", mesh.triangle_color));
  for (const NamedArray& a : mesh.point_data) data.GetPointData()->AddArray(float64_array(a));
  for (const NamedArray& a : mesh.cell_data) data.GetCellData()->AddArray(float64_array(a));
  add_rgb_state(data, mesh);  // rgb_state_io.cpp: the RGB state's point and field data
}

vtkSmartPointer<vtkPolyData> vtk_poly_data(const MeshSnapshot& mesh) {
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(vtk_points(mesh));
  data->SetPolys(vtk_triangles(mesh));
  return data;
}

// Appended raw binary, zlib-compressed: the smallest files ParaView reads fastest.
void configure_xml(vtkXMLWriter& writer) {
  writer.SetDataModeToAppended();
  writer.EncodeAppendedDataOff();
  writer.SetCompressorTypeToZLib();
}

// vtkPLYWriter ignores failed writes (a full disk leaves a short file and no error), so the
// file is checked: after its header, a binary PLY of ours holds exactly 12 bytes per point
// (float x, y, z) and 13 per triangle (uchar 3, int a, b, c).
void check_ply_length(const fs::path& file, const MeshSnapshot& mesh) {
  std::ifstream in(file, std::ios::binary);
  std::string header;
  for (std::string line; std::getline(in, line) && line != "end_header";) header += line + "\n";
  const std::uintmax_t expected = header.size() + std::string("end_header\n").size() +
                                  12 * mesh.points.size() + 13 * mesh.triangles.size();
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (!in || ec || size != expected)
    throw std::runtime_error("the PLY writer left an incomplete file (" + std::to_string(ec ? 0 : size) +
                             " of " + std::to_string(expected) + " bytes)");
}

void write_with_vtk(const fs::path& file, const std::string& ext, const MeshSnapshot& mesh) {
  if (ext == ".vtu") {
    vtkNew<vtkUnstructuredGrid> grid;
    grid->SetPoints(vtk_points(mesh));
    grid->SetCells(VTK_TRIANGLE, vtk_triangles(mesh));
    add_arrays(*grid, mesh);
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    configure_xml(*writer);
    writer->SetInputData(grid);
    writer->SetFileName(file.c_str());
    run_writer(*writer);
    return;
  }
  const vtkSmartPointer<vtkPolyData> data = vtk_poly_data(mesh);
  if (ext == ".vtp") {
    add_arrays(*data, mesh);
    vtkNew<vtkXMLPolyDataWriter> writer;
    configure_xml(*writer);
    writer->SetInputData(data);
    writer->SetFileName(file.c_str());
    run_writer(*writer);
  } else if (ext == ".ply") {
    vtkNew<vtkPLYWriter> writer;
    writer->SetFileTypeToBinary();
    writer->SetInputData(data);
    writer->SetFileName(file.c_str());
    run_writer(*writer);
    check_ply_length(file, mesh);
  } else {
    vtkNew<vtkSTLWriter> writer;
    writer->SetFileTypeToBinary();
    writer->SetInputData(data);
    writer->SetFileName(file.c_str());
    run_writer(*writer);
  }
}

std::string xml_attribute(const std::string& value) {
  std::string escaped;
  for (const char c : value) {
    switch (c) {
      case '&':
        escaped += "&amp;";
        break;
      case '<':
        escaped += "&lt;";
        break;
      case '>':
        escaped += "&gt;";
        break;
      case '"':
        escaped += "&quot;";
        break;
      case '\'':
        escaped += "&apos;";
        break;
      default:
        escaped += c;
    }
  }
  return escaped;
}

}  // namespace

MeshSnapshot snapshot_for_file(RgbMesh& mesh, const fs::path& path, bool limit_points) {
  const std::string ext = lowercase_extension(path);
  const bool xml = ext == ".vtp" || ext == ".vtu";
  if (limit_points || xml) mesh.compute_limits();
  MeshSnapshot snapshot = mesh.snapshot(limit_points ? RgbMesh::Points::limit : RgbMesh::Points::control, xml);
  if (xml) snapshot.state = save_state(mesh, snapshot);  // what read_rgb_mesh restores
  return snapshot;
}

std::string supported_output_extensions() {
  return joined(std::begin(output_extensions), std::end(output_extensions));
}

void write_mesh(const fs::path& path, const MeshSnapshot& mesh) {
  const std::string ext = lowercase_extension(path);
  if (std::find(std::begin(output_extensions), std::end(output_extensions), ext) ==
      std::end(output_extensions))
    throw InputError(path.string() + ": unknown output format '" + ext +
                     "' (supported: " + supported_output_extensions() + ")");
  check_snapshot(mesh, path);
  replace_atomically(path, [&](const fs::path& temp) {
    if (ext == ".off")
      write_off(temp, mesh);
    else if (ext == ".obj")
      write_obj(temp, mesh);
    else
      write_with_vtk(temp, ext, mesh);
  });
}

void write_point_cloud(const fs::path& path, const std::vector<Vec3>& points,
                       const std::vector<NamedArray>& point_data) {
  if (lowercase_extension(path) != ".vtp")
    throw InputError(path.string() + ": point clouds are written as .vtp, not '" + lowercase_extension(path) +
                     "'");
  MeshSnapshot cloud;  // for the shared checks and conversions; it has no triangles
  cloud.points = points;
  cloud.point_data = point_data;
  check_snapshot(cloud, path);
  const auto n = static_cast<vtkIdType>(points.size());
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(n + 1);
  connectivity->SetNumberOfValues(n);
  for (vtkIdType i = 0; i <= n; ++i) offsets->SetValue(i, i);
  for (vtkIdType i = 0; i < n; ++i) connectivity->SetValue(i, i);
  vtkNew<vtkCellArray> vertices;
  vertices->SetData(offsets, connectivity);
  vtkNew<vtkPolyData> data;
  data->SetPoints(vtk_points(cloud));
  data->SetVerts(vertices);
  add_arrays(*data, cloud);
  replace_atomically(path, [&](const fs::path& temp) {
    vtkNew<vtkXMLPolyDataWriter> writer;
    configure_xml(*writer);
    writer->SetInputData(data);
    writer->SetFileName(temp.c_str());
    run_writer(*writer);
  });
}

void write_text_atomically(const fs::path& path, const std::string& contents) {
  replace_atomically(path, [&](const fs::path& temp) { write_bytes(temp, contents); });
}

void write_pvd(const fs::path& pvd,
               const std::vector<std::pair<double, std::string>>& time_and_relative_file) {
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  for (const auto& [time, file] : time_and_relative_file) {
    if (!std::isfinite(time))
      throw std::invalid_argument(pvd.string() + ": time " + shortest(time) + " is not finite");
    xml += "    <DataSet timestep=\"" + shortest(time) + "\" group=\"\" part=\"0\" file=\"" +
           xml_attribute(file) + "\"/>\n";
  }
  xml +=
      "  </Collection>\n"
      "</VTKFile>\n";
  write_text_atomically(pvd, xml);
}

}  // namespace rgbmesh
