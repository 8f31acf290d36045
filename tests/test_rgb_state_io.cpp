// The RGB state in VTK XML files: what write_mesh writes for .vtp and .vtu, read_rgb_mesh
// restores exactly; files without it read as base meshes; edited files are refused with the
// file's name and what is wrong; and the tool's info and refine use it.

#include <gtest/gtest.h>

#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <set>
#include <sstream>

#include "rgbmesh/refinement.hpp"
#include "rgbmesh/vtk_io.hpp"
#include "test_meshes.hpp"

namespace rgbmesh {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("rgbmesh_state_io_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

// Handle-independent identity: base vertices by index, others by their parents' identities.
class Keys {
 public:
  std::int64_t operator()(const RgbMesh& m, VertexHandle v) {
    if (m.level(v) == 0) return v.idx;
    std::int64_t a = (*this)(m, m.parents(v)[0]), b = (*this)(m, m.parents(v)[1]);
    if (a > b) std::swap(a, b);
    return ids_.try_emplace({a, b}, static_cast<std::int64_t>(ids_.size()) + (1 << 30)).first->second;
  }

 private:
  std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> ids_;
};

using Described = std::set<std::array<std::int64_t, 5>>;  // corners, level, colour
Described describe(const RgbMesh& m, Keys& keys) {
  Described out;
  for (TriangleHandle t : m.triangles()) {
    const auto c = m.triangle_vertices(t);
    std::array<std::int64_t, 3> k{keys(m, c[0]), keys(m, c[1]), keys(m, c[2])};
    std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
    out.insert({k[0], k[1], k[2], m.level(t), static_cast<std::int64_t>(m.color(t))});
  }
  return out;
}

class StateFile : public ::testing::TestWithParam<const char*> {};

TEST_P(StateFile, RoundTripAfterRandomWalks) {
  const fs::path dir = temp_dir();
  for (const auto& base : {testing::double_torus(), testing::grid_with_holes(6, 2), testing::icosahedron(),
                           testing::graded_icosahedron(CreaseMethod::chaikin), testing::sharp_cube()}) {
    RgbMesh m = base.build();
    random_walk(m, 1500, 3);
    const fs::path file = dir / (base.name + GetParam());
    write_mesh(file, snapshot_for_file(m, file));
    RgbMeshFile r = read_rgb_mesh(file);
    ASSERT_TRUE(r.restored);
    ASSERT_EQ(r.mesh.validate(true), "");
    Keys keys;
    EXPECT_EQ(describe(r.mesh, keys), describe(m, keys)) << base.name;
    EXPECT_EQ(r.mesh.sharp_features(), m.sharp_features()) << base.name;
    std::map<std::int64_t, VertexHandle> by_key;
    for (VertexHandle v : m.vertices()) by_key[keys(m, v)] = v;
    r.mesh.compute_limits();
    for (VertexHandle w : r.mesh.vertices()) {
      const VertexHandle v = by_key.at(keys(r.mesh, w));
      EXPECT_LE(norm(r.mesh.control_point(w) - m.control_point(v)), 1e-12 * std::max(1.0, norm(m.control_point(v))));
      EXPECT_LE(norm(r.mesh.limit_position(w) - m.limit_position(v)), 1e-12 * std::max(1.0, norm(m.limit_position(v))));
    }
    // Coarsening everything returns the base exactly.
    selective_refinement(r.mesh, CoarsenAll());
    EXPECT_EQ(testing::canonical_triangles(r.mesh), testing::canonical_triangles(base.build()));
    std::vector<Vec3> points;
    for (VertexHandle v : r.mesh.vertices()) points.push_back(r.mesh.insertion_point(v));
    EXPECT_EQ(points, base.points);
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Formats, StateFile, ::testing::Values(".vtp", ".vtu"),
                         [](const auto& p) { return std::string(p.param + 1); });

std::string bytes_of_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// write_rgb_mesh (what the tool writes) computes VTK XML files from the mesh block by block; the
// file must be the snapshot's, byte for byte: on meshes with and without free slots, with
// boundaries and genus, with arrays of many blocks whose boundaries fall inside tuples and
// triangles, in every compression, with control or limit points. (The snapshot's files are
// read back bit-exactly by VTK's readers in test_vtk_write.)
TEST(StateFile, StreamedFromTheMeshIsTheSnapshotsFileByteForByte) {
  const fs::path dir = temp_dir();
  struct Case {
    std::string name;
    RgbMesh mesh;
  };
  std::vector<Case> cases;
  // Removals free slots (later insertions take them again): every third removable vertex.
  const auto remove_some = [](RgbMesh& m) {
    std::vector<VertexHandle> vertices(m.vertices().begin(), m.vertices().end());
    int k = 0;
    for (const VertexHandle v : vertices)
      if (m.alive(v) && m.is_removable(v) && ++k % 3 == 0) m.remove_vertex(v);
  };
  RgbMesh uniform = testing::double_torus().build();
  selective_refinement(uniform, UniformLevel(4));
  cases.push_back({"double torus, level 4", std::move(uniform)});
  RgbMesh holes = testing::grid_with_holes(6, 2).build();
  selective_refinement(holes, UniformLevel(3));
  random_walk(holes, 4000, 11);
  remove_some(holes);
  cases.push_back({"grid with two holes, level 3, random walk", std::move(holes)});
  RgbMesh creased = testing::graded_icosahedron(CreaseMethod::chaikin).build();
  random_walk(creased, 1500, 5);
  cases.push_back({"icosahedron with Chaikin creases, random walk", std::move(creased)});
  RgbMesh walked = testing::icosahedron().build();
  random_walk(walked, 1500, 3);
  cases.push_back({"icosahedron, random walk", std::move(walked)});
  std::set<bool> free_slots;
  for (Case& c : cases) {
    free_slots.insert(static_cast<std::size_t>(c.mesh.vertex_slots()) != c.mesh.num_vertices() ||
                      static_cast<std::size_t>(c.mesh.triangle_slots()) != c.mesh.num_triangles());
    for (const char* ext : {".vtp", ".vtu"})
      for (const Compression compression : {Compression::lz4, Compression::zlib, Compression::none})
        for (const bool limit_points : {false, true}) {
          SCOPED_TRACE(c.name + " " + ext + " " + compression_name(compression) + (limit_points ? " limit" : " control"));
          WriteOptions options;
          options.compression = compression;
          const fs::path streamed = dir / (std::string("streamed") + ext), snapshot = dir / (std::string("snapshot") + ext);
          write_rgb_mesh(streamed, c.mesh, options, limit_points);
          write_mesh(snapshot, snapshot_for_file(c.mesh, snapshot, limit_points), options);
          const std::string a = bytes_of_file(streamed), b = bytes_of_file(snapshot);
          ASSERT_GT(a.size(), 1000u);
          ASSERT_TRUE(a == b) << "the files differ at byte "
                              << std::mismatch(a.begin(), a.end(), b.begin(), b.end()).first - a.begin();
        }
  }
  EXPECT_EQ(free_slots, (std::set<bool>{false, true})) << "both kinds of mesh are covered";
  EXPECT_GT(3 * 4 * cases.front().mesh.num_triangles(), 8 * 32768u) << "the connectivity spans many blocks";
  // And what it writes is read back as the same mesh.
  RgbMeshFile r = read_rgb_mesh(dir / "streamed.vtu");
  ASSERT_TRUE(r.restored);
  ASSERT_EQ(r.mesh.validate(true), "");
  Keys keys;
  EXPECT_EQ(describe(r.mesh, keys), describe(cases.back().mesh, keys));
  fs::remove_all(dir);
}

TEST(StateFile, FileWithoutStateIsABaseMesh) {
  const fs::path dir = temp_dir();
  RgbMesh m = testing::torus(6, 5).build();
  selective_refinement(m, UniformLevel(1));
  write_mesh(dir / "plain.vtp", m.snapshot());  // no state: a snapshot not made for a file
  RgbMeshFile r = read_rgb_mesh(dir / "plain.vtp");
  EXPECT_FALSE(r.restored);
  EXPECT_EQ(r.mesh.num_vertices(), m.num_vertices());
  EXPECT_EQ(r.mesh.max_level(), 0);
  write_mesh(dir / "m.obj", snapshot_for_file(m, dir / "m.obj"));
  EXPECT_FALSE(read_rgb_mesh(dir / "m.obj").restored);
  fs::remove_all(dir);
}

// Reads a .vtp with VTK, lets `edit` change it, writes it back (ASCII, so that nothing hides).
void edit_file(const fs::path& file, const std::function<void(vtkPolyData&)>& edit) {
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkPolyData* data = reader->GetOutput();
  edit(*data);
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetDataModeToAscii();
  writer->SetInputData(data);
  writer->SetFileName(file.c_str());
  ASSERT_EQ(writer->Write(), 1);
}

std::string refusal(const fs::path& file) {
  try {
    read_rgb_mesh(file);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

class EditedFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = temp_dir();
    file = dir / "edited.vtp";
    mesh = testing::grid_with_holes(6, 2).build();
    random_walk(mesh, 1500, 21);
    write_mesh(file, snapshot_for_file(mesh, file));
    ASSERT_EQ(refusal(file), "");
  }
  void TearDown() override { fs::remove_all(dir); }
  void expect_refused(const std::string& what) {
    const std::string m = refusal(file);
    EXPECT_EQ(m.rfind(file.string() + ": inconsistent RGB state: ", 0), 0u) << m;
    EXPECT_NE(m.find(what), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  // The last inserted point that no other point has as a parent.
  static vtkIdType leaf(vtkPolyData& d) {
    vtkDataArray* parents = d.GetPointData()->GetArray("rgb_parents");
    std::vector<char> is_parent(static_cast<std::size_t>(d.GetNumberOfPoints()), 0);
    for (vtkIdType i = 0; i < d.GetNumberOfPoints(); ++i)
      for (int c = 0; c < 2; ++c)
        if (parents->GetComponent(i, c) >= 0) is_parent[static_cast<std::size_t>(parents->GetComponent(i, c))] = 1;
    for (vtkIdType i = d.GetNumberOfPoints() - 1; i >= 0; --i)
      if (parents->GetComponent(i, 0) >= 0 && !is_parent[static_cast<std::size_t>(i)]) return i;
    return -1;
  }
  fs::path dir, file;
  RgbMesh mesh;
};

TEST_F(EditedFile, ChangedParent) {
  edit_file(file, [](vtkPolyData& d) {
    vtkDataArray* parents = d.GetPointData()->GetArray("rgb_parents");
    const vtkIdType k = leaf(d);
    parents->SetComponent(k, 1, parents->GetComponent(k, 0) == 0 ? 1 : 0);
  });
  expect_refused("point ");
}

TEST_F(EditedFile, ChangedLevel) {
  edit_file(file, [](vtkPolyData& d) {
    vtkDataArray* level = d.GetPointData()->GetArray("level");
    level->SetComponent(leaf(d), 0, level->GetComponent(leaf(d), 0) + 1);
  });
  expect_refused("has level");
}

TEST_F(EditedFile, SwappedTriangle) {
  edit_file(file, [](vtkPolyData& d) {
    vtkNew<vtkIdList> ids;
    d.GetPolys()->GetCellAtId(5, ids);
    const vtkIdType swapped[3] = {ids->GetId(1), ids->GetId(0), ids->GetId(2)};
    d.GetPolys()->ReplaceCellAtId(5, 3, swapped);
  });
  expect_refused("triangle 5 ");
}

TEST_F(EditedFile, ChangedBasePoints) {
  edit_file(file, [](vtkPolyData& d) {
    vtkDataArray* base = d.GetFieldData()->GetArray("rgb_base_points");
    base->SetComponent(4, 2, base->GetComponent(4, 2) + 0.5);
  });
  expect_refused("edited base points");
}

// Points are what ParaView shows and what a user edits; the state alone gives the mesh, so
// an edit used to be dropped without a word.
void edit_points(const fs::path& file, const std::function<Vec3(vtkIdType, const Vec3&)>& move, bool single = false) {
  edit_file(file, [&](vtkPolyData& d) {
    vtkNew<vtkPoints> points;
    if (single) points->SetDataTypeToFloat();
    for (vtkIdType i = 0; i < d.GetNumberOfPoints(); ++i) {
      double p[3];
      d.GetPoint(i, p);
      const Vec3 q = move(i, Vec3(p[0], p[1], p[2]));
      points->InsertNextPoint(q.x, q.y, q.z);
    }
    d.SetPoints(points);
  });
}

TEST_F(EditedFile, MovedPoint) {
  edit_points(file, [](vtkIdType i, const Vec3& p) { return i == 17 ? p + Vec3(0, 0, 1e-3) : p; });
  expect_refused("point 17: its position (Points) is 0.001 away from where the state puts it");
}

TEST_F(EditedFile, ScaledPoints) {
  edit_points(file, [](vtkIdType, const Vec3& p) { return 2.0 * p; });
  expect_refused(": its position (Points) is ");
}

TEST_F(EditedFile, PointsStoredInSinglePrecisionAreNoEdit) {
  // Float32 Points (a file saved again by another tool) are the positions rounded: accepted.
  // A move far above the rounding is not.
  edit_points(file, [](vtkIdType, const Vec3& p) { return p; }, true);
  EXPECT_EQ(refusal(file), "");
  edit_points(file, [](vtkIdType i, const Vec3& p) { return i == 3 ? p + Vec3(1e-4, 0, 0) : p; }, true);
  expect_refused("point 3: its position (Points)");
}

TEST_F(EditedFile, LimitPointsAreNoEdit) {
  // Points at the limit positions (refine --limit) are what rgbmesh writes too.
  write_mesh(file, snapshot_for_file(mesh, file, true));
  EXPECT_EQ(refusal(file), "");
  edit_points(file, [](vtkIdType i, const Vec3& p) { return i == 40 ? p + Vec3(0, 1e-3, 0) : p; });
  expect_refused("point 40: its position (Points)");
}

TEST_F(EditedFile, MissingArrayAndBadValues) {
  edit_file(file, [](vtkPolyData& d) { d.GetPointData()->RemoveArray("rgb_base_vertex"); });
  expect_refused("the array 'rgb_base_vertex' is missing");
  SetUp();
  edit_file(file, [](vtkPolyData& d) { d.GetPointData()->GetArray("rgb_parents")->SetComponent(0, 0, -5); });
  expect_refused("is -5, not an integer from -1 to");
  SetUp();
  edit_file(file, [](vtkPolyData& d) { d.GetFieldData()->GetArray("rgb_state_version")->SetComponent(0, 0, 7); });
  expect_refused("version 7 is not supported");
}

// The tool: info reports the saved levels, refine continues and coarsens back to the base, an
// edited file is one line and exit code 2.
std::string run(const std::string& args, int* code) {
  const fs::path out = temp_dir() / "cli_output.txt";
  const int status = std::system((std::string(RGBMESH_CLI) + " " + args + " > " + out.string() + " 2>&1").c_str());
  *code = WEXITSTATUS(status);
  std::ifstream in(out);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(StateCli, InfoAndRefineUseTheState) {
  const fs::path dir = temp_dir();
  const std::string bunny = std::string(RGBMESH_DATA_DIR) + "/bunny.obj";
  const std::string a = (dir / "a.vtp").string(), b = (dir / "b.vtu").string(), c = (dir / "c.vtp").string();
  int code = 0;
  run("refine " + bunny + " " + a + " --random-walk 3000,9", &code);
  ASSERT_EQ(code, 0);
  std::string info = run("info --json " + a, &code);
  ASSERT_EQ(code, 0) << info;
  EXPECT_EQ(info.find("\"max_level\": 0"), std::string::npos) << info;
  // Continue: one more stage, then everything back to the base.
  run("refine " + a + " " + b + " --random-walk 500,10", &code);
  ASSERT_EQ(code, 0);
  const std::string stats = run("refine " + b + " " + c + " --coarsen-all --stats", &code);
  ASSERT_EQ(code, 0) << stats;
  EXPECT_EQ(stats.find("\"removals\": 0,"), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"max_level\": 0"), std::string::npos) << stats;
  const std::string base_info = run("info --json " + bunny, &code), coarse_info = run("info --json " + c, &code);
  const auto counts = [](const std::string& json) { return json.substr(json.find("\"vertices\""), 60); };
  EXPECT_EQ(counts(coarse_info), counts(base_info));
  // An edited state: one line naming the file, exit code 2.
  edit_file(a, [](vtkPolyData& d) { d.GetPointData()->GetArray("rgb_parents")->SetComponent(d.GetNumberOfPoints() - 1, 0, 0); });
  const std::string refused = run("info " + a, &code);
  EXPECT_EQ(code, 2) << refused;
  EXPECT_NE(refused.find(a + ": inconsistent RGB state: "), std::string::npos) << refused;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rgbmesh
