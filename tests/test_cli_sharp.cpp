// Sharp features through the tool (issue 42): the note that a part's edges are rounded,
// --sharp-angle on info, refine, convert and adapt, OBJ tags written and read back, the sharp
// edges beside VTK outputs for ParaView, adapt --problem cube-cosine, and the refusals.

#include <gtest/gtest.h>

#include <vtkCellData.h>
#include <vtkPointData.h>

#include <string>

#include "cli_fixture.hpp"

namespace rgbmesh::testing {
namespace {

class CliSharp : public Cli {
 protected:
  // The unit cube as 12 triangles, no tags.
  std::string write_cube(const std::string& name) const {
    std::ofstream f(path(name));
    f << "OFF\n8 12 0\n";
    for (int i = 0; i < 8; ++i) f << (i & 1) << " " << ((i >> 1) & 1) << " " << ((i >> 2) & 1) << "\n";
    f << "3 0 2 3\n3 0 3 1\n3 4 5 7\n3 4 7 6\n3 0 1 5\n3 0 5 4\n3 2 6 7\n3 2 7 3\n3 0 4 6\n3 0 6 2\n3 1 3 7\n3 1 7 5\n";
    return path(name);
  }
};

TEST_F(CliSharp, APartWithoutItsEdgesGetsOneNoteNamingSharpAngle) {
  const std::string cube = write_cube("cube.off");
  const RunResult plain = run("info " + cube);
  EXPECT_EQ(plain.code, 0) << plain.err;
  EXPECT_NE(plain.err.find("the Loop limit surface lies"), std::string::npos) << plain.err;
  EXPECT_NE(plain.err.find("--sharp-angle 30"), std::string::npos) << plain.err;
  EXPECT_EQ(std::count(plain.err.begin(), plain.err.end(), '\n'), 1) << plain.err;
  const RunResult sharp = run("info " + cube + " --sharp-angle 30 --json");
  EXPECT_EQ(sharp.code, 0) << sharp.err;
  EXPECT_EQ(sharp.err.find("the Loop limit surface lies"), std::string::npos) << sharp.err;
  EXPECT_NE(sharp.err.find("12 crease edges"), std::string::npos) << sharp.err;
  EXPECT_NE(sharp.out.find("\"sharp_edges\": 12"), std::string::npos) << sharp.out;
  EXPECT_NE(sharp.out.find("\"corners\": 8"), std::string::npos) << sharp.out;
}

TEST_F(CliSharp, RefineKeepsTheCubeAndWritesItsEdgesBeside) {
  const std::string cube = write_cube("cube.off");
  const RunResult r = run("refine " + cube + " " + path("c.vtp") + " --uniform 3 --limit --sharp-angle 30");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto mesh = read_vtp(path("c.vtp"));
  ASSERT_NE(mesh->GetPointData()->GetArray("vertex_rule"), nullptr);
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i) {
    double p[3];
    mesh->GetPoint(i, p);
    double to_face = 1;
    for (double x : p) to_face = std::min({to_face, std::abs(x), std::abs(1 - x)});
    ASSERT_LE(to_face, 1e-12) << "point " << i << " is off the cube";
  }
  const auto lines = read_vtp(path("c.creases.vtp"));
  EXPECT_EQ(lines->GetNumberOfLines(), 12 * 8);  // each cube edge in 8 pieces at level 3
  ASSERT_NE(lines->GetCellData()->GetArray("sharpness"), nullptr);
  EXPECT_EQ(lines->GetCellData()->GetArray("sharpness")->GetRange()[0], 10.0);
  // The state keeps the features: info on the file counts the crease pieces.
  const RunResult info = run("info " + path("c.vtp") + " --json");
  EXPECT_NE(info.out.find("\"sharp_edges\": 96"), std::string::npos) << info.out;
}

TEST_F(CliSharp, ObjOutputsCarryTheTagsAndReadBackTheSame) {
  const std::string cube = write_cube("cube.off");
  ASSERT_EQ(run("refine " + cube + " " + path("c2.obj") + " --uniform 2 --sharp-angle 30").code, 0);
  const std::string obj = read_text(path("c2.obj"));
  EXPECT_NE(obj.find("t crease 2/1/0 "), std::string::npos);
  // The level-2 mesh read back as a base, refined once more, against the cube refined to 3.
  ASSERT_EQ(run("refine " + path("c2.obj") + " " + path("a.vtp") + " --uniform 1").code, 0);
  ASSERT_EQ(run("refine " + cube + " " + path("b.vtp") + " --uniform 3 --sharp-angle 30").code, 0);
  const auto a = read_vtp(path("a.vtp")), b = read_vtp(path("b.vtp"));
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  double lo_a[6], lo_b[6];
  a->GetBounds(lo_a);
  b->GetBounds(lo_b);
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(lo_a[k], lo_b[k], 1e-12);
  EXPECT_EQ(read_vtp(path("a.creases.vtp"))->GetNumberOfLines(), 12 * 8);
}

TEST_F(CliSharp, CubeCosineReportsItsExactErrorsAndTheCreasesAsPartOfTheSeries) {
  const RunResult r = run("adapt --problem cube-cosine --strategy uniform --cycles 3 --out " + path("run"));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string report = read_text(path("run/report.json"));
  EXPECT_NE(report.find("\"error_h1\""), std::string::npos);
  EXPECT_TRUE(fs::exists(path("run/cycle_002.creases.vtp")));
  const std::string pvd = read_text(path("run/solution.pvd"));
  EXPECT_NE(pvd.find("part=\"1\" file=\"cycle_002.creases.vtp\""), std::string::npos) << pvd;
}

TEST_F(CliSharp, AResumedRunWithSharpFeaturesIsTheUninterruptedOne) {
  const std::string cube = write_cube("cube.off");
  ASSERT_EQ(run("adapt --mesh " + cube + " --sharp-angle 30 --min-level 2 --cycles 7 --out " + path("whole")).code, 0);
  ASSERT_EQ(run("adapt --mesh " + cube + " --sharp-angle 30 --min-level 2 --cycles 4 --out " + path("part")).code, 0);
  const RunResult resumed = run("adapt --resume " + path("part") + " --cycles 7");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  // The last cycle's estimate (written with every digit) and mesh are the same.
  const std::string whole = read_text(path("whole/report.json")), part = read_text(path("part/report.json"));
  const auto last_estimate = [](const std::string& report) {
    const std::size_t at = report.rfind("\"estimate\": ");
    return report.substr(at, report.find_first_of(",}", at) - at);
  };
  EXPECT_EQ(last_estimate(whole), last_estimate(part));
  EXPECT_EQ(read_vtp(path("whole/cycle_006.vtp"))->GetNumberOfCells(), read_vtp(path("part/cycle_006.vtp"))->GetNumberOfCells());
  EXPECT_TRUE(fs::exists(path("part/cycle_006.creases.vtp")));
  EXPECT_NE(read_text(path("part/solution.pvd")).find("part=\"1\" file=\"cycle_001.creases.vtp\""), std::string::npos);
}

TEST_F(CliSharp, SharpAngleAndCubeCosineRefuseWhatTheyCannotDo) {
  const std::string cube = write_cube("cube.off");
  RunResult r = run("info " + cube + " --sharp-angle 180");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--sharp-angle"), std::string::npos) << r.err;
  r = run("adapt --problem cube-cosine --mesh " + cube + " --out " + path("x"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("cube-cosine is posed on the unit cube"), std::string::npos) << r.err;
  ASSERT_EQ(run("adapt --problem cube-cosine --cycles 1 --out " + path("y")).code, 0);
  r = run("adapt --resume " + path("y") + " --sharp-angle 30 --cycles 2");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--sharp-angle: does not apply with --resume"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace rgbmesh::testing
