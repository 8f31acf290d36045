// VTK XML output: every compression reads back bit-exactly through VTK's own readers and ours,
// progress is reported and its exceptions fail the write cleanly, and the tool's --compression.

#include <gtest/gtest.h>
#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPointSet.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_fixture.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace {

namespace fs = std::filesystem;
using namespace rgbmesh;
using rgbmesh::testing::Cli;
using rgbmesh::testing::RunResult;

// An octahedron refined around one corner: several levels, all three colours.
MeshSnapshot mixed_snapshot(const fs::path& file) {
  const std::vector<Vec3> points = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const std::vector<std::array<std::int32_t, 3>> triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                                              {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  RgbMesh mesh = RgbMesh::from_triangles(points, triangles);
  selective_refinement(mesh, UniformLevel(2));
  selective_refinement(mesh, BallLevel({1, 0, 0}, 0.5, 5));
  MeshSnapshot s = snapshot_for_file(mesh, file);
  // Extra arrays of values that do not survive any rounding.
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> value(-1e6, 1e6);
  NamedArray p{"pressure", 1, {}}, c{"flux", 3, {}};
  for (std::size_t i = 0; i < s.points.size(); ++i) p.values.push_back(value(random) / 3.0);
  for (std::size_t i = 0; i < 3 * s.triangles.size(); ++i) c.values.push_back(value(random) / 7.0);
  s.point_data.push_back(p);
  s.cell_data.push_back(c);
  return s;
}

vtkSmartPointer<vtkPointSet> read_with_vtk(const fs::path& file) {
  if (file.extension() == ".vtu") {
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(file.c_str());
    reader->Update();
    return vtkSmartPointer<vtkPointSet>(reader->GetOutput());
  }
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  return vtkSmartPointer<vtkPointSet>(reader->GetOutput());
}

std::string file_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The compressor attribute the file's header names ("" for none).
std::string compressor_of(const fs::path& file) {
  const std::string text = file_text(file).substr(0, 400);
  const auto at = text.find("compressor=\"");
  if (at == std::string::npos) return "";
  const auto begin = at + 12;
  return text.substr(begin, text.find('"', begin) - begin);
}

void expect_same_array(vtkDataArray* array, const std::vector<double>& expected, int components,
                       const std::string& what) {
  ASSERT_NE(array, nullptr) << what;
  ASSERT_EQ(array->GetNumberOfComponents(), components) << what;
  ASSERT_EQ(static_cast<std::size_t>(array->GetNumberOfValues()), expected.size()) << what;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const double got = array->GetComponent(static_cast<vtkIdType>(i) / components, static_cast<int>(i) % components);
    ASSERT_EQ(std::memcmp(&got, &expected[i], sizeof got), 0) << what << " value " << i;
  }
}

template <class T>
void expect_same_bytes(vtkDataArray* array, const std::vector<T>& expected, const std::string& what) {
  ASSERT_NE(array, nullptr) << what;
  ASSERT_EQ(static_cast<std::size_t>(array->GetNumberOfValues()), expected.size()) << what;
  for (std::size_t i = 0; i < expected.size(); ++i)
    ASSERT_EQ(array->GetComponent(static_cast<vtkIdType>(i), 0), static_cast<double>(expected[i])) << what << " " << i;
}

class WriteFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rgbmesh_write_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(WriteFiles, EveryCompressionReadsBackBitExactlyThroughVtk) {
  const struct {
    Compression compression;
    const char* compressor;
  } cases[] = {{Compression::lz4, "vtkLZ4DataCompressor"},
               {Compression::zlib, "vtkZLibDataCompressor"},
               {Compression::none, ""}};
  for (const char* ext : {".vtp", ".vtu"}) {
    for (const auto& c : cases) {
      const fs::path file = dir_ / (std::string("mesh-") + compression_name(c.compression) + ext);
      const MeshSnapshot s = mixed_snapshot(file);
      ASSERT_GT(s.triangles.size(), 100u);
      WriteOptions options;
      options.compression = c.compression;
      write_mesh(file, s, options);
      SCOPED_TRACE(file.filename().string());
      EXPECT_EQ(compressor_of(file), c.compressor);

      const vtkSmartPointer<vtkPointSet> data = read_with_vtk(file);
      ASSERT_EQ(static_cast<std::size_t>(data->GetNumberOfPoints()), s.points.size());
      ASSERT_EQ(static_cast<std::size_t>(data->GetNumberOfCells()), s.triangles.size());
      std::vector<double> coordinates;
      for (const Vec3& p : s.points) coordinates.insert(coordinates.end(), {p.x, p.y, p.z});
      expect_same_array(data->GetPoints()->GetData(), coordinates, 3, "points");
      vtkNew<vtkIdList> ids;
      for (std::size_t t = 0; t < s.triangles.size(); ++t) {
        data->GetCellPoints(static_cast<vtkIdType>(t), ids);
        ASSERT_EQ(ids->GetNumberOfIds(), 3);
        for (int k = 0; k < 3; ++k) ASSERT_EQ(ids->GetId(k), s.triangles[t][k]) << "triangle " << t;
      }
      expect_same_bytes(data->GetPointData()->GetArray("level"), s.vertex_level, "point level");
      expect_same_bytes(data->GetCellData()->GetArray("level"), s.triangle_level, "cell level");
      std::vector<int> colors;
      for (const Color k : s.triangle_color) colors.push_back(static_cast<int>(k));
      expect_same_bytes(data->GetCellData()->GetArray("color"), colors, "color");
      for (const NamedArray& a : s.point_data)
        expect_same_array(data->GetPointData()->GetArray(a.name.c_str()), a.same_as_points ? coordinates : a.values,
                          a.components, a.name);
      for (const NamedArray& a : s.cell_data)
        expect_same_array(data->GetCellData()->GetArray(a.name.c_str()), a.values, a.components, a.name);

      // rgbmesh's own (validated) reader takes every compression too.
      const PolygonSoup soup = read_polygon_soup(file);
      ASSERT_EQ(soup.faces.size(), s.triangles.size());
      ASSERT_EQ(soup.points.size(), s.points.size());
      for (std::size_t i = 0; i < s.points.size(); ++i) ASSERT_EQ(soup.points[i], s.points[i]) << i;
    }
  }
}

TEST_F(WriteFiles, TheDefaultIsLz4AndTheTwoArgumentCallStillWorks) {
  const fs::path file = dir_ / "mesh.vtp";
  write_mesh(file, mixed_snapshot(file));
  EXPECT_EQ(compressor_of(file), "vtkLZ4DataCompressor");
  EXPECT_EQ(WriteOptions().compression, Compression::lz4);
}

// snapshot_for_file is lean (no handles; the points are not copied into the array they equal)
// and holds the same values as the full snapshot, bit for bit, with control or limit points.
TEST_F(WriteFiles, TheSnapshotForAFileHoldsTheFullSnapshotsValuesWithoutCopies) {
  for (const bool limit_points : {false, true}) {
    const fs::path file = dir_ / "lean.vtp";
    RgbMesh mesh = RgbMesh::from_triangles({{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
                                           {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}});
    selective_refinement(mesh, UniformLevel(2));
    selective_refinement(mesh, BallLevel({1, 0, 0}, 0.5, 5));
    const MeshSnapshot lean = snapshot_for_file(mesh, file, limit_points);
    const MeshSnapshot full =
        mesh.snapshot(limit_points ? RgbMesh::Points::limit : RgbMesh::Points::control, true);
    EXPECT_TRUE(lean.vertex_handle.empty());
    EXPECT_TRUE(lean.triangle_handle.empty());
    ASSERT_EQ(lean.points.size(), full.points.size());
    EXPECT_EQ(0, std::memcmp(lean.points.data(), full.points.data(), lean.points.size() * sizeof(Vec3)));
    ASSERT_EQ(lean.point_data.size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) {
      const NamedArray& a = lean.point_data[k];
      EXPECT_EQ(a.name, full.point_data[k].name);
      EXPECT_EQ(a.same_as_points, (a.name == "limit") == limit_points) << a.name;
      std::vector<double> values = a.values;
      if (a.same_as_points)
        for (const Vec3& p : lean.points) values.insert(values.end(), {p.x, p.y, p.z});
      ASSERT_EQ(values.size(), full.point_data[k].values.size());
      EXPECT_EQ(0, std::memcmp(values.data(), full.point_data[k].values.data(), values.size() * sizeof(double)))
          << a.name;
    }
    write_mesh(file, lean);
    EXPECT_TRUE(read_rgb_mesh(file).restored);
  }
}

TEST_F(WriteFiles, CompressionNames) {
  for (const Compression c : {Compression::lz4, Compression::zlib, Compression::none}) {
    Compression parsed = c == Compression::lz4 ? Compression::none : Compression::lz4;
    EXPECT_TRUE(compression_from_name(compression_name(c), parsed));
    EXPECT_EQ(parsed, c);
  }
  Compression unchanged = Compression::zlib;
  for (const char* bad : {"", "LZ4", "gzip", "lz4 ", "zlib1"}) {
    EXPECT_FALSE(compression_from_name(bad, unchanged)) << bad;
    EXPECT_EQ(unchanged, Compression::zlib);
  }
}

TEST_F(WriteFiles, ProgressRisesFromZeroToOneForEveryFormat) {
  for (const char* ext : {".vtp", ".vtu", ".ply", ".stl", ".obj", ".off"}) {
    const fs::path file = dir_ / (std::string("mesh") + ext);
    std::vector<double> seen;
    WriteOptions options;
    options.progress = [&](double f) { seen.push_back(f); };
    write_mesh(file, mixed_snapshot(file), options);
    ASSERT_GE(seen.size(), 2u) << ext;
    EXPECT_EQ(seen.front(), 0.0) << ext;
    EXPECT_EQ(seen.back(), 1.0) << ext;
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1.0), 1) << ext;
    for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_LE(seen[i - 1], seen[i]) << ext;
  }
}

TEST_F(WriteFiles, AProgressCallbackThatThrowsFailsTheWriteAndLeavesNothing) {
  for (const char* ext : {".vtp", ".vtu", ".obj"}) {
    const fs::path file = dir_ / (std::string("mesh") + ext);
    const MeshSnapshot s = mixed_snapshot(file);
    write_mesh(file, s);  // an older file, which must survive
    const std::string before = file_text(file);
    int calls = 0;
    WriteOptions options;
    options.compression = Compression::zlib;  // so that the contents differ
    options.progress = [&](double) {
      if (++calls == 1) throw std::domain_error("stop here");
    };
    EXPECT_THROW(write_mesh(file, s, options), std::domain_error) << ext;
    EXPECT_EQ(file_text(file), before) << ext;
    std::size_t files = 0;
    for (const auto& entry : fs::directory_iterator(dir_)) files += entry.is_regular_file() ? 1 : 0;
    EXPECT_EQ(files, 1u) << ext << ": a temporary file was left";
    fs::remove(file);
  }
}

// Quadratic triangles: VTK reads six-node VTK_QUADRATIC_TRIANGLE cells with the nodes and the
// point and cell data bit for bit, in every compression; other extensions and bad indices are
// refused.
TEST_F(WriteFiles, QuadraticTrianglesReadBackAsVtkQuadraticTriangles) {
  // Two curved triangles sharing the edge 1-2, its middle node 6.
  const std::vector<Vec3> points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.1},  {0.5, -0.05, 0.02},
                                    {0.01, 0.5, 0}, {0.5, 0.5, 0.03}, {1.02, 0.5, 0}, {0.5, 1.03, 0.01}};
  const std::vector<std::array<std::int32_t, 6>> cells = {{0, 1, 2, 4, 6, 5}, {1, 3, 2, 7, 8, 6}};
  std::vector<double> values;
  for (std::size_t i = 0; i < points.size(); ++i) values.push_back(1.0 / 3.0 + static_cast<double>(i) * 1e-9);
  for (const Compression c : {Compression::lz4, Compression::zlib, Compression::none}) {
    const fs::path file = dir_ / (std::string("p2-") + compression_name(c) + ".vtu");
    WriteOptions options;
    options.compression = c;
    write_quadratic_triangles(file, points, cells, {{"solution", 1, values}}, {{"eta", 1, {0.25, 1e-300}}}, options);
    const vtkSmartPointer<vtkPointSet> data = read_with_vtk(file);
    ASSERT_EQ(data->GetNumberOfCells(), 2);
    for (vtkIdType k = 0; k < 2; ++k) {
      EXPECT_EQ(data->GetCellType(k), VTK_QUADRATIC_TRIANGLE);
      vtkNew<vtkIdList> ids;
      data->GetCellPoints(k, ids);
      ASSERT_EQ(ids->GetNumberOfIds(), 6);
      for (int j = 0; j < 6; ++j) EXPECT_EQ(ids->GetId(j), cells[static_cast<std::size_t>(k)][j]);
    }
    std::vector<double> coordinates;
    for (const Vec3& p : points) coordinates.insert(coordinates.end(), {p.x, p.y, p.z});
    expect_same_array(data->GetPoints()->GetData(), coordinates, 3, "points");
    expect_same_array(data->GetPointData()->GetArray("solution"), values, 1, "solution");
    expect_same_array(data->GetCellData()->GetArray("eta"), {0.25, 1e-300}, 1, "eta");
  }
  EXPECT_THROW(write_quadratic_triangles(dir_ / "p2.vtp", points, cells, {}, {}), InputError);
  EXPECT_THROW(write_quadratic_triangles(dir_ / "bad.vtu", points, {{0, 1, 2, 4, 6, 9}}, {}, {}), std::invalid_argument);
  EXPECT_THROW(write_quadratic_triangles(dir_ / "bad.vtu", points, cells, {{"short", 1, {1.0}}}, {}), std::invalid_argument);
}

TEST_F(WriteFiles, PointCloudsTakeTheCompressionToo) {
  const fs::path file = dir_ / "cloud.vtp";
  const std::vector<Vec3> points = {{0.1, 0.2, 0.3}, {1.0 / 3.0, 2e-300, -7.25}, {1e300, -0.0, 5}};
  WriteOptions options;
  options.compression = Compression::none;
  write_point_cloud(file, points, {{"distance", 1, {1.5, 2.0 / 3.0, -4}}}, options);
  EXPECT_EQ(compressor_of(file), "");
  const vtkSmartPointer<vtkPointSet> data = read_with_vtk(file);
  expect_same_array(data->GetPoints()->GetData(), {0.1, 0.2, 0.3, 1.0 / 3.0, 2e-300, -7.25, 1e300, -0.0, 5}, 3,
                    "points");
  expect_same_array(data->GetPointData()->GetArray("distance"), {1.5, 2.0 / 3.0, -4}, 1, "distance");
}

// The command-line tool.

class CompressionCli : public Cli {};

TEST_F(CompressionCli, EachValueOnEachWritingCommand) {
  const std::string in = write_octahedron("octa.off");
  EXPECT_EQ(run("refine " + in + " " + path("default.vtp") + " --uniform 2").code, 0);
  EXPECT_EQ(compressor_of(path("default.vtp")), "vtkLZ4DataCompressor");
  EXPECT_EQ(run("refine " + in + " " + path("z.vtu") + " --uniform 2 --compression zlib").code, 0);
  EXPECT_EQ(compressor_of(path("z.vtu")), "vtkZLibDataCompressor");
  EXPECT_EQ(run("--compression none convert " + in + " " + path("n.vtp")).code, 0);
  EXPECT_EQ(compressor_of(path("n.vtp")), "");
  EXPECT_EQ(run("convert " + in + " " + path("z.vtp") + " --compression zlib").code, 0);
  EXPECT_EQ(compressor_of(path("z.vtp")), "vtkZLibDataCompressor");
  // Other formats ignore it.
  EXPECT_EQ(run("convert " + in + " " + path("o.ply") + " --compression none").code, 0);
  const RunResult adapt =
      run("adapt --strategy uniform --max-dofs 200 --compression zlib --out " + path("a"));
  ASSERT_EQ(adapt.code, 0) << adapt.err;
  EXPECT_EQ(compressor_of(path("a/cycle_000.vtp")), "vtkZLibDataCompressor");
  // Written files read back, whatever their compression.
  for (const char* f : {"default.vtp", "z.vtu", "n.vtp", "z.vtp"}) {
    const RunResult info = run("info " + path(f));
    EXPECT_EQ(info.code, 0) << f << ": " << info.err;
    EXPECT_EQ(info.err, "") << f;
  }
}

TEST_F(CompressionCli, ABadValueIsOneLineAndExitCode2) {
  const std::string in = write_octahedron("octa.off");
  for (const std::string& args : {"refine " + in + " " + path("x.vtp") + " --compression gzip",
                                  "--compression LZ4 convert " + in + " " + path("x.vtp"),
                                  "convert " + in + " " + path("x.vtp") + " --compression="}) {
    const RunResult r = run(args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("--compression"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("x.vtp")));
  }
  const RunResult info = run("--compression zlib info " + in);
  EXPECT_EQ(info.code, 2);
  EXPECT_EQ(info.err, "rgbmesh: error: --compression: info writes no file\n");
}

TEST_F(CompressionCli, QuickWritesPrintNoProgress) {
  const std::string in = write_octahedron("octa.off");
  const RunResult r = run("refine " + in + " " + path("x.vtp") + " --uniform 4");
  EXPECT_EQ(r.code, 0);
  // (The only line: the note that the octahedron's limit surface rounds its corners.)
  EXPECT_EQ(r.err.find("writing"), std::string::npos) << r.err;
  EXPECT_LE(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

}  // namespace
