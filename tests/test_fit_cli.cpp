// `rgbmesh fit` as a user runs it: point clouds and meshes that failed before (issue 9), the
// files it writes (targets.vtp's distances are the report's figures; limit_surface.vtp's cell
// data), the report's stages, one-line errors with exit code 2, and the output-folder rule.

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include "cli_fixture.hpp"
#include "public_data.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh::testing {
namespace {

// The number after "key": in a JSON text (the first occurrence after `from`).
double json_number(const std::string& json, const std::string& key, std::size_t from = 0) {
  const auto p = json.find("\"" + key + "\": ", from);
  EXPECT_NE(p, std::string::npos) << key << " in " << json;
  return p == std::string::npos ? NAN : std::stod(json.substr(p + key.size() + 4));
}

class FitCli : public Cli {
 protected:
  // Fibonacci points on a sphere of radius 2 as "x y z" lines: a cloud without normals.
  std::string write_sphere_cloud(const std::string& name, int n) const {
    std::ofstream f(path(name));
    f.precision(17);
    const double golden = M_PI * (3 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
      const double z = 1 - (2 * i + 1.0) / n, r = std::sqrt(1 - z * z);
      f << 2 * r * std::cos(golden * i) << " " << 2 * r * std::sin(golden * i) << " " << 2 * z << "\n";
    }
    return path(name);
  }
};

TEST_F(FitCli, PointCloudTargetsVtpHoldsTheReportedDistances) {
  const std::string cloud = write_sphere_cloud("sphere.xyz", 2000);
  const RunResult r = run("fit --target " + cloud + " --out " + path("f") + " --report " + path("f.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* file :
       {"base.obj", "fitted_base.obj", "limit_surface.vtp", "initial_limit_surface.vtp", "targets.vtp"})
    EXPECT_TRUE(fs::exists(path("f") + "/" + file)) << file;

  const vtkSmartPointer<vtkPolyData> targets = read_vtp(path("f/targets.vtp"));
  ASSERT_EQ(targets->GetNumberOfPoints(), 2000);
  EXPECT_EQ(targets->GetNumberOfVerts(), 2000);
  vtkDataArray* distance = targets->GetPointData()->GetArray("distance");
  ASSERT_NE(distance, nullptr);
  double sum = 0, max = 0;
  for (vtkIdType i = 0; i < distance->GetNumberOfTuples(); ++i) {
    const double d = distance->GetComponent(i, 0);
    sum += d * d;
    max = std::max(max, d);
  }
  const std::string report = read_text(path("f.json"));
  const std::size_t top = report.find("\"iterations\": [");
  const std::size_t after_iterations = report.find("]", top);
  EXPECT_DOUBLE_EQ(std::sqrt(sum / 2000), json_number(report, "rms", after_iterations));
  EXPECT_DOUBLE_EQ(max, json_number(report, "max", after_iterations));
  const double diagonal = json_number(report, "diagonal", after_iterations);
  EXPECT_NEAR(diagonal, 4 * std::sqrt(3.0), 0.01);
  EXPECT_LT(std::sqrt(sum / 2000), 1e-3 * diagonal);

  // The stages.
  EXPECT_NE(report.find("\"source\": \"reconstructed\""), std::string::npos) << report;
  EXPECT_EQ(json_number(report, "faces", report.find("\"base\"")), 1000);
  EXPECT_EQ(json_number(report, "genus", report.find("\"base\"")), 0);
  EXPECT_GT(json_number(report, "reconstruction_seconds"), 0);
  EXPECT_GT(json_number(report, "decimation_seconds"), 0);
  EXPECT_NE(report.find("\"notes\": [\"reconstructed a surface of "), std::string::npos) << report;
  EXPECT_NE(report.find("\"normals\": false"), std::string::npos) << report;

  // The limit surface: per triangle, the targets whose closest point is in it and their RMS
  // distance; no per-vertex "distance" (it was to the nearest target, the sample spacing).
  const vtkSmartPointer<vtkPolyData> limit = read_vtp(path("f/limit_surface.vtp"));
  EXPECT_EQ(limit->GetNumberOfPolys(), 1000 * 64);
  EXPECT_EQ(limit->GetPointData()->GetArray("distance"), nullptr);
  vtkDataArray* counts = limit->GetCellData()->GetArray("targets");
  vtkDataArray* rms = limit->GetCellData()->GetArray("rms_distance");
  ASSERT_NE(counts, nullptr);
  ASSERT_NE(rms, nullptr);
  double counted = 0, squares = 0;
  for (vtkIdType t = 0; t < counts->GetNumberOfTuples(); ++t) {
    counted += counts->GetComponent(t, 0);
    squares += counts->GetComponent(t, 0) * rms->GetComponent(t, 0) * rms->GetComponent(t, 0);
  }
  EXPECT_EQ(counted, 2000);
  EXPECT_NEAR(squares, sum, 1e-9 * sum);
}

TEST_F(FitCli, TheMeshesOfTheIssueFitWithDefaultOptions) {
  // Before: "edge (32, 33) is shared by 4 triangles" (VTK's decimation of the cow) and "vertex
  // 191 is non-manifold" (of the elephant with holes).
  for (const std::string file : {"cow.off", "elephant-with-holes.off"}) {
    const RunResult r = run("fit --target " + public_data(file) + " --out " + path(file) + " --report " +
                            path(file + ".json"));
    ASSERT_EQ(r.code, 0) << file << ": " << r.err;
    const std::string report = read_text(path(file + ".json"));
    EXPECT_NE(report.find("\"source\": \"decimated\""), std::string::npos) << report;
    EXPECT_EQ(json_number(report, "faces", report.find("\"base\"")), 1000) << file;
    EXPECT_LT(json_number(report, "rms_relative"), 0.003) << file;
    const auto base = rgbmesh::read_mesh(path(file) + "/base.obj");
    EXPECT_EQ(base.triangles.size(), 1000u);
  }
}

TEST_F(FitCli, MalformedCloudsAreOneLineErrorsWithExitCode2) {
  std::ofstream(path("bad.xyz")) << "0 0 0\n1 2 x\n";
  std::ofstream(path("empty.xyz")) << "";
  std::ofstream(path("garbage.vtp"))
      << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\"><PolyData><Piece Num";
  const std::pair<std::string, std::string> cases[] = {{"bad.xyz", "bad.xyz:2: 'x' is not a number"},
                                                       {"empty.xyz", "empty.xyz: no points"},
                                                       {"garbage.vtp", "garbage.vtp: cannot read: "},
                                                       {"none.xyz", "none.xyz: file does not exist"}};
  for (const auto& [file, message] : cases) {
    const RunResult r = run("fit --target " + path(file) + " --out " + path("g"));
    EXPECT_EQ(r.code, 2) << file << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << file << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << file << ": " << r.err;
    EXPECT_FALSE(fs::exists(path("g"))) << file;  // nothing written before the input is read
  }
}

TEST_F(FitCli, ARunRemovesThePreviousRunsOutputsOnly) {
  fs::create_directories(path("f"));
  std::ofstream(path("f/cycle_003.vtp")) << "old";
  std::ofstream(path("f/mine.txt")) << "keep";
  const RunResult r = run("fit --target " + std::string(RGBMESH_DATA_DIR) +
                          "/bunny.obj --base-faces 400 --levels 2 "
                          "--out " +
                          path("f"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(path("f/cycle_003.vtp")));
  EXPECT_TRUE(fs::exists(path("f/mine.txt")));
  EXPECT_TRUE(fs::exists(path("f/targets.vtp")));
}

}  // namespace
}  // namespace rgbmesh::testing
