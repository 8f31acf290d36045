// Writing mesh files, point clouds and ParaView collections, atomically. See vtk_io.hpp for
// the contract.

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPLYWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSTLWriter.h>
#include <vtkSmartPointer.h>
#include <vtkTypeInt32Array.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>
#include <vtkXMLWriter.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <exception>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <type_traits>

#include "atomic_file.hpp"
#include "io_common.hpp"
#include "rgb_state_io.hpp"
#include "rgbmesh/vtk_io.hpp"
#include "vtk_messages.hpp"
#include "xml_datasets.hpp"
#include "xml_stream.hpp"

namespace rgbmesh {
namespace {

namespace fs = std::filesystem;
using namespace detail;

// OFF and OBJ are written here: shortest round-trip numbers, and (unlike vtkOBJWriter, which
// ignores failed writes) every I/O error reported.
// Reports the lines written so far as a fraction of all, every 100,000 lines.
class LineProgress {
 public:
  LineProgress(const WriteOptions& options, std::size_t lines) : progress_(options.progress), lines_(lines) {}
  void line() {
    if (progress_ && ++done_ % 100000 == 0) progress_(static_cast<double>(done_) / static_cast<double>(lines_));
  }

 private:
  const std::function<void(double)>& progress_;
  std::size_t lines_, done_ = 0;
};

// Appends the decimal digits of an index (faster than std::to_string for millions of them).
void append_index(std::string& line, std::int64_t value) {
  char buf[24];
  const auto result = std::to_chars(buf, buf + sizeof buf, value);
  line.append(buf, result.ptr);
}

void write_off(const fs::path& file, const MeshSnapshot& mesh, const WriteOptions& options) {
  CheckedFile out(file);
  LineProgress progress(options, mesh.points.size() + mesh.triangles.size());
  out.append("OFF\n" + std::to_string(mesh.points.size()) + " " + std::to_string(mesh.triangles.size()) +
             " 0\n");
  std::string line;
  for (const Vec3& p : mesh.points) {
    line = shortest(p.x) + " " + shortest(p.y) + " " + shortest(p.z) + "\n";
    out.append(line);
    progress.line();
  }
  for (const auto& t : mesh.triangles) {
    line = "3";
    for (const std::int32_t v : t) {
      line += ' ';
      append_index(line, v);
    }
    line += '\n';
    out.append(line);
    progress.line();
  }
  out.close();
}

void write_obj(const fs::path& file, const MeshSnapshot& mesh, const WriteOptions& options) {
  CheckedFile out(file);
  LineProgress progress(options, mesh.points.size() + mesh.triangles.size());
  out.append("# written by rgbmesh\n");
  std::string line;
  for (const Vec3& p : mesh.points) {
    line = "v " + shortest(p.x) + " " + shortest(p.y) + " " + shortest(p.z) + "\n";
    out.append(line);
    progress.line();
  }
  for (const auto& t : mesh.triangles) {
    line = "f";
    for (const std::int32_t v : t) {  // OBJ counts vertices from 1
      line += ' ';
      append_index(line, std::int64_t{v} + 1);
    }
    line += '\n';
    out.append(line);
    progress.line();
  }
  // Sharp features as OpenSubdiv's tags (vertices counted from 0), which read_mesh reads back.
  if (mesh.sharp.method == CreaseMethod::chaikin) out.append("t creasemethod 0/0/1 chaikin\n");
  for (const SharpEdge& e : mesh.sharp.edges) {
    line = "t crease 2/1/0 ";
    append_index(line, e.a);
    line += ' ';
    append_index(line, e.b);
    line += ' ' + shortest(e.sharpness) + '\n';
    out.append(line);
  }
  for (const SharpVertex& v : mesh.sharp.vertices) {
    line = "t corner 1/1/0 ";
    append_index(line, v.v);
    line += ' ' + shortest(v.sharpness) + '\n';
    out.append(line);
  }
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
  if (!mesh.vertex_rule.empty() && mesh.vertex_rule.size() != n_points) fail("vertex_rule has the wrong size");
  for (const SharpEdge& e : mesh.sharp.edges)
    if (e.a < 0 || e.b < 0 || static_cast<std::size_t>(e.a) >= n_points || static_cast<std::size_t>(e.b) >= n_points)
      fail("a sharp edge names a point outside the snapshot");
  for (const SharpVertex& v : mesh.sharp.vertices)
    if (v.v < 0 || static_cast<std::size_t>(v.v) >= n_points) fail("a sharp vertex names a point outside the snapshot");
  if (!mesh.triangle_level.empty() && mesh.triangle_level.size() != n_cells)
    fail("triangle_level has the wrong size");
  if (!mesh.triangle_color.empty() && mesh.triangle_color.size() != n_cells)
    fail("triangle_color has the wrong size");
  const auto check_arrays = [&](const std::vector<NamedArray>& arrays, std::size_t n, bool points) {
    for (const NamedArray& a : arrays) {
      if (a.same_as_points) {
        if (!points || a.name.empty() || a.components != 3 || !a.values.empty())
          fail("array '" + a.name + "': only a named point-data array of 3 components and no values can be the points");
      } else if (a.name.empty() || a.components < 1 || a.values.size() != n * static_cast<std::size_t>(a.components)) {
        fail("array '" + a.name + "' needs a name and " + std::to_string(a.components) + " x " +
             std::to_string(n) + " values");
      }
    }
  };
  check_arrays(mesh.point_data, n_points, true);
  check_arrays(mesh.cell_data, n_cells, false);
}

// The snapshot's vectors are handed to VTK as they are, without copies (a mesh of millions of
// vertices would need twice its memory to be written otherwise). VTK is told not to free them
// (save = 1), and only reads them: the data sets built here live inside one write call, shorter
// than the snapshot they borrow from.
static_assert(sizeof(Vec3) == 3 * sizeof(double) && std::is_standard_layout_v<Vec3>,
              "Vec3 must be three packed doubles to be borrowed as a VTK array");
static_assert(sizeof(std::array<std::int32_t, 3>) == 3 * sizeof(std::int32_t),
              "a triangle must be three packed int32 to be borrowed as VTK connectivity");
static_assert(sizeof(Color) == 1, "Color must be one byte to be borrowed as a UInt8 array");

template <class Array, class Value>
vtkSmartPointer<Array> borrowed(const Value* values, std::size_t count, int components) {
  auto array = vtkSmartPointer<Array>::New();
  array->SetNumberOfComponents(components);
  // VTK's API takes a non-const pointer; its writers never write through it.
  if (count > 0) array->SetArray(const_cast<Value*>(values), static_cast<vtkIdType>(count), 1);
  return array;
}

vtkSmartPointer<vtkPoints> vtk_points(const MeshSnapshot& mesh) {
  // Double precision, so that VTP/VTU round trips are exact.
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetData(borrowed<vtkDoubleArray>(reinterpret_cast<const double*>(mesh.points.data()),
                                           3 * mesh.points.size(), 3));
  return points;
}

// Connectivity borrowed from the triangles; the offsets (0, 3, 6, ...) are the only cell data
// made, 4 bytes per triangle.
vtkSmartPointer<vtkCellArray> vtk_triangles(const MeshSnapshot& mesh) {
  const std::size_t n = mesh.triangles.size();
  const auto connectivity =
      borrowed<vtkTypeInt32Array>(mesh.triangles.empty() ? nullptr : mesh.triangles.front().data(), 3 * n, 1);
  vtkNew<vtkTypeInt32Array> offsets;
  offsets->SetNumberOfValues(static_cast<vtkIdType>(n + 1));
  std::int32_t* offset = offsets->GetPointer(0);
  for (std::size_t t = 0; t <= n; ++t) offset[t] = static_cast<std::int32_t>(3 * t);
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->SetData(offsets, connectivity);
  return cells;
}

vtkSmartPointer<vtkPolyData> vtk_poly_data(const MeshSnapshot& mesh) {
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(vtk_points(mesh));
  data->SetPolys(vtk_triangles(mesh));
  return data;
}

// Passes a VTK writer's progress events on to options.progress. An exception from the callback
// cannot cross VTK: it is kept, the writer asked to stop, and it is rethrown after Write.
struct ProgressRelay {
  const WriteOptions* options = nullptr;
  std::exception_ptr failure;
  double last = 0;

  static void on_progress(vtkObject* caller, unsigned long, void* client, void* data) {
    auto& relay = *static_cast<ProgressRelay*>(client);
    if (relay.failure || data == nullptr) return;
    const double fraction = std::clamp(*static_cast<double*>(data), relay.last, 1.0);
    if (fraction >= 1.0) return;  // the end is reported once, after the file is complete
    relay.last = fraction;
    try {
      relay.options->progress(fraction);
    } catch (...) {
      relay.failure = std::current_exception();
      if (auto* algorithm = vtkAlgorithm::SafeDownCast(caller)) algorithm->SetAbortExecute(1);
    }
  }
};

template <class Writer>
void run_writer_with_progress(Writer& writer, const WriteOptions& options) {
  if (!options.progress) {
    run_writer(writer);
    return;
  }
  ProgressRelay relay;
  relay.options = &options;
  vtkNew<vtkCallbackCommand> command;
  command->SetCallback(&ProgressRelay::on_progress);
  command->SetClientData(&relay);
  writer.AddObserver(vtkCommand::ProgressEvent, command);
  try {
    run_writer(writer);
  } catch (...) {
    if (relay.failure) std::rethrow_exception(relay.failure);
    throw;
  }
  if (relay.failure) std::rethrow_exception(relay.failure);
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

// PLY and STL through VTK's writers (VTK XML files through write_vtk_xml).
void write_with_vtk(const fs::path& file, const std::string& ext, const MeshSnapshot& mesh,
                    const WriteOptions& options) {
  const vtkSmartPointer<vtkPolyData> data = vtk_poly_data(mesh);
  if (ext == ".ply") {
    vtkNew<vtkPLYWriter> writer;
    writer->SetFileTypeToBinary();
    writer->SetInputData(data);
    writer->SetFileName(file.c_str());
    run_writer_with_progress(*writer, options);
    check_ply_length(file, mesh);
  } else {
    vtkNew<vtkSTLWriter> writer;
    writer->SetFileTypeToBinary();
    writer->SetInputData(data);
    writer->SetFileName(file.c_str());
    run_writer_with_progress(*writer, options);
  }
}

// replace_atomically, with options.progress called at 0 first and at 1 once the file is
// complete (before the rename). An exception from the callback fails the write like any other
// (the temporary is removed), and is then rethrown as it was thrown rather than as the
// OutputError that replace_atomically makes of failures.
void replace_reporting_progress(const fs::path& path, const WriteOptions& options,
                                const std::function<void(const fs::path&, const WriteOptions&)>& write) {
  struct Stopped : std::runtime_error {
    Stopped() : std::runtime_error("stopped by the progress callback") {}
  };
  std::exception_ptr failure;
  WriteOptions guarded = options;
  if (options.progress) {
    guarded.progress = [&](double fraction) {
      try {
        options.progress(fraction);
      } catch (...) {
        failure = std::current_exception();
        throw Stopped();
      }
    };
  }
  try {
    replace_atomically(path, [&](const fs::path& temp) {
      if (guarded.progress) guarded.progress(0.0);
      write(temp, guarded);
      if (guarded.progress) guarded.progress(1.0);
    });
  } catch (...) {
    if (failure) std::rethrow_exception(failure);
    throw;
  }
}

}  // namespace

MeshSnapshot snapshot_for_file(RgbMesh& mesh, const fs::path& path, bool limit_points) {
  const std::string ext = lowercase_extension(path);
  const bool xml = ext == ".vtp" || ext == ".vtu";
  if (limit_points || xml) mesh.compute_limits();
  if (!xml) {
    MeshSnapshot snapshot = mesh.snapshot(limit_points ? RgbMesh::Points::limit : RgbMesh::Points::control);
    std::vector<VertexHandle>().swap(snapshot.vertex_handle);  // writers do not use the handles
    std::vector<TriangleHandle>().swap(snapshot.triangle_handle);
    return snapshot;
  }
  // The same arrays as mesh.snapshot(..., true) gives, with less memory: the points are the
  // "control_point" (or "limit") array too, and the handles are dropped once the state and
  // the limits have been read through them.
  MeshSnapshot snapshot = mesh.snapshot(RgbMesh::Points::control);
  std::vector<TriangleHandle>().swap(snapshot.triangle_handle);
  snapshot.state = save_state(mesh, snapshot);  // what read_rgb_mesh restores
  const std::size_t n = snapshot.points.size();
  NamedArray control{"control_point", 3, {}}, limit{"limit", 3, {}};
  if (limit_points) {
    control.values.resize(3 * n);
    std::copy_n(reinterpret_cast<const double*>(snapshot.points.data()), 3 * n, control.values.data());
    for (std::size_t i = 0; i < n; ++i) snapshot.points[i] = mesh.limit_position(snapshot.vertex_handle[i]);
    limit.same_as_points = true;
  } else {
    limit.values.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 p = mesh.limit_position(snapshot.vertex_handle[i]);
      limit.values[3 * i] = p.x;
      limit.values[3 * i + 1] = p.y;
      limit.values[3 * i + 2] = p.z;
    }
    control.same_as_points = true;
  }
  std::vector<VertexHandle>().swap(snapshot.vertex_handle);
  snapshot.point_data.push_back(std::move(control));
  snapshot.point_data.push_back(std::move(limit));
  return snapshot;
}

void write_rgb_mesh(const fs::path& path, RgbMesh& mesh, const WriteOptions& options, bool limit_points) {
  const std::string ext = lowercase_extension(path);
  if (ext != ".vtp" && ext != ".vtu") {
    write_mesh(path, snapshot_for_file(mesh, path, limit_points), options);
    return;
  }
  mesh.compute_limits();
  const MeshDataSet data(mesh, ext == ".vtu", limit_points);
  replace_reporting_progress(path, options, [&](const fs::path& temp, const WriteOptions& guarded) {
    write_vtk_xml(temp, data.data(), guarded.compression, guarded.progress);
  });
}

std::string supported_output_extensions() {
  return joined(std::begin(output_extensions), std::end(output_extensions));
}

const char* compression_name(Compression compression) {
  switch (compression) {
    case Compression::lz4:
      return "lz4";
    case Compression::zlib:
      return "zlib";
    case Compression::none:
      return "none";
  }
  return "?";
}

bool compression_from_name(const std::string& name, Compression& compression) {
  for (const Compression c : {Compression::lz4, Compression::zlib, Compression::none}) {
    if (name == compression_name(c)) {
      compression = c;
      return true;
    }
  }
  return false;
}

void write_mesh(const fs::path& path, const MeshSnapshot& mesh) { write_mesh(path, mesh, WriteOptions{}); }

void write_mesh(const fs::path& path, const MeshSnapshot& mesh, const WriteOptions& options) {
  const std::string ext = lowercase_extension(path);
  if (std::find(std::begin(output_extensions), std::end(output_extensions), ext) ==
      std::end(output_extensions))
    throw InputError(path.string() + ": unknown output format '" + ext +
                     "' (supported: " + supported_output_extensions() + ")");
  check_snapshot(mesh, path);
  replace_reporting_progress(path, options, [&](const fs::path& temp, const WriteOptions& guarded) {
    if (ext == ".off")
      write_off(temp, mesh, guarded);
    else if (ext == ".obj")
      write_obj(temp, mesh, guarded);
    else if (ext == ".vtp" || ext == ".vtu")
      write_vtk_xml(temp, snapshot_data_set(mesh, ext == ".vtu"), guarded.compression, guarded.progress);
    else
      write_with_vtk(temp, ext, mesh, guarded);
  });
}

void write_point_cloud(const fs::path& path, const std::vector<Vec3>& points,
                       const std::vector<NamedArray>& point_data, const WriteOptions& options) {
  if (lowercase_extension(path) != ".vtp")
    throw InputError(path.string() + ": point clouds are written as .vtp, not '" + lowercase_extension(path) +
                     "'");
  MeshSnapshot cloud;  // for the shared checks and conversions; it has no triangles
  cloud.points = points;
  cloud.point_data = point_data;
  check_snapshot(cloud, path);
  replace_reporting_progress(path, options, [&](const fs::path& temp, const WriteOptions& guarded) {
    write_vtk_xml(temp, point_cloud_data_set(points, point_data), guarded.compression, guarded.progress);
  });
}

static_assert(sizeof(std::array<std::int32_t, 6>) == 6 * sizeof(std::int32_t),
              "a quadratic triangle must be six packed int32 to be written as connectivity");

void write_quadratic_triangles(const fs::path& path, const std::vector<Vec3>& points,
                               const std::vector<std::array<std::int32_t, 6>>& cells,
                               const std::vector<NamedArray>& point_data, const std::vector<NamedArray>& cell_data,
                               const WriteOptions& options) {
  if (lowercase_extension(path) != ".vtu")
    throw InputError(path.string() + ": quadratic triangles are written as .vtu, not '" + lowercase_extension(path) + "'");
  for (std::size_t c = 0; c < cells.size(); ++c)
    for (const std::int32_t v : cells[c])
      if (v < 0 || static_cast<std::size_t>(v) >= points.size())
        throw std::invalid_argument(path.string() + ": quadratic triangle " + std::to_string(c) + " references point " +
                                    std::to_string(v) + " of " + std::to_string(points.size()));
  const auto check = [&](const std::vector<NamedArray>& arrays, std::size_t n) {
    for (const NamedArray& a : arrays)
      if (a.name.empty() || a.components < 1 || a.same_as_points || a.values.size() != n * static_cast<std::size_t>(a.components))
        throw std::invalid_argument(path.string() + ": array '" + a.name + "' needs a name and " +
                                    std::to_string(a.components) + " x " + std::to_string(n) + " values");
  };
  check(point_data, points.size());
  check(cell_data, cells.size());
  XmlDataSet d;
  d.kind = XmlDataSet::Kind::grid_quadratic_triangles;
  d.points = points.size();
  d.cells = cells.size();
  d.coordinates = borrowed_array("Points", XmlType::float64, 3, d.points, points.data());
  d.connectivity = borrowed_array("connectivity", XmlType::int32, 1, 6 * d.cells, cells.empty() ? nullptr : cells.front().data());
  for (const NamedArray& a : point_data)
    d.point_data.push_back(borrowed_array(a.name, XmlType::float64, a.components, d.points, a.values.data()));
  for (const NamedArray& a : cell_data)
    d.cell_data.push_back(borrowed_array(a.name, XmlType::float64, a.components, d.cells, a.values.data()));
  replace_reporting_progress(path, options, [&](const fs::path& temp, const WriteOptions& guarded) {
    write_vtk_xml(temp, d, guarded.compression, guarded.progress);
  });
}

fs::path sharp_edges_path(const fs::path& mesh_file) {
  fs::path p = mesh_file;
  return p.replace_extension(".creases.vtp");
}

bool write_sharp_edges(const fs::path& path, const MeshSnapshot& mesh, const WriteOptions& options) {
  if (lowercase_extension(path) != ".vtp")
    throw InputError(path.string() + ": sharp edges are written as .vtp, not '" + lowercase_extension(path) + "'");
  if (mesh.sharp.edges.empty()) return false;
  // The points the sharp edges use, numbered as met; each edge a line cell.
  std::vector<vtkIdType> point_of(mesh.points.size(), -1);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkUnsignedCharArray> rule;
  rule->SetName("vertex_rule");
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkDoubleArray> sharpness;
  sharpness->SetName("sharpness");
  const auto point = [&](std::int32_t i) {
    if (i < 0 || static_cast<std::size_t>(i) >= mesh.points.size())
      throw std::invalid_argument(path.string() + ": a sharp edge names point " + std::to_string(i));
    vtkIdType& p = point_of[static_cast<std::size_t>(i)];
    if (p < 0) {
      const Vec3& x = mesh.points[static_cast<std::size_t>(i)];
      p = points->InsertNextPoint(x.x, x.y, x.z);
      rule->InsertNextValue(mesh.vertex_rule.empty() ? 0 : mesh.vertex_rule[static_cast<std::size_t>(i)]);
    }
    return p;
  };
  for (const SharpEdge& e : mesh.sharp.edges) {
    const vtkIdType ends[2] = {point(e.a), point(e.b)};
    lines->InsertNextCell(2, ends);
    sharpness->InsertNextValue(e.sharpness);
  }
  vtkNew<vtkPolyData> data;
  data->SetPoints(points);
  data->SetLines(lines);
  data->GetCellData()->AddArray(sharpness);
  data->GetPointData()->AddArray(rule);
  replace_reporting_progress(path, options, [&](const fs::path& temp, const WriteOptions& guarded) {
    vtkNew<vtkXMLPolyDataWriter> writer;
    writer->SetInputData(data);
    writer->SetFileName(temp.c_str());
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetCompressorType(guarded.compression == Compression::zlib ? vtkXMLWriter::ZLIB
                              : guarded.compression == Compression::lz4 ? vtkXMLWriter::LZ4
                                                                        : vtkXMLWriter::NONE);
    run_writer_with_progress(*writer, guarded);
  });
  return true;
}

bool write_sharp_edges(const fs::path& path, const RgbMesh& mesh, bool limit_points, const WriteOptions& options) {
  if (!mesh.has_sharp_features()) return false;
  // A snapshot of the sharp edges' ends only (a whole one would hold the whole mesh again).
  MeshSnapshot ends;
  std::vector<std::int32_t> point_of(static_cast<std::size_t>(mesh.vertex_slots()), -1);
  for (const EdgeHandle e : mesh.edges()) {
    if (mesh.is_boundary(e) || mesh.sharpness(e) <= 0.0f) continue;
    for (const VertexHandle v : mesh.edge_vertices(e)) {
      std::int32_t& p = point_of[static_cast<std::size_t>(v.idx)];
      if (p >= 0) continue;
      p = static_cast<std::int32_t>(ends.points.size());
      ends.points.push_back(limit_points ? mesh.limit_position(v) : mesh.control_point(v));
      ends.vertex_handle.push_back(v);
    }
  }
  mesh.add_sharp_features(ends);
  return write_sharp_edges(path, ends, options);
}

void write_text_atomically(const fs::path& path, const std::string& contents) {
  replace_atomically(path, [&](const fs::path& temp) { write_bytes(temp, contents); });
}

void write_pvd(const fs::path& pvd,
               const std::vector<std::pair<double, std::string>>& time_and_relative_file) {
  std::vector<PvdEntry> entries;
  entries.reserve(time_and_relative_file.size());
  for (const auto& [time, file] : time_and_relative_file) entries.push_back({time, 0, file});
  write_pvd(pvd, entries);
}

void write_pvd(const fs::path& pvd, const std::vector<PvdEntry>& entries) {
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  for (const PvdEntry& e : entries) {
    if (!std::isfinite(e.time))
      throw std::invalid_argument(pvd.string() + ": time " + shortest(e.time) + " is not finite");
    xml += "    <DataSet timestep=\"" + shortest(e.time) + "\" group=\"\" part=\"" + std::to_string(e.part) +
           "\" file=\"" + xml_attribute(e.file) + "\"/>\n";
  }
  xml +=
      "  </Collection>\n"
      "</VTKFile>\n";
  write_text_atomically(pvd, xml);
}

}  // namespace rgbmesh
