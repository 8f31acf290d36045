// Point clouds for the fit: read_point_cloud reads every format through the validated readers
// (vertex cells and files without faces accepted, normals kept where the file has them) and
// rejects malformed files with one InputError naming the file; write_point_cloud writes vertex
// cells that VTK's own reader gives back.

#include <gtest/gtest.h>
#include <unistd.h>
#include <vtkCellArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "public_data.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh {
namespace {

namespace fs = std::filesystem;

class PointCloudFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("rgbmesh_fit_io_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& contents) const {
    std::ofstream(dir_ / name, std::ios::binary) << contents;
    return (dir_ / name).string();
  }

  // The message of the InputError that reading `file` throws ("" if none is thrown).
  static std::string error_reading(const std::string& file) {
    try {
      read_point_cloud(file);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
};

TEST_F(PointCloudFiles, XyzWithAndWithoutNormals) {
  const PointCloud plain =
      read_point_cloud(write("a.xyz", "# a comment\n0 0 0\n1 0 0\n\n0 1 0.5  # trailing\n"));
  ASSERT_EQ(plain.points.size(), 3u);
  EXPECT_EQ(plain.points[2], Vec3(0, 1, 0.5));
  EXPECT_TRUE(plain.normals.empty());
  EXPECT_TRUE(plain.faces.empty());
  const PointCloud oriented = read_point_cloud(write("b.pwn", "0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 2\n"));
  ASSERT_EQ(oriented.normals.size(), 3u);
  EXPECT_EQ(oriented.normals[2], Vec3(0, 0, 2));
}

TEST_F(PointCloudFiles, ZeroNormalsAreDroppedWithANote) {
  // CGAL's blobby.xyz has six columns whose last three are all zero.
  const PointCloud cloud = read_point_cloud(write("z.xyz", "0 0 0 0 0 0\n1 0 0 0 0 0\n0 1 0 0 0 0\n"));
  EXPECT_EQ(cloud.points.size(), 3u);
  EXPECT_TRUE(cloud.normals.empty());
  ASSERT_EQ(cloud.notes.size(), 1u);
  EXPECT_NE(cloud.notes[0].find("all 3 of 3 normals are zero"), std::string::npos) << cloud.notes[0];
}

TEST_F(PointCloudFiles, AFewZeroNormalsAmongGoodOnesAreKeptForTheirUserToSkip) {
  // Two zero normals among 4,387 once made the whole set unusable (the fit's RMS doubled).
  const PointCloud cloud =
      read_point_cloud(write("some.xyz", "0 0 0 0 0 1\n1 0 0 0 0 0\n0 1 0 0 0 1\n1 1 0 0 0 -2\n"));
  ASSERT_EQ(cloud.normals.size(), 4u);
  EXPECT_EQ(cloud.normals[0], Vec3(0, 0, 1));
  EXPECT_EQ(cloud.normals[1], Vec3(0, 0, 0));
  EXPECT_TRUE(cloud.notes.empty());
}

TEST_F(PointCloudFiles, MalformedXyzNamesTheFileAndLine) {
  const std::string bad = write("bad.xyz", "0 0 0\n1 x 0\n");
  EXPECT_NE(error_reading(bad).find("bad.xyz:2: 'x' is not a number"), std::string::npos)
      << error_reading(bad);
  const std::string columns = write("columns.xyz", "0 0 0 1 0 0\n1 0 0\n");
  EXPECT_NE(
      error_reading(columns).find("columns.xyz:2: expected 6 numbers like the first point (line 1), found 3"),
      std::string::npos)
      << error_reading(columns);
  const std::string four = write("four.xyz", "\n0 0 0 1\n");
  EXPECT_NE(error_reading(four).find("four.xyz:2: expected 3 numbers (x y z) or 6"), std::string::npos);
  const std::string infinite = write("inf.xyz", "0 0 0\n1 inf 0\n");
  EXPECT_NE(error_reading(infinite).find("inf.xyz:2: 'inf' is not a finite number"), std::string::npos);
  EXPECT_NE(error_reading(write("empty.xyz", "")).find("empty.xyz: no points"), std::string::npos);
  EXPECT_NE(error_reading(write("comments.xyz", "# nothing\n\n")).find("comments.xyz: no points"),
            std::string::npos);
  EXPECT_NE(
      error_reading(write("binary.xyz", std::string("0 0 0\n\0\1\2", 9))).find("binary.xyz: not a text file"),
      std::string::npos);
  EXPECT_NE(error_reading((dir_ / "missing.xyz").string()).find("missing.xyz: file does not exist"),
            std::string::npos);
  EXPECT_NE(error_reading(write("cloud.txt", "0 0 0\n")).find("cloud.txt: unknown point-cloud format '.txt'"),
            std::string::npos);
}

TEST_F(PointCloudFiles, VtpWithVertexCellsAndItsNormals) {
  const std::string file = write(
      "cloud.vtp",
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "<PolyData><Piece NumberOfPoints=\"2\" NumberOfVerts=\"2\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
      "NumberOfPolys=\"0\">\n"
      "<PointData Normals=\"n\"><DataArray type=\"Float64\" Name=\"n\" NumberOfComponents=\"3\" "
      "format=\"ascii\">"
      "0 0 1 0 1 0</DataArray></PointData>\n"
      "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 2 "
      "3</DataArray></Points>\n"
      "<Verts><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1</DataArray>"
      "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">1 2</DataArray></Verts>\n"
      "</Piece></PolyData></VTKFile>\n");
  const PointCloud cloud = read_point_cloud(file);
  ASSERT_EQ(cloud.points.size(), 2u);
  EXPECT_EQ(cloud.points[1], Vec3(1, 2, 3));
  ASSERT_EQ(cloud.normals.size(), 2u);
  EXPECT_EQ(cloud.normals[1], Vec3(0, 1, 0));
  EXPECT_TRUE(cloud.faces.empty());
  // Mesh reading still refuses the vertex cells.
  EXPECT_THROW(read_polygon_soup(file), InputError);
}

TEST_F(PointCloudFiles, GarbledVtpIsOneInputErrorNamingTheFile) {
  const std::vector<std::string> garbage = {
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\">\n<PolyData><Piece "
      "NumberOfPoints=\"9",
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "<PolyData><Piece NumberOfPoints=\"99999999999999\" NumberOfVerts=\"0\" NumberOfLines=\"0\" "
      "NumberOfStrips=\"0\" "
      "NumberOfPolys=\"0\"><Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">0 0 "
      "0"
      "</DataArray></Points></Piece></PolyData></VTKFile>\n",
      std::string("\x00\x01garbage\xff", 11), ""};
  for (std::size_t i = 0; i < garbage.size(); ++i) {
    const std::string name = "garbage" + std::to_string(i) + ".vtp";
    const std::string message = error_reading(write(name, garbage[i]));
    EXPECT_EQ(message.rfind((dir_ / name).string() + ": ", 0), 0u) << i << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << i << ": " << message;
  }
}

TEST_F(PointCloudFiles, EveryFormatWithoutFaces) {
  // PLY with normals (CGAL's hippo1.ply is binary; this one is ASCII), OFF and OBJ without faces,
  // OBJ 'p' elements and legacy VTK vertices.
  const PointCloud ply = read_point_cloud(write(
      "c.ply",
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\nend_header\n0 0 0 0 0 1\n1 1 1 1 0 0\n"));
  ASSERT_EQ(ply.points.size(), 2u);
  ASSERT_EQ(ply.normals.size(), 2u);
  EXPECT_EQ(ply.normals[1], Vec3(1, 0, 0));
  EXPECT_EQ(read_point_cloud(write("c.off", "OFF\n2 0 0\n0 0 0\n1 1 1\n")).points.size(), 2u);
  EXPECT_EQ(read_point_cloud(write("c.obj", "v 0 0 0\nv 1 1 1\np 1 2\n")).points.size(), 2u);
  EXPECT_EQ(read_point_cloud(write("c.vtk",
                                   "# vtk DataFile Version 3.0\nc\nASCII\nDATASET POLYDATA\n"
                                   "POINTS 2 double\n0 0 0 1 1 1\nVERTICES 2 4\n1 0\n1 1\n"))
                .points.size(),
            2u);
  // A mesh's faces come through unchecked, for the caller to judge.
  const PointCloud mesh = read_point_cloud(write("m.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
  EXPECT_EQ(mesh.faces.size(), 1u);
  // The public scans.
  const PointCloud hippo = read_point_cloud(testing::public_data("hippo1.ply"));
  EXPECT_EQ(hippo.points.size(), 6104u);
  EXPECT_EQ(hippo.normals.size(), 6104u);
  const PointCloud kitten = read_point_cloud(testing::public_data("kitten.xyz"));
  EXPECT_EQ(kitten.points.size(), 5210u);
  EXPECT_EQ(kitten.normals.size(), 5210u);
  EXPECT_EQ(read_point_cloud(testing::public_data("oni.pwn")).normals.size(), 1435u);
}

TEST_F(PointCloudFiles, WrittenCloudsHaveVertexCellsAndTheirArrays) {
  const std::vector<Vec3> points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0.25}};
  const std::string file = (dir_ / "t.vtp").string();
  write_point_cloud(file, points, {{"distance", 1, {0.5, 1.5, 2.5}}});
  auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkPolyData* data = reader->GetOutput();
  ASSERT_EQ(data->GetNumberOfPoints(), 3);
  EXPECT_EQ(data->GetNumberOfVerts(), 3);
  EXPECT_EQ(data->GetNumberOfPolys(), 0);
  ASSERT_NE(data->GetPointData()->GetArray("distance"), nullptr);
  EXPECT_EQ(data->GetPointData()->GetArray("distance")->GetComponent(2, 0), 2.5);
  const PointCloud back = read_point_cloud(file);
  ASSERT_EQ(back.points.size(), 3u);
  EXPECT_EQ(back.points[2], points[2]);
  EXPECT_THROW(write_point_cloud((dir_ / "t.obj").string(), points, {}), InputError);
  EXPECT_THROW(write_point_cloud(file, points, {{"distance", 1, {1.0}}}), std::invalid_argument);
}

}  // namespace
}  // namespace rgbmesh
