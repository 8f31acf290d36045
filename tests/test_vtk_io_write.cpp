// Mesh files, writing: round trips through every output format, the XML arrays as VTK's readers
// see them, atomic writing (failures, limits, unwritable folders), ParaView collections.

#include "vtk_io_fixture.hpp"

namespace {

// ---------------------------------------------------------------------------------------------
// Writing

// Every output format read back gives the same triangles over the same points: exactly for
// OBJ, OFF, VTP and VTU, to single precision for PLY and STL (whose numbering STL does not keep).
TEST_F(VtkIo, EveryOutputFormatRoundTrips) {
  const MeshSnapshot m = grid_snapshot(4);
  for (const std::string ext : {".obj", ".off", ".ply", ".stl", ".vtp", ".vtu"}) {
    write_mesh(path("m" + ext), m);
    const TriangleMeshData back = read_mesh(path("m" + ext));
    EXPECT_TRUE(back.notes.empty()) << ext;
    ASSERT_EQ(back.points.size(), m.points.size()) << ext;
    ASSERT_EQ(back.triangles.size(), m.triangles.size()) << ext;
    const bool single = ext == ".ply" || ext == ".stl";
    // Through a volatile float: GCC 12.2 at -O2 drops the rounding of Vec3(float(x), float(y),
    // float(z)) in this loop (its SLP vectorizer; -fno-tree-slp-vectorize avoids it).
    const auto rounded = [](double v) {
      const volatile float f = static_cast<float>(v);
      return static_cast<double>(f);
    };
    if (ext != ".stl") {
      EXPECT_EQ(back.triangles, m.triangles) << ext;
    }
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const Vec3& p = m.points[m.triangles[t][k]];
        const Vec3 want = single ? Vec3(rounded(p.x), rounded(p.y), rounded(p.z)) : p;
        ASSERT_EQ(back.points[back.triangles[t][k]], want) << ext << " triangle " << t << " corner " << k;
      }
  }
  EXPECT_EQ(entries(dir_), (std::vector<std::string>{"m.obj", "m.off", "m.ply", "m.stl", "m.vtp", "m.vtu"}));
}

TEST_F(VtkIo, OffOutputIsPlainText) {
  MeshSnapshot m;
  m.points = {{0.1, 0, 0}, {1.0 / 3, 1, 0}, {-2, 0.5, 1e-20}};
  m.triangles = {{0, 1, 2}};
  write_mesh(path("t.off"), m);
  EXPECT_EQ(contents(path("t.off")), "OFF\n3 1 0\n0.1 0 0\n0.3333333333333333 1 0\n-2 0.5 1e-20\n3 0 1 2\n");
}

template <class Reader>
void check_xml_arrays(const fs::path& file, const MeshSnapshot& m) {
  vtkNew<Reader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  ASSERT_EQ(reader->GetErrorCode(), 0u);
  vtkDataSet* data = reader->GetOutputAsDataSet();
  ASSERT_EQ(data->GetNumberOfPoints(), static_cast<vtkIdType>(m.points.size()));
  ASSERT_EQ(data->GetNumberOfCells(), static_cast<vtkIdType>(m.triangles.size()));
  EXPECT_EQ(vtkPointSet::SafeDownCast(data)->GetPoints()->GetDataType(), VTK_DOUBLE);

  const auto uint8 = [](vtkDataSetAttributes* attributes, const char* name) {
    return vtkUnsignedCharArray::SafeDownCast(attributes->GetArray(name));
  };
  vtkUnsignedCharArray* point_level = uint8(data->GetPointData(), "level");
  vtkUnsignedCharArray* cell_level = uint8(data->GetCellData(), "level");
  vtkUnsignedCharArray* color = uint8(data->GetCellData(), "color");
  ASSERT_NE(point_level, nullptr);
  ASSERT_NE(cell_level, nullptr);
  ASSERT_NE(color, nullptr);
  for (std::size_t v = 0; v < m.points.size(); ++v) {
    double p[3];
    data->GetPoint(static_cast<vtkIdType>(v), p);
    EXPECT_EQ(Vec3(p[0], p[1], p[2]), m.points[v]);
    EXPECT_EQ(point_level->GetValue(static_cast<vtkIdType>(v)), m.vertex_level[v]);
  }
  vtkNew<vtkIdList> ids;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto c = static_cast<vtkIdType>(t);
    data->GetCellPoints(c, ids);
    ASSERT_EQ(ids->GetNumberOfIds(), 3);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(ids->GetId(k), m.triangles[t][k]);
    EXPECT_EQ(data->GetCellType(c), VTK_TRIANGLE);
    EXPECT_EQ(cell_level->GetValue(c), m.triangle_level[t]);
    EXPECT_EQ(color->GetValue(c), static_cast<unsigned char>(m.triangle_color[t]));
  }
  const auto check_named = [](vtkDataSetAttributes* attributes, const rgbmesh::NamedArray& a) {
    auto* array = vtkDoubleArray::SafeDownCast(attributes->GetArray(a.name.c_str()));
    ASSERT_NE(array, nullptr) << a.name;
    ASSERT_EQ(array->GetNumberOfComponents(), a.components) << a.name;
    ASSERT_EQ(array->GetNumberOfValues(), static_cast<vtkIdType>(a.values.size())) << a.name;
    for (std::size_t i = 0; i < a.values.size(); ++i)
      EXPECT_EQ(array->GetValue(static_cast<vtkIdType>(i)), a.values[i]);
  };
  check_named(data->GetPointData(), m.point_data.at(0));
  check_named(data->GetCellData(), m.cell_data.at(0));

  // Compressed (LZ4, the default), appended, raw binary: the header says so.
  std::ifstream in(file, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string header = text.substr(0, text.find("<AppendedData"));
  EXPECT_NE(header.find("compressor=\"vtkLZ4DataCompressor\""), std::string::npos) << header;
  EXPECT_NE(text.find("<AppendedData encoding=\"raw\">"), std::string::npos);
  EXPECT_EQ(header.find("format=\"ascii\""), std::string::npos);
  EXPECT_EQ(header.find("format=\"binary\""), std::string::npos);
  EXPECT_NE(header.find("format=\"appended\""), std::string::npos);
}

TEST_F(VtkIo, XmlOutputCarriesLevelsColorsAndArraysCompressed) {
  const MeshSnapshot m = grid_snapshot(3);
  write_mesh(path("m.vtp"), m);
  write_mesh(path("m.vtu"), m);
  check_xml_arrays<vtkXMLPolyDataReader>(path("m.vtp"), m);
  check_xml_arrays<vtkXMLUnstructuredGridReader>(path("m.vtu"), m);
}

TEST_F(VtkIo, BadOutputRequestsWriteNothing) {
  const MeshSnapshot m = grid_snapshot(1);
  const std::string message = input_error([&] { write_mesh(path("m.xyz"), m); });
  expect_names(message, path("m.xyz"), {"unknown output format '.xyz'"});
  MeshSnapshot broken = m;
  broken.triangles[1][2] = 17;
  EXPECT_THROW(write_mesh(path("m.vtp"), broken), std::invalid_argument);
  broken = m;
  broken.cell_data[0].values.pop_back();
  EXPECT_THROW(write_mesh(path("m.vtp"), broken), std::invalid_argument);
  EXPECT_TRUE(entries(dir_).empty());
}

// I/O failures are std::runtime_error (not InputError) naming the target, and leave nothing.
TEST_F(VtkIo, WritingWhereItIsImpossibleThrowsAndLeavesNoTemporary) {
  const MeshSnapshot m = grid_snapshot(1);
  write_file("file", "not a directory");
  for (const std::string ext : {".obj", ".off", ".ply", ".stl", ".vtp", ".vtu"}) {
    for (const fs::path& target : {path("missing/m" + ext), path("file/m" + ext)}) {
      try {
        write_mesh(target, m);
        ADD_FAILURE() << target << " was written";
      } catch (const InputError& e) {
        ADD_FAILURE() << "an I/O failure is not bad input: " << e.what();
      } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()).rfind(target.string() + ": cannot write: ", 0), 0u) << e.what();
      }
    }
  }
  EXPECT_THROW(rgbmesh::write_text_atomically(path("missing/a.json"), "{}"), std::runtime_error);
  EXPECT_EQ(entries(dir_), std::vector<std::string>{"file"});
}

TEST_F(VtkIo, WritingIntoAReadOnlyDirectoryThrows) {
  fs::create_directories(path("readonly"));
  fs::permissions(path("readonly"), fs::perms::owner_read | fs::perms::owner_exec);
  if (std::ofstream(path("readonly/probe")))
    GTEST_SKIP() << "running with permission to write anywhere (root)";
  EXPECT_THROW(write_mesh(path("readonly/m.vtp"), grid_snapshot(1)), std::runtime_error);
  EXPECT_TRUE(entries(path("readonly")).empty());
}

// A folder where no file can be created, even by root (/proc): every writer, VTK's included,
// reports the folder and the system's reason, not the name of a temporary file.
TEST_F(VtkIo, WritingWhereNoFileCanBeCreatedNamesTheFolderAndTheReason) {
  if (!fs::is_directory("/proc")) GTEST_SKIP() << "no /proc";
  for (const std::string ext : {".obj", ".off", ".ply", ".stl", ".vtp", ".vtu"}) {
    const fs::path target = "/proc/rgbmesh-test" + ext;
    try {
      write_mesh(target, grid_snapshot(1));
      ADD_FAILURE() << target << " was written";
    } catch (const rgbmesh::OutputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(target.string() + ": cannot write: cannot create a file in the folder /proc: "),
                std::string::npos)
          << message;
      EXPECT_EQ(message.find(".tmp-"), std::string::npos) << message;
    }
  }
}

// A write that fails part way (here: the file size limit is hit) leaves an existing target as
// it was and removes its temporary file.
TEST_F(VtkIo, FailedWriteLeavesTheTargetUntouched) {
  const MeshSnapshot big = grid_snapshot(60);
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  struct sigaction ignore {
  }, previous{};
  ignore.sa_handler = SIG_IGN;
  ASSERT_EQ(::sigaction(SIGXFSZ, &ignore, &previous), 0);  // writes past the limit fail with EFBIG
  for (const std::string ext : {".obj", ".off", ".ply", ".stl", ".vtp", ".vtu"}) {
    const fs::path target = write_file("old" + ext, "previous contents");
    rlimit limited = saved;
    limited.rlim_cur = 4096;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limited), 0);
    std::string error;
    try {
      write_mesh(target, big);
    } catch (const std::runtime_error& e) {
      error = e.what();
    }
    ::setrlimit(RLIMIT_FSIZE, &saved);
    EXPECT_EQ(error.rfind(target.string() + ": cannot write: ", 0), 0u) << ext << ": '" << error << "'";
    EXPECT_EQ(error.find("reader"), std::string::npos) << ext << ": a write failure is no reader's";
    EXPECT_EQ(contents(target), "previous contents") << ext;
    EXPECT_EQ(entries(dir_), std::vector<std::string>{"old" + ext}) << ext;
    fs::remove(target);
  }
  ::sigaction(SIGXFSZ, &previous, nullptr);
}

TEST_F(VtkIo, WritingReplacesAnExistingFile) {
  const MeshSnapshot m = grid_snapshot(2);
  write_file("m.vtp", "old");
  write_mesh(path("m.vtp"), m);
  EXPECT_EQ(read_mesh(path("m.vtp")).triangles, m.triangles);
  rgbmesh::write_text_atomically(path("r.json"), "{\"a\": 1}\n");
  rgbmesh::write_text_atomically(path("r.json"), "{\"a\": 2}\n");
  EXPECT_EQ(contents(path("r.json")), "{\"a\": 2}\n");
  EXPECT_EQ(entries(dir_), (std::vector<std::string>{"m.vtp", "r.json"}));
}

TEST_F(VtkIo, PvdListsTheTimeSeriesForParaView) {
  rgbmesh::write_pvd(path("series.pvd"),
                     {{0.0, "step_0.vtp"}, {0.25, "sub dir/step&1.vtp"}, {1e-3, "s\"2.vtu"}});
  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(path("series.pvd").c_str());
  ASSERT_EQ(parser->Parse(), 1);
  vtkXMLDataElement* root = parser->GetRootElement();
  ASSERT_NE(root, nullptr);
  EXPECT_STREQ(root->GetName(), "VTKFile");
  EXPECT_STREQ(root->GetAttribute("type"), "Collection");
  ASSERT_EQ(root->GetNumberOfNestedElements(), 1);
  vtkXMLDataElement* collection = root->GetNestedElement(0);
  EXPECT_STREQ(collection->GetName(), "Collection");
  ASSERT_EQ(collection->GetNumberOfNestedElements(), 3);
  const char* times[] = {"0", "0.25", "0.001"};
  const char* files[] = {"step_0.vtp", "sub dir/step&1.vtp", "s\"2.vtu"};
  for (int i = 0; i < 3; ++i) {
    vtkXMLDataElement* dataset = collection->GetNestedElement(i);
    EXPECT_STREQ(dataset->GetName(), "DataSet");
    EXPECT_STREQ(dataset->GetAttribute("timestep"), times[i]);
    EXPECT_STREQ(dataset->GetAttribute("file"), files[i]);
  }
  EXPECT_THROW(rgbmesh::write_pvd(path("bad.pvd"), {{std::nan(""), "a.vtp"}}), std::invalid_argument);
  EXPECT_EQ(entries(dir_), std::vector<std::string>{"series.pvd"});
}

}  // namespace
