// Mesh files, reading: exact contents read from hand-written files, the XML arrays and encoding
// as VTK's own readers see them, one test per input error, truncated and garbage files.

#include "vtk_io_fixture.hpp"

namespace {

// ---------------------------------------------------------------------------------------------
// OFF

TEST_F(VtkIo, OffIsReadExactly) {
  const fs::path f = write_file("a.off",
                                "# written by hand\n"
                                "OFF\n"
                                "5 3 0  # counts\n"
                                "0.1 0 0\n"
                                "1 0 0\n"
                                "1 1 0   # a comment after the values\n"
                                "\n"
                                "0 1 0\n"
                                "1e-3 -2.5 +3\n"
                                "3 0 1 2\n"
                                "4 0 2 3 4 255 0 0\n"  // a colour after the indices
                                "3 1 2 4\n");
  const PolygonSoup s = read_polygon_soup(f);
  EXPECT_EQ(s.points, (std::vector<Vec3>{{0.1, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.001, -2.5, 3}}));
  EXPECT_EQ(s.faces, (Faces{{0, 1, 2}, {0, 2, 3, 4}, {1, 2, 4}}));
}

TEST_F(VtkIo, OffVariantsAreRead) {
  const Faces triangle = {{0, 1, 2}};
  const std::vector<Vec3> points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (const std::string& text :
       {std::string("3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),                   // no header
        std::string("OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),               // counts on it
        std::string("OFF\r\n3 1 0\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n"),  // CRLF
        std::string("COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 1 0 0 1\n0 1 0 1 0 0 1\n3 0 1 2\n")}) {
    const fs::path f = write_file("v.OFF", text);  // the extension is case-insensitive
    const PolygonSoup s = read_polygon_soup(f);
    EXPECT_EQ(s.points, points) << text;
    EXPECT_EQ(s.faces, triangle) << text;
  }
}

TEST_F(VtkIo, OffErrorsNameTheLine) {
  struct Case {
    std::string text, expect;
  } cases[] = {
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n", "line 6: expected 3 vertex indices, found 2"},
      {"OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", "line 4: 'zero' is not a number"},
      {"OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", "line 4: expected 3 vertex coordinates, found 2"},
      {"OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "the file ends after 1 of 2 faces"},
      {"OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n", "the file ends after 3 of 4 vertices"},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 x 2\n", "line 6: 'x' is not a vertex index"},
      {"OFF\n3 -1 0\n", "line 2: expected the counts"},
      {"4OFF\n3 1 0\n", "line 1: unsupported OFF variant '4OFF'"},
      {"OFF BINARY\n", "line 1: binary OFF files are not supported"},
      {"", "the file is empty"},
  };
  for (const auto& c : cases) {
    const fs::path f = write_file("bad.off", c.text);
    expect_names(input_error([&] { read_polygon_soup(f); }), f, {c.expect});
  }
}

// ---------------------------------------------------------------------------------------------
// OBJ

TEST_F(VtkIo, ObjIsReadExactlyInDoublePrecision) {
  const fs::path f = write_file("a.obj",
                                "# comment\n"
                                "mtllib a.mtl\n"
                                "o thing\n"
                                "v 0.1 0.2 0.3\n"
                                "v 1 0 0 1.0\n"    // with w
                                "v 0 1 0 1 0 0\n"  // with a colour
                                "v 1 1 0\n"
                                "v 9 9 9\n"  // unreferenced: kept in the soup
                                "vt 0 0\nvt 1 0\nvn 0 0 1\n"
                                "g group\nusemtl red\ns 1\n"
                                "f 1/1/1 2/2/1 3/1/1\n"
                                "f -4//1 \\\n"  // continued on the next line
                                "  -3//1 4//1 -2//1\n");
  const PolygonSoup s = read_polygon_soup(f);
  EXPECT_EQ(s.points, (std::vector<Vec3>{{0.1, 0.2, 0.3}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {9, 9, 9}}));
  EXPECT_EQ(s.faces, (Faces{{0, 1, 2}, {1, 2, 3, 3}}));
}

// vtkOBJReader gives every face corner its own point when normals or texture coordinates are
// indexed differently from the vertices, which would cut the mesh into separate triangles. The
// 'v' lines are the vertices: two triangles sharing an edge stay connected.
TEST_F(VtkIo, ObjPerCornerAttributesDoNotSplitVertices) {
  const fs::path f = write_file("corners.obj",
                                "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                "vn 0 0 1\nvn 0 0 1\nvt 0 0\nvt 1 1\n"
                                "f 1/1/1 2/2/2 3/1/1\nf 2/1/2 4/2/1 3/2/1\n");
  const TriangleMeshData m = read_mesh(f);
  EXPECT_EQ(m.points.size(), 4u);
  EXPECT_EQ(m.triangles, (std::vector<std::array<std::int32_t, 3>>{{0, 1, 2}, {1, 3, 2}}));
}

// vtkOBJReader 9.1 reads out of bounds (and crashes) on this file.
TEST_F(VtkIo, ObjIndexOutOfRangeWithNormalsIsAnError) {
  const fs::path f = write_file("oor.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 300000000//1\n");
  expect_names(read_error(f), f,
               {"line 5: vertex index 300000000 is out of range (the file has 3 vertices)"});
}

TEST_F(VtkIo, ObjErrorsNameTheLine) {
  struct Case {
    std::string text, expect;
  } cases[] = {
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
       "line 4: vertex index 0 is invalid (OBJ counts vertices from 1)"},
      {"v 0 0 0\nv 1 0 0\nf -1 -2 -3\n", "line 3: relative vertex index -3 points before the first vertex"},
      {"v 0 0 0\nv 1 0 0\nl 1 2\n", "line 3: 'l' elements (polylines) are not surface polygons"},
      {"v 0 0 0\np 1\n", "line 2: 'p' elements (points) are not surface polygons"},
      {"v 0 0 0\nv 1 0\n", "line 2: expected 3 vertex coordinates, found 2"},
      {"v 0 0 0\nv 1 0 one\n", "line 2: 'one' is not a number"},
      {"v 0 0 0\nf 1 a/2 1\n", "line 2: 'a/2' is not a vertex reference"},
      {std::string("v 0 0 0\0\n", 10), "not a text file"},
  };
  for (const auto& c : cases) {
    const fs::path f = write_file("bad.obj", c.text);
    expect_names(input_error([&] { read_polygon_soup(f); }), f, {c.expect});
  }
}

// vtkOBJReader 9.1 reads "nan" as 0; here it reaches the checks.
TEST_F(VtkIo, ObjNonFiniteCoordinateIsNamed) {
  const fs::path f = write_file("nan.obj", "v nan 0 1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  expect_names(read_error(f), f, {"vertex 0 has a non-finite coordinate (nan, 0, 1)"});
}

// ---------------------------------------------------------------------------------------------
TEST_F(VtkIo, AsciiStlCoordinatesAreSinglePrecisionLikeBinaryOnes) {
  // Every coordinate, x and y too (GCC's vectorizer once dropped their rounding): the float
  // nearest each decimal, as a binary STL of the same triangle holds it.
  const fs::path f = write_file("t.stl",
                                "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0.1 0.2 0.3\nvertex 1.1 0.2 0.3\n"
                                "vertex 0.1 1.7 0.3\nendloop\nendfacet\nendsolid t\n");
  const PolygonSoup s = read_polygon_soup(f);
  const auto single = [](double x) { return static_cast<double>(static_cast<float>(x)); };
  ASSERT_EQ(s.points.size(), 3u);
  EXPECT_EQ(s.points[0], Vec3(single(0.1), single(0.2), single(0.3)));
  EXPECT_EQ(s.points[1], Vec3(single(1.1), single(0.2), single(0.3)));
  EXPECT_EQ(s.points[2], Vec3(single(0.1), single(1.7), single(0.3)));
  EXPECT_NE(s.points[0].x, 0.1);
}

// PLY

TEST_F(VtkIo, AsciiPlyIsReadExactly) {
  const fs::path f = write_file("a.ply",
                                "ply\n"
                                "format ascii 1.0\n"
                                "comment hand-written\n"
                                "element vertex 4\n"
                                "property double x\nproperty double y\nproperty float nx\nproperty double z\n"
                                "property uchar red\n"
                                "element face 2\n"
                                "property uchar flags\n"
                                "property list uchar int vertex_index\n"
                                "element edge 1\n"
                                "property int vertex1\nproperty int vertex2\n"
                                "end_header\n"
                                "0.1 0 7 0 255\n1 0 7 0 255\n1 1 7 0.3 255\n0 1 7 0 255\n"
                                "9 3 0 1 2\n9 4 0 2 3 1\n"
                                "0 1\n");
  const PolygonSoup s = read_polygon_soup(f);
  EXPECT_EQ(s.points, (std::vector<Vec3>{{0.1, 0, 0}, {1, 0, 0}, {1, 1, 0.3}, {0, 1, 0}}));
  EXPECT_EQ(s.faces, (Faces{{0, 1, 2}, {0, 2, 3, 1}}));
}

// A binary PLY with double coordinates, an extra property, a 300-gon (which vtkPLYReader 9.1
// cuts to 300 mod 256 = 44 vertices) and an element after the faces.
std::string binary_ply(bool big_endian, int polygon) {
  Bytes b{big_endian, ""};
  b.data = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
           " 1.0\nelement vertex " + std::to_string(polygon) +
           "\nproperty double x\nproperty double y\nproperty double z\nproperty short extra\n"
           "element face 2\nproperty list int uint vertex_indices\nproperty float quality\n"
           "element material 1\nproperty uchar r\nend_header\n";
  for (int i = 0; i < polygon; ++i)
    b.put(std::cos(0.1 * i)).put(std::sin(0.1 * i) / 3).put(0.0).put(static_cast<std::int16_t>(-i));
  b.put(static_cast<std::int32_t>(3)).put(0u).put(1u).put(2u).put(0.5f);
  b.put(static_cast<std::int32_t>(polygon));
  for (int i = 0; i < polygon; ++i) b.put(static_cast<std::uint32_t>(polygon - 1 - i));
  b.put(0.25f).put(static_cast<std::uint8_t>(7));
  return b.data;
}

TEST_F(VtkIo, BinaryPlyIsReadExactlyInBothByteOrders) {
  const int n = 300;
  for (const bool big_endian : {false, true}) {
    const fs::path f = write_file("b.ply", binary_ply(big_endian, n));
    const PolygonSoup s = read_polygon_soup(f);
    ASSERT_EQ(s.points.size(), static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i)
      EXPECT_EQ(s.points[i], Vec3(std::cos(0.1 * i), std::sin(0.1 * i) / 3, 0.0)) << i;
    ASSERT_EQ(s.faces.size(), 2u);
    EXPECT_EQ(s.faces[0], (std::vector<std::int64_t>{0, 1, 2}));
    ASSERT_EQ(s.faces[1].size(), static_cast<std::size_t>(n));
    EXPECT_EQ(s.faces[1].front(), n - 1);
    EXPECT_EQ(s.faces[1].back(), 0);
  }
}

// vtkPLYReader 9.1 crashes or aborts on most of these.
TEST_F(VtkIo, TruncatedPlyIsAnErrorAtEveryLength) {
  const std::string full = binary_ply(false, 5);
  for (std::size_t n = 0; n < full.size(); ++n) {
    const fs::path f = write_file("t.ply", full.substr(0, n));
    const std::string message = input_error([&] { read_polygon_soup(f); });
    EXPECT_EQ(message.rfind(f.string() + ": ", 0), 0u) << n << ": " << message;
  }
  const std::string ascii =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  for (std::size_t n = 0; n + 2 < ascii.size(); ++n) {  // the last line without "2\n" is still valid
    const fs::path f = write_file("t.ply", ascii.substr(0, n));
    const std::string message = input_error([&] { read_polygon_soup(f); });
    EXPECT_EQ(message.rfind(f.string() + ": ", 0), 0u) << n << ": " << message;
  }
}

TEST_F(VtkIo, PlyErrorsNameTheProblem) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n";
  struct Case {
    std::string text, expect;
  } cases[] = {
      {head + "end_header\n0 0\n1 0\n0 1\n", "the PLY 'vertex' element has no scalar property 'z'"},
      {head + "property float z\nelement face 1\nproperty list uchar int other\nend_header\n0 0 0\n1 0 0\n0 "
              "1 0\n3 0 1 2\n",
       "the PLY 'face' element has no integer list 'vertex_indices'"},
      {"ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n",
       "the PLY file has no 'vertex' element"},
      {head + "property float z\nend_header\n0 0 0\n1 0\n0 1 0\n",
       "line 9: too few values for element 'vertex'"},
      {head + "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 "
              "0\n1 0 0\n0 1 0\n"
              "4 0 1 2\n",
       "line 13: expected 4 list values, found 3"},
      {"ply\nformat binary_middle_endian 1.0\n", "line 2: unknown PLY format 'binary_middle_endian'"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n",
       "line 4: expected 'property <type> <name>'"},
      {"solid x\n", "not a PLY file"},
  };
  for (const auto& c : cases) {
    const fs::path f = write_file("bad.ply", c.text);
    expect_names(input_error([&] { read_polygon_soup(f); }), f, {c.expect});
  }
}

TEST_F(VtkIo, PlyFreeTextHeaderLinesOfOldExportersAreReadAsComments) {
  // Old Blender exporters wrote "Created by ..." without 'comment'; VTK's reader skips such
  // lines. The file reads as the same file without the line, with one note naming the line.
  const int n = 40;
  const std::string clean = binary_ply(false, n);
  std::string old = clean;
  old.insert(old.find("element vertex"), "Created by Blender 2.49 - www.blender.org\nExported from a.blend\n");
  const PolygonSoup expected = read_polygon_soup(write_file("clean.ply", clean));
  const PolygonSoup s = read_polygon_soup(write_file("old.ply", old));
  EXPECT_EQ(s.points, expected.points);
  EXPECT_EQ(s.faces, expected.faces);
  ASSERT_EQ(s.notes.size(), 1u);  // one note, for the first such line
  EXPECT_NE(s.notes[0].find("line 3: free text 'Created ...'"), std::string::npos) << s.notes[0];
  EXPECT_TRUE(expected.notes.empty());
  // Point clouds too, with the file named.
  const fs::path cloud = write_file("cloud.ply", "ply\nformat ascii 1.0\nScanned with a turntable, 2004\n"
                                                 "element vertex 2\nproperty float x\nproperty float y\n"
                                                 "property float z\nend_header\n0 0 0\n1 2 3\n");
  const rgbmesh::PointCloud c = rgbmesh::read_point_cloud(cloud);
  ASSERT_EQ(c.points.size(), 2u);
  EXPECT_EQ(c.points[1], Vec3(1, 2, 3));
  ASSERT_EQ(c.notes.size(), 1u);
  EXPECT_EQ(c.notes[0].rfind(cloud.string() + ": line 3: free text", 0), 0u) << c.notes[0];
}

TEST_F(VtkIo, PlyHeaderLinesThatLookLikeDamagedDeclarationsAreRefused) {
  // Skipping a damaged 'property' line would shift every value after it: refused, as before.
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n";
  for (const std::string line : {"bogus", "propery float z", "proprety float z", "elemnt face 1",
                                 "vertex_color uchar red", "faces list uchar int vertex_indices", "end_headr x y"}) {
    const fs::path f = write_file("bad.ply", head + line + "\nproperty float z\nend_header\n0 0 0\n");
    const std::string first = line.substr(0, line.find(' '));
    expect_names(input_error([&] { read_polygon_soup(f); }), f, {"line 6: unexpected '" + first + "' in the PLY header"});
  }
}

// vtkPLYReader 9.1 reads out of bounds on this file.
TEST_F(VtkIo, PlyIndexOutOfRangeIsNamed) {
  const fs::path f =
      write_file("oor.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                 "0 0 0\n1 0 0\n0 1 0\n3 0 1 2000000\n");
  expect_names(read_error(f), f, {"face 0 references vertex 2000000 but the file has 3 vertices"});
}

// ---------------------------------------------------------------------------------------------
// STL

TEST_F(VtkIo, AsciiStlMergesCoincidentCorners) {
  const fs::path f =
      write_file("a.stl",
                 "solid two\n"
                 " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 1 1 0\n"
                 "  endloop\n endfacet\n"
                 " facet normal 0 0 1\n  outer loop\n   vertex -0 0 0\n   vertex 1 1 0\n   vertex 0 1 0\n"
                 "  endloop\n endfacet\n"
                 "endsolid two\n");
  const PolygonSoup s = read_polygon_soup(f);
  EXPECT_EQ(s.points, (std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}));
  EXPECT_EQ(s.faces, (Faces{{0, 1, 2}, {0, 2, 3}}));
}

std::string binary_stl(const std::vector<std::array<Vec3, 3>>& triangles) {
  Bytes b;
  b.data = std::string(80, ' ');
  b.put(static_cast<std::uint32_t>(triangles.size()));
  for (const auto& t : triangles) {
    b.put(0.f).put(0.f).put(1.f);
    for (const Vec3& p : t)
      b.put(static_cast<float>(p.x)).put(static_cast<float>(p.y)).put(static_cast<float>(p.z));
    b.put(static_cast<std::uint16_t>(0));
  }
  return b.data;
}

TEST_F(VtkIo, BinaryStlMergesCoincidentCorners) {
  const fs::path f = write_file("b.stl", binary_stl({{Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 1, 0}},
                                                     {Vec3{0, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 0}}}));
  const PolygonSoup s = read_polygon_soup(f);
  EXPECT_EQ(s.points, (std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}));
  EXPECT_EQ(s.faces, (Faces{{0, 1, 2}, {0, 2, 3}}));
}

// vtkSTLReader 9.1 silently returns the complete triangles of a truncated binary file.
TEST_F(VtkIo, TruncatedBinaryStlIsAnErrorAtEveryLength) {
  write_mesh(path("full.stl"), grid_snapshot(2));
  const std::string full = contents(path("full.stl"));
  ASSERT_EQ(full.size(), 84u + 50u * 8u);
  for (std::size_t n = 0; n < full.size(); ++n) {
    const fs::path f = write_file("t.stl", full.substr(0, n));
    const std::string message = input_error([&] { read_polygon_soup(f); });
    EXPECT_EQ(message.rfind(f.string() + (n == 0 ? ": the file is empty" : ": cannot read: "), 0), 0u)
        << n << ": " << message;
  }
  expect_names(
      read_error(write_file("t.stl", full.substr(0, 200))), path("t.stl"),
      {"the binary STL header announces 8 triangles (484 bytes), the file has 200 bytes: it is truncated"});
}

// ---------------------------------------------------------------------------------------------
// VTP, VTU

vtkSmartPointer<vtkPoints> triangle_points() {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  for (const Vec3& p : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}})
    points->InsertNextPoint(p.x, p.y, p.z);
  return points;
}

void write_xml(vtkPolyData* data, const fs::path& file) {
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(data);
  writer->SetDataModeToAscii();  // no compression: what is written is what is read
  writer->SetFileName(file.c_str());
  ASSERT_EQ(writer->Write(), 1);
}

void write_xml(vtkUnstructuredGrid* data, const fs::path& file) {
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetInputData(data);
  writer->SetDataModeToAscii();
  writer->SetFileName(file.c_str());
  ASSERT_EQ(writer->Write(), 1);
}

TEST_F(VtkIo, VtpNonSurfaceCellsAreNamed) {
  vtkNew<vtkPolyData> data;
  data->SetPoints(triangle_points());
  vtkNew<vtkCellArray> verts, lines, polys;
  const vtkIdType vertex[] = {4}, line[] = {0, 4}, triangle[] = {0, 1, 2};
  verts->InsertNextCell(1, vertex);
  lines->InsertNextCell(2, line);
  polys->InsertNextCell(3, triangle);
  data->SetVerts(verts);
  data->SetPolys(polys);
  write_xml(data, path("verts.vtp"));
  expect_names(read_error(path("verts.vtp")), path("verts.vtp"),
               {"cell 0 is a vertex, not a surface polygon"});
  data->SetVerts(nullptr);
  data->SetLines(lines);
  write_xml(data, path("lines.vtp"));
  expect_names(read_error(path("lines.vtp")), path("lines.vtp"), {"cell 0 is a line, not a surface polygon"});
}

TEST_F(VtkIo, VtuVolumeCellIsNamed) {
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(triangle_points());
  const vtkIdType triangle[] = {0, 1, 2}, tetra[] = {0, 1, 3, 4};
  grid->InsertNextCell(VTK_TRIANGLE, 3, triangle);
  grid->InsertNextCell(VTK_TETRA, 4, tetra);
  write_xml(grid, path("tetra.vtu"));
  expect_names(read_error(path("tetra.vtu")), path("tetra.vtu"),
               {"cell 1 is a tetrahedron, not a surface polygon"});
}

TEST_F(VtkIo, VtuSurfaceCellsBecomeFaces) {
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(triangle_points());
  const vtkIdType triangle[] = {0, 1, 4}, quad[] = {0, 1, 2, 3}, pixel[] = {0, 1, 3, 2},
                  polygon[] = {0, 1, 2, 3, 4}, strip[] = {0, 1, 3, 2, 4};
  grid->InsertNextCell(VTK_TRIANGLE, 3, triangle);
  grid->InsertNextCell(VTK_QUAD, 4, quad);
  grid->InsertNextCell(VTK_PIXEL, 4, pixel);  // the pixel (0,1,3,2) is the quad (0,1,2,3)
  grid->InsertNextCell(VTK_POLYGON, 5, polygon);
  grid->InsertNextCell(VTK_TRIANGLE_STRIP, 5, strip);
  write_xml(grid, path("cells.vtu"));
  const PolygonSoup s = read_polygon_soup(path("cells.vtu"));
  EXPECT_EQ(s.points.size(), 5u);
  // Strip triangles as VTK itself orients them: every second one reversed.
  EXPECT_EQ(s.faces,
            (Faces{{0, 1, 4}, {0, 1, 2, 3}, {0, 1, 2, 3}, {0, 1, 2, 3, 4}, {0, 1, 3}, {3, 1, 2}, {3, 2, 4}}));
}

// The strip convention above, checked against VTK's own triangulation of a strip.
TEST_F(VtkIo, StripsAreSplitLikeVtkDoes) {
  vtkNew<vtkPolyData> data;
  data->SetPoints(triangle_points());
  vtkNew<vtkCellArray> strips;
  const vtkIdType strip[] = {0, 1, 3, 2, 4};
  strips->InsertNextCell(5, strip);
  data->SetStrips(strips);
  write_xml(data, path("strip.vtp"));
  vtkNew<vtkTriangleFilter> filter;
  filter->SetInputData(data);
  filter->Update();
  Faces expected;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < filter->GetOutput()->GetNumberOfCells(); ++c) {
    filter->GetOutput()->GetCellPoints(c, ids);
    expected.push_back({ids->GetId(0), ids->GetId(1), ids->GetId(2)});
  }
  EXPECT_EQ(read_polygon_soup(path("strip.vtp")).faces, expected);
}

// The XML readers do not validate connectivity: bad ids and coordinates reach the checks.
TEST_F(VtkIo, VtpBadIdsAndCoordinatesAreNamed) {
  vtkNew<vtkPolyData> data;
  const vtkSmartPointer<vtkPoints> points = triangle_points();
  data->SetPoints(points);
  vtkNew<vtkCellArray> polys;
  const vtkIdType triangle[] = {0, 1, 99};
  polys->InsertNextCell(3, triangle);
  data->SetPolys(polys);
  write_xml(data, path("ids.vtp"));
  expect_names(read_error(path("ids.vtp")), path("ids.vtp"),
               {"face 0 references vertex 99 but the file has 5 vertices"});
  const vtkIdType good[] = {0, 1, 2};
  polys->Reset();
  polys->InsertNextCell(3, good);
  points->SetPoint(3, std::numeric_limits<double>::quiet_NaN(), 0, 0);
  write_xml(data, path("nan.vtp"));
  expect_names(read_error(path("nan.vtp")), path("nan.vtp"),
               {"vertex 3 has a non-finite coordinate (nan, 0, 0)"});
}

// A truncated or corrupted XML file is an error, or (when only the closing tags are cut off) the
// complete mesh: never a silently different one.
TEST_F(VtkIo, TruncatedAndCorruptXmlIsAnErrorOrTheCompleteMesh) {
  const MeshSnapshot m = grid_snapshot(3);
  for (const std::string ext : {".vtp", ".vtu"}) {
    write_mesh(path("full" + ext), m);
    const TriangleMeshData expected = read_mesh(path("full" + ext));
    const std::string full = contents(path("full" + ext));
    for (std::size_t n = 0; n < full.size(); n += (n < full.size() - 600 ? 37 : 1)) {
      const fs::path f = write_file("t" + ext, full.substr(0, n));
      try {
        const TriangleMeshData back = read_mesh(f);
        EXPECT_EQ(back.points, expected.points) << ext << " " << n;
        EXPECT_EQ(back.triangles, expected.triangles) << ext << " " << n;
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(f.string() + ": ", 0), 0u) << e.what();
      }
    }
    std::string corrupt = full;
    const auto data = corrupt.find("<AppendedData encoding=\"raw\">");
    ASSERT_NE(data, std::string::npos);
    for (std::size_t i = data + 60; i + 40 < corrupt.size(); i += 5)
      corrupt[i] = static_cast<char>(corrupt[i] ^ 0x5a);
    const fs::path f = write_file("corrupt" + ext, corrupt);
    expect_names(read_error(f), f, {"cannot read: "});
  }
}

// ---------------------------------------------------------------------------------------------
// Legacy VTK

TEST_F(VtkIo, LegacyAsciiIsReadExactly) {
  const fs::path f = write_file("a.vtk",
                                "# vtk DataFile Version 3.0\n"
                                "hand-written\n"
                                "ASCII\n"
                                "DATASET POLYDATA\n"
                                "FIELD FieldData 1\n"
                                "TIME 1 1 double\n"
                                "0.5\n"
                                "POINTS 4 double\n"
                                "0.1 0 0 1 0 0\n1 1 0\n0 1 0.3\n"
                                "POLYGONS 2 9\n"
                                "3 0 1 2\n"
                                "4 0 2 3 1\n"
                                "POINT_DATA 4\n"
                                "SCALARS s float 1\nLOOKUP_TABLE default\n1 2 3 4\n");
  const PolygonSoup s = read_polygon_soup(f);
  EXPECT_EQ(s.points, (std::vector<Vec3>{{0.1, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.3}}));
  EXPECT_EQ(s.faces, (Faces{{0, 1, 2}, {0, 2, 3, 1}}));
}

// Files as VTK 9.1 writes them (version 5.1 cell layout), ASCII and big-endian binary, both
// data set kinds.
TEST_F(VtkIo, LegacyFilesWrittenByVtkAreReadExactly) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  const std::vector<Vec3> expected = {{0.1, 0, 0}, {1.0 / 3, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const Vec3& p : expected) points->InsertNextPoint(p.x, p.y, p.z);
  vtkNew<vtkCellArray> triangles;
  const Faces faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& t : faces) {
    const vtkIdType ids[] = {t[0], t[1], t[2]};
    triangles->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetPolys(triangles);
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  grid->SetCells(VTK_TRIANGLE, triangles);
  for (const bool binary : {false, true}) {
    vtkNew<vtkPolyDataWriter> poly_writer;
    poly_writer->SetInputData(poly);
    poly_writer->SetFileName(path("poly.vtk").c_str());
    vtkNew<vtkUnstructuredGridWriter> grid_writer;
    grid_writer->SetInputData(grid);
    grid_writer->SetFileName(path("grid.vtk").c_str());
    if (binary) {
      poly_writer->SetFileTypeToBinary();
      grid_writer->SetFileTypeToBinary();
    }
    ASSERT_EQ(poly_writer->Write(), 1);
    ASSERT_EQ(grid_writer->Write(), 1);
    for (const char* name : {"poly.vtk", "grid.vtk"}) {
      const PolygonSoup s = read_polygon_soup(path(name));
      EXPECT_EQ(s.faces, faces) << name << binary;
      ASSERT_EQ(s.points.size(), expected.size());
      for (std::size_t i = 0; i < expected.size(); ++i) {
        if (binary) {
          EXPECT_EQ(s.points[i], expected[i]) << name;
        } else {  // VTK writes ASCII numbers with fewer digits than a double needs
          EXPECT_LT(rgbmesh::distance(s.points[i], expected[i]), 1e-9) << name;
        }
      }
    }
  }
  // Every truncation of the binary files is an error (VTK's reader returns garbage for some).
  for (const char* name : {"poly.vtk", "grid.vtk"}) {
    const std::string full = contents(path(name));
    for (std::size_t n = 0; n + 1 < full.size(); ++n) {  // the final newline is not needed
      const fs::path f = write_file("t.vtk", full.substr(0, n));
      const std::string message = input_error([&] { read_mesh(f); });
      EXPECT_EQ(message.rfind(f.string() + ": ", 0), 0u) << name << " " << n << ": " << message;
    }
  }
}

TEST_F(VtkIo, LegacyErrorsNameTheProblem) {
  const std::string head = "# vtk DataFile Version 3.0\nx\nASCII\n";
  struct Case {
    std::string text, expect;
  } cases[] = {
      // vtkPolyDataReader 9.1 crashes on this one (the cell list is shorter than announced).
      {head + "DATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1\n",
       "the file is truncated"},
      {head + "DATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n300 0 1 2\n",
       "line 8: cell 0 does not fit in the 4 values the section announces"},
      {head + "DATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\nLINES 1 3\n2 0 1\n",
       "cell 0 is a line, not a surface polygon"},
      {head + "DATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 1 5\n4 0 1 2 "
              "3\nCELL_TYPES 1\n10\n",
       "cell 0 is a tetrahedron, not a surface polygon"},
      {head + "DATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\n",
       "holds a STRUCTURED_POINTS data set, not a polygonal mesh or unstructured grid"},
      {head + "DATASET POLYDATA\nPOINTS 3 quaternion\n", "line 5: unsupported data type 'quaternion'"},
      {"# not vtk\n", "not a legacy VTK file"},
  };
  for (const auto& c : cases) {
    const fs::path f = write_file("bad.vtk", c.text);
    expect_names(read_error(f), f, {c.expect});
  }
}

// ---------------------------------------------------------------------------------------------
// Any format

TEST_F(VtkIo, MissingDirectoryAndUnknownFilesAreNamed) {
  expect_names(read_error(path("missing.obj")), path("missing.obj"), {"file does not exist"});
  fs::create_directories(path("dir.off"));
  expect_names(read_error(path("dir.off")), path("dir.off"), {"is a directory"});
  const fs::path f = write_file("mesh.xyz", "1 2 3\n");
  expect_names(read_error(f), f,
               {"unknown mesh format '.xyz' (supported: " + rgbmesh::supported_input_extensions() + ")"});
  EXPECT_EQ(rgbmesh::supported_input_extensions(), ".3mf, .obj, .off, .ply, .stl, .vtk, .vtp, .vtu");
  EXPECT_EQ(rgbmesh::supported_output_extensions(), ".obj, .off, .ply, .stl, .vtp, .vtu");
}

TEST_F(VtkIo, GarbageIsAnErrorInEveryFormatAndVtkPrintsNothing) {
  std::mt19937 rng(7);
  vtkOutputWindow* const window = vtkOutputWindow::GetInstance();
  for (const std::string ext : {".obj", ".off", ".ply", ".stl", ".vtk", ".vtp", ".vtu"}) {
    for (int round = 0; round < 20; ++round) {
      std::string garbage(static_cast<std::size_t>(rng() % 2000), '\0');
      for (char& c : garbage) c = static_cast<char>(rng());
      const fs::path f = write_file("garbage" + ext, garbage);
      // input_error also checks that nothing reached stderr.
      const std::string message = input_error([&] { read_mesh(f); });
      EXPECT_EQ(message.rfind(f.string() + ": ", 0), 0u) << message;
    }
  }
  EXPECT_EQ(vtkOutputWindow::GetInstance(), window);  // the capture restores VTK's output window
}

// Valid files with random damage (bytes changed, removed, repeated): every read ends in a mesh or
// an InputError naming the file, with nothing printed.
TEST_F(VtkIo, DamagedFilesGiveAMeshOrAnError) {
  const MeshSnapshot m = grid_snapshot(3);
  std::vector<fs::path> originals;
  for (const std::string ext : {".obj", ".off", ".ply", ".stl", ".vtp", ".vtu"}) {
    originals.push_back(path("original" + ext));
    write_mesh(originals.back(), m);
  }
  originals.push_back(write_file("ascii.ply",
                                 "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                                 "property float y\nproperty float z\nelement face 2\n"
                                 "property list uchar int vertex_indices\nend_header\n"
                                 "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"));
  originals.push_back(
      write_file("ascii.vtk",
                 "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\n"
                 "POINTS 4 float\n0 0 0 1 0 0 1 1 0 0 1 0\nPOLYGONS 2 8\n3 0 1 2\n3 0 2 3\n"));
  std::mt19937 rng(2024);
  for (const fs::path& original : originals) {
    EXPECT_NO_THROW(read_mesh(original)) << original;
    const std::string full = contents(original);
    for (int round = 0; round < 150; ++round) {
      std::string damaged = full;
      for (int edit = 0; edit < 1 + static_cast<int>(rng() % 4); ++edit) {
        const std::size_t at = rng() % damaged.size(), length = 1 + rng() % 16;
        switch (rng() % 3) {
          case 0:
            damaged[at] = static_cast<char>(rng());
            break;
          case 1:
            damaged.erase(at, length);
            break;
          default:
            damaged.insert(at, damaged.substr(at, length));
            break;
        }
        if (damaged.empty()) damaged = "x";
      }
      const fs::path f = write_file("damaged" + original.extension().string(), damaged);
      ::testing::internal::CaptureStderr();
      try {
        read_mesh(f);
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(f.string() + ": ", 0), 0u) << e.what();
      } catch (const std::exception& e) {
        ADD_FAILURE() << original << " round " << round << ": " << e.what();
      }
      EXPECT_EQ(::testing::internal::GetCapturedStderr(), "") << original << " round " << round;
    }
  }
}

TEST_F(VtkIo, ReadMeshPrefixesTheFileToMeshErrors) {
  const fs::path f = write_file("quad.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
  expect_names(read_error(f), f, {"face 0 has 4 vertices; only triangles are supported"});
  rgbmesh::SoupOptions options;
  options.triangulate = true;
  const TriangleMeshData m = read_mesh(f, options);
  EXPECT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(m.notes.size(), 1u);
}

// ---------------------------------------------------------------------------------------------
// Issue 10: damaged headers, special files, byte-order marks, and every encoding VTK writes

// A grid as VTK data, for VTK's own writers.
vtkSmartPointer<vtkPolyData> grid_poly_data(const MeshSnapshot& m) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  for (const Vec3& p : m.points) points->InsertNextPoint(p.x, p.y, p.z);
  auto polys = vtkSmartPointer<vtkCellArray>::New();
  for (const auto& t : m.triangles) {
    const vtkIdType ids[] = {t[0], t[1], t[2]};
    polys->InsertNextCell(3, ids);
  }
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(points);
  data->SetPolys(polys);
  auto u = vtkSmartPointer<vtkDoubleArray>::New();
  u->SetName("u");
  for (std::size_t v = 0; v < m.points.size(); ++v) u->InsertNextValue(0.5 * static_cast<double>(v));
  data->GetPointData()->AddArray(u);
  auto level = vtkSmartPointer<vtkUnsignedCharArray>::New();
  level->SetName("level");
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    level->InsertNextValue(static_cast<unsigned char>(t % 5));
  data->GetCellData()->AddArray(level);
  return data;
}

// Every data mode, appended encoding, compressor, header type and byte order that VTK's XML
// writers produce passes the validation and reads back exactly; small compression blocks give
// many blocks with a partial last one.
TEST_F(VtkIo, XmlFilesInEveryEncodingVtkWritesAreRead) {
  const MeshSnapshot m = grid_snapshot(8);
  const vtkSmartPointer<vtkPolyData> poly = grid_poly_data(m);
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(poly->GetPoints());
  grid->SetCells(VTK_TRIANGLE, poly->GetPolys());
  grid->GetPointData()->ShallowCopy(poly->GetPointData());
  grid->GetCellData()->ShallowCopy(poly->GetCellData());
  Faces faces;
  for (const auto& t : m.triangles) faces.push_back({t[0], t[1], t[2]});
  int written = 0;
  for (const std::string mode : {"ascii", "binary", "appended-raw", "appended-base64"})
    for (const int compressor :
         {vtkXMLWriter::NONE, vtkXMLWriter::ZLIB, vtkXMLWriter::LZ4, vtkXMLWriter::LZMA})
      for (const bool header64 : {false, true})
        for (const bool big_endian : {false, true})
          for (const bool small_blocks : {false, true}) {
            if (mode == "ascii" &&
                (compressor != vtkXMLWriter::NONE || header64 || big_endian || small_blocks))
              continue;
            const auto configure = [&](vtkXMLWriter& w) {
              if (mode == "ascii") w.SetDataModeToAscii();
              if (mode == "binary") w.SetDataModeToBinary();
              if (mode.rfind("appended", 0) == 0) w.SetDataModeToAppended();
              w.SetEncodeAppendedData(mode == "appended-base64");
              w.SetCompressorType(compressor);
              if (header64) w.SetHeaderTypeToUInt64();
              if (big_endian) w.SetByteOrderToBigEndian();
              if (small_blocks) w.SetBlockSize(64);
            };
            const std::string what = mode + " compressor " + std::to_string(compressor) +
                                     (header64 ? " UInt64" : " UInt32") + (big_endian ? " big-endian" : "") +
                                     (small_blocks ? " 64-byte blocks" : "");
            vtkNew<vtkXMLPolyDataWriter> poly_writer;
            poly_writer->SetInputData(poly);
            poly_writer->SetFileName(path("e.vtp").c_str());
            configure(*poly_writer);
            ASSERT_EQ(poly_writer->Write(), 1) << what;
            vtkNew<vtkXMLUnstructuredGridWriter> grid_writer;
            grid_writer->SetInputData(grid);
            grid_writer->SetFileName(path("e.vtu").c_str());
            configure(*grid_writer);
            ASSERT_EQ(grid_writer->Write(), 1) << what;
            for (const char* name : {"e.vtp", "e.vtu"}) {
              PolygonSoup s;
              EXPECT_NO_THROW(s = read_polygon_soup(path(name))) << name << " " << what;
              EXPECT_EQ(s.points, m.points) << name << " " << what;
              EXPECT_EQ(s.faces, faces) << name << " " << what;
            }
            ++written;
          }
  EXPECT_EQ(written, 1 + 3 * 4 * 2 * 2 * 2);
}

// The file as written by rgbmesh, with `from` replaced by `to`.
std::string edited(const std::string& text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at == std::string::npos) return text;
  return text.substr(0, at) + to + text.substr(at + from.size());
}

TEST_F(VtkIo, DamagedXmlHeadersAreNamedBeforeVtkReadsThem) {
  write_mesh(path("good.vtu"), grid_snapshot(2));
  write_mesh(path("good.vtp"), grid_snapshot(2));
  const std::string vtu = contents(path("good.vtu")), vtp = contents(path("good.vtp"));
  const auto count = [](const std::string& text, const std::string& name) {
    const auto at = text.find(name + "=\"");
    return text.substr(at, text.find('"', at + name.size() + 2) + 1 - at);
  };
  struct Case {
    std::string name, text, expect;
  } cases[] = {
      // These crashed VTK's reader (exit code 139) or made it resize a vector to 2^64 elements.
      {"points.vtu", edited(vtu, count(vtu, "NumberOfPoints"), "NumberOfPoints=\"-1\""),
       "cannot read: piece 0: NumberOfPoints=\"-1\" is not a count (a non-negative integer)"},
      {"cells.vtu", edited(vtu, count(vtu, "NumberOfCells"), "NumberOfCells=\"-1\""),
       "NumberOfCells=\"-1\" is not a count"},
      {"verts.vtp", edited(vtp, count(vtp, "NumberOfVerts"), "NumberOfVerts=\"-2147483648\""),
       "NumberOfVerts=\"-2147483648\" is not a count"},
      {"components.vtu", edited(vtu, "NumberOfComponents=\"3\"", "NumberOfComponents=\"-1\""),
       "CellData array 'grad': NumberOfComponents=\"-1\" is not a positive count"},
      {"type.vtp", edited(vtp, "type=\"Float64\"", "type=\"Float65\""), "unsupported type=\"Float65\""},
      {"offset.vtp", edited(vtp, "offset=\"0\"", "offset=\"-1\""), "offset=\"-1\" is not an offset"},
      {"compressor.vtp", edited(vtp, "vtkLZ4DataCompressor", "vtkZipDataCompressor"), "unknown compressor"},
      {"header.vtp", edited(vtp, "header_type=\"UInt64\"", "header_type=\"UInt8\""), "header_type=\"UInt8\""},
      {"more.vtp", edited(vtp, count(vtp, "NumberOfPoints"), "NumberOfPoints=\"10\""),
       "piece 0 points: the array holds 27 values, the header announces 30"},
  };
  for (const Case& c : cases) {
    const fs::path f = write_file(c.name, c.text);
    expect_names(read_error(f), f, {c.expect});
  }
  // A compressed array whose header says 0 blocks (VTK read through a null block table).
  std::string zero = vtu;
  const std::size_t data = zero.find('_', zero.find("<AppendedData")) + 1;
  std::memset(&zero[data], 0, 4);
  const fs::path f = write_file("zero.vtu", zero);
  expect_names(
      read_error(f), f,
      {"PointData array 'level': the compression header announces 0 blocks with a partial last block"});
}

TEST_F(VtkIo, SpecialFilesAreRefusedAndNamed) {
  ASSERT_EQ(::mkfifo(path("fifo.obj").c_str(), 0600), 0);
  expect_names(read_error(path("fifo.obj")), path("fifo.obj"),
               {"is a FIFO (named pipe), not a regular file: only regular files are read"});
  fs::create_symlink("/dev/null", path("null.stl"));
  expect_names(read_error(path("null.stl")), path("null.stl"), {"is a character device, not a regular file"});
  fs::create_symlink(path("b.off"), path("a.off"));
  fs::create_symlink(path("a.off"), path("b.off"));
  expect_names(read_error(path("a.off")), path("a.off"), {"is a symbolic-link loop"});
  fs::create_symlink(path("nothing.ply"), path("dangling.ply"));
  expect_names(read_error(path("dangling.ply")), path("dangling.ply"),
               {"is a symbolic link to a file that does not exist"});
  expect_names(read_error(write_file("empty.vtp", "")), path("empty.vtp"), {"the file is empty"});
  // A symbolic link to a good file is read.
  write_mesh(path("good.obj"), grid_snapshot(1));
  fs::create_symlink(path("good.obj"), path("link.obj"));
  EXPECT_EQ(read_mesh(path("link.obj")).triangles.size(), 2u);
}

// Some editors start text files with a UTF-8 byte-order mark; it is no part of the first line.
TEST_F(VtkIo, ByteOrderMarkIsSkippedInEveryTextFormat) {
  const std::string bom = "\xEF\xBB\xBF";
  write_mesh(path("m.obj"), grid_snapshot(2));
  write_mesh(path("m.off"), grid_snapshot(2));
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const std::string stl =
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
      "endloop\nendfacet\nendsolid t\n";
  const std::string vtk =
      "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n"
      "0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 2\n";
  write_file("m.ply", ply);
  write_file("m.stl", stl);
  write_file("m.vtk", vtk);
  for (const char* name : {"m.obj", "m.off", "m.ply", "m.stl", "m.vtk"}) {
    const fs::path plain = path(name);
    const fs::path marked = write_file(std::string("bom_") + name, bom + contents(plain));
    const PolygonSoup expected = read_polygon_soup(plain), got = read_polygon_soup(marked);
    EXPECT_EQ(got.points, expected.points) << name;
    EXPECT_EQ(got.faces, expected.faces) << name;
  }
  const fs::path cloud = write_file("c.xyz", bom + "1 2 3\n4 5 6\n");
  EXPECT_EQ(rgbmesh::read_point_cloud(cloud).points, (std::vector<Vec3>{{1, 2, 3}, {4, 5, 6}}));
  // The OBJ of the issue: its first vertex was lost, and a face then named an index out of range.
  const fs::path obj = write_file("issue.obj", bom + "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(read_polygon_soup(obj).points.size(), 3u);
}

TEST_F(VtkIo, CountsThatDisagreeWithTheFileAreErrors) {
  // An OFF face count smaller than the faces: the rest was silently dropped.
  const fs::path off = write_file("few.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
  expect_names(
      read_error(off), off,
      {"line 8: data after the last of the 1 faces that the header announces: the face count is wrong"});
  // A binary STL longer than its triangle count says: it was read without complaint.
  write_mesh(path("long.stl"), grid_snapshot(1));
  const fs::path stl = write_file("long.stl", contents(path("long.stl")) + std::string(50, '\0'));
  expect_names(
      read_error(stl), stl,
      {"cannot read: the binary STL header announces 2 triangles (184 bytes), the file has 234 bytes: "
       "the count or the file is damaged"});
  // A binary PLY announcing 10^12 vertices, with a list property: bad_alloc before.
  Bytes b;
  b.data =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\n"
      "property float y\nproperty float z\nproperty list uchar int extra\nend_header\n";
  for (int i = 0; i < 5; ++i) b.put(0.f).put(0.f).put(0.f).put(static_cast<std::uint8_t>(0));
  const fs::path ply = write_file("huge.ply", b.data);
  expect_names(
      read_error(ply), ply,
      {"the header announces 1000000000000 items of element 'vertex' (at least 13 bytes each), the 65 "
       "bytes left in the file hold at most 5"});
}

TEST_F(VtkIo, AsciiStlIsReadStrictly) {
  const std::string facet =
      "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n"
      " endloop\nendfacet\n";
  // Keywords in any case, and several solids in one file, as some exporters write them.
  const fs::path two = write_file("two.stl", "solid a\n" + facet +
                                                 "endsolid a\nSOLID B\nFACET NORMAL 0 0 1\n"
                                                 "OUTER LOOP\nVERTEX 0 0 0\nVERTEX 0 1 0\nVERTEX 0 0 1\n"
                                                 "ENDLOOP\nENDFACET\nENDSOLID B\n");
  EXPECT_EQ(read_polygon_soup(two).faces, (Faces{{0, 1, 2}, {0, 2, 3}}));
  struct Case {
    std::string text, expect;
  } cases[] = {
      {"solid a\n" + edited(facet, "endloop", "endlop") + "endsolid a\n",
       "line 7: expected 'endloop', found 'endlop'"},
      {"solid a\n" + edited(facet, "normal", "normals") + "endsolid a\n",
       "line 2: expected 'normal', found 'normals'"},
      {"solid a\n" + edited(facet, "vertex 1 0 0", "vertex 1 0") + "endsolid a\n",
       "'vertex' is not a number"},
      {"solid a\n" + facet, "the file ends before 'endsolid': it is truncated"},
      {"solid a\n" + facet + "endsolid a\nrubbish\n",
       "expected 'solid' or the end of the file after 'endsolid'"},
  };
  for (const Case& c : cases) {
    const fs::path f = write_file("bad.stl", c.text);
    expect_names(read_error(f), f, {c.expect});
  }
  // A binary file whose header starts with "solid" is binary.
  std::string binary = binary_stl({{Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}}});
  binary.replace(0, 6, "solid ");
  EXPECT_EQ(read_polygon_soup(write_file("solid.stl", binary)).faces, (Faces{{0, 1, 2}}));
}

// Every file of the malformed-input corpus (tests/corpus) through the library, in the process
// (so that sanitizer builds check the readers on all of them): an InputError naming the file,
// for the mesh reader and, where the damage is at the reading level, the point-cloud reader.
TEST_F(VtkIo, CorpusFilesAreInputErrorsNamingTheFile) {
  const fs::path corpus = fs::path(RGBMESH_TEST_DATA_DIR).parent_path() / "corpus" / "files";
  std::ifstream manifest(corpus / "MANIFEST.tsv");
  std::string line;
  std::size_t files = 0;
  while (std::getline(manifest, line)) {
    const std::string name = line.substr(0, line.find('\t'));
    const fs::path file = corpus / name;
    const std::string ext = file.extension().string();
    const bool cloud_only = ext == ".xyz" || ext == ".pwn";
    if (!cloud_only) expect_names(read_error(file), file, {});
    if (line.find("fit") != std::string::npos) {
      // .xyz/.pwn errors name the line as "file:line: ...".
      const std::string message = input_error([&] { rgbmesh::read_point_cloud(file); });
      EXPECT_EQ(message.rfind(file.string() + ":", 0), 0u) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
    ++files;
  }
  EXPECT_GE(files, 150u);
}

}  // namespace
