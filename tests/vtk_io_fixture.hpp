#pragma once
// What the mesh-file tests share (test_vtk_io.cpp: reading; test_vtk_io_write.cpp: writing):
// a grid snapshot with levels, colours and arrays, binary helpers, and the fixture with its
// scratch folder and error-message checks.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkPointSet.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataWriter.h>
#include <vtkSmartPointer.h>
#include <vtkTriangleFilter.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridWriter.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>
#include <vtkXMLWriter.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <sstream>

#include "rgbmesh/errors.hpp"
#include "rgbmesh/vtk_io.hpp"

#if defined(__SANITIZE_ADDRESS__)
// VTK 9.1 leaks a few objects when its XML reader or writer fails (a truncated file, a full
// disk); these tests provoke exactly that. Leaks in our own code are still reported.
extern "C" const char* __lsan_default_suppressions() { return "leak:libvtk\n"; }
#endif

namespace {

namespace fs = std::filesystem;
using rgbmesh::Color;
using rgbmesh::InputError;
using rgbmesh::MeshSnapshot;
using rgbmesh::PolygonSoup;
using rgbmesh::read_mesh;
using rgbmesh::read_polygon_soup;
using rgbmesh::TriangleMeshData;
using rgbmesh::Vec3;
using rgbmesh::write_mesh;
using Faces = std::vector<std::vector<std::int64_t>>;

// An n x n grid of quads split into triangles, over a bumpy surface, with coordinates that have
// no short decimal form, and levels, colours and extra arrays that differ between elements.
MeshSnapshot grid_snapshot(int n) {
  MeshSnapshot m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      m.points.push_back({i * 0.1, j / 3.0, 0.01 * std::sin(i + 2.0 * j)});
      m.vertex_level.push_back(static_cast<std::uint8_t>((i + j) % 7));
    }
  const auto id = [n](int i, int j) { return static_cast<std::int32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    m.triangle_level.push_back(static_cast<std::uint8_t>(t % 5));
    m.triangle_color.push_back(static_cast<Color>(t % 3));
  }
  rgbmesh::NamedArray u{"u", 1, {}}, grad{"grad", 3, {}};
  for (std::size_t v = 0; v < m.points.size(); ++v) u.values.push_back(0.5 * static_cast<double>(v) + 1e-9);
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) grad.values.push_back(static_cast<double>(t) - k / 7.0);
  m.point_data = {u};
  m.cell_data = {grad};
  return m;
}

// Little- or big-endian binary data for hand-made PLY files.
struct Bytes {
  bool big_endian = false;
  std::string data;
  template <class T>
  Bytes& put(T value) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    if (big_endian) std::reverse(raw, raw + sizeof(T));
    data.append(raw, sizeof(T));
    return *this;
  }
};

class VtkIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("rgbmesh_vtk_io_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    for (const auto& entry : fs::recursive_directory_iterator(dir_, ignored))
      fs::permissions(entry.path(), fs::perms::owner_all, fs::perm_options::add, ignored);
    fs::remove_all(dir_, ignored);
  }

  fs::path path(const std::string& name) const { return dir_ / name; }

  fs::path write_file(const std::string& name, const std::string& contents) const {
    std::ofstream(path(name), std::ios::binary) << contents;
    return path(name);
  }

  static std::string contents(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }

  // Names in the test directory, sorted.
  std::vector<std::string> entries(const fs::path& dir) const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

  // The message of the InputError that f throws; the test fails if f throws anything else or
  // nothing. Also checks that VTK printed nothing meanwhile.
  static std::string input_error(const std::function<void()>& f) {
    ::testing::internal::CaptureStderr();
    std::string message = "(no InputError)";
    try {
      f();
    } catch (const InputError& e) {
      message = e.what();
    } catch (const std::exception& e) {
      message = std::string("(other exception) ") + e.what();
    }
    const std::string printed = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(printed, "");
    return message;
  }

  static std::string read_error(const fs::path& file) {
    return input_error([&] { read_mesh(file); });
  }

  // The message must start with the file and contain every given part.
  static void expect_names(const std::string& message, const fs::path& file,
                           const std::vector<std::string>& parts) {
    EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
    for (const auto& part : parts)
      EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' in: " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }

  fs::path dir_;
};

}  // namespace
