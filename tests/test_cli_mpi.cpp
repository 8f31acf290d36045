// `mpirun -np P rgbmesh adapt` (issue 13): for P = 2, 3 and 4 (oversubscribed on two cores),
// the same run as one process with the same options gives the same mesh in every cycle (the
// same unknowns and triangles, the final mesh's triangles by their corners' positions) and the
// same estimates and errors within the solver's tolerance: sphere-peak above --min-level 2, a
// Gaussian source on a torus with a hole (boundary and genus), and the moving peak with
// coarsening. Each process computes the estimates and errors of its own triangles only (the
// others' arrive by messages), so equal estimates also check that exchange; the report counts
// the bytes sent, the coarsening rounds and the exchanges. Skipped, with a message, where the
// build has no MPI.

#include <vtkCellType.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPPolyDataReader.h>
#include <vtkXMLPUnstructuredGridReader.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>

#include "cli_fixture.hpp"
#include "cli_reports.hpp"
#include "test_meshes.hpp"

namespace {

using namespace rgbmesh::testing;

vtkSmartPointer<vtkPolyData> read_pvtp(const std::string& file) {
  auto reader = vtkSmartPointer<vtkXMLPPolyDataReader>::New();
  reader->SetFileName(file.c_str());
  reader->Update();
  return reader->GetOutput();
}

class Mpi : public Cli {
 protected:
  void SetUp() override {
    Cli::SetUp();
    if (std::string(RGBMESH_MPIEXEC).empty()) GTEST_SKIP() << "built without MPI (Debian: openmpi-bin, libopenmpi-dev)";
    // Open MPI refuses to start as root (CI machines, containers) unless told.
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  }
  RunResult run_on(int processes, const std::string& args) const {
    return run_with(std::string(RGBMESH_MPIEXEC) + " --oversubscribe -np " + std::to_string(processes) + " " +
                    RGBMESH_CLI, args);
  }
  // The run on one process and on 2, 3 and 4: the same cycles and the same final mesh.
  // removals: the serial run must remove vertices (a run that coarsens).
  void expect_same_runs(const std::string& args, const std::string& last, bool whole_mesh = false,
                        bool removals = false) {
    const std::string serial = path("serial");
    const RunResult one = run(args + " --out " + serial);
    ASSERT_EQ(one.code, 0) << one.err;
    const JsonValue a = report_of(serial);
    if (removals) {
      double removed = 0;
      for (const Cycle& c : cycles_of(a)) removed += c.removals;
      EXPECT_GT(removed, 100.0) << "the serial run hardly coarsens";
    }
    for (int p : {2, 3, 4}) {
      const std::string dir = path("p" + std::to_string(p));
      const RunResult many = run_on(p, args + " --out " + dir);
      ASSERT_EQ(many.code, 0) << p << " processes: " << many.err;
      const JsonValue b = report_of(dir);
      const std::vector<Cycle> ca = cycles_of(a), cb = cycles_of(b);
      ASSERT_EQ(ca.size(), cb.size()) << p << " processes";
      ASSERT_GE(ca.size(), 6u);
      double rounds = 0;
      for (std::size_t i = 0; i < ca.size(); ++i) {
        EXPECT_EQ(ca[i].dofs, cb[i].dofs) << p << " processes, cycle " << i;
        EXPECT_EQ(ca[i].triangles, cb[i].triangles) << p << " processes, cycle " << i;
        EXPECT_EQ(ca[i].removals, cb[i].removals) << p << " processes, cycle " << i;
        EXPECT_NEAR(ca[i].estimate, cb[i].estimate, 1e-7 * ca[i].estimate) << p << " processes, cycle " << i;
        if (std::isfinite(ca[i].error_h1)) {
          EXPECT_NEAR(ca[i].error_h1, cb[i].error_h1, 1e-7 * ca[i].error_h1) << p << " processes, cycle " << i;
        }
        // The bytes sent: none by one process; on several, at least the estimates, which each
        // process sends for its own triangles (two numbers each: η_T² and its geometric part);
        // all processes' bytes at least the most by one and at most p times it.
        EXPECT_EQ(ca[i].bytes_sent, 0.0) << "cycle " << i;
        EXPECT_GE(cb[i].bytes_sent, 16.0 * static_cast<double>(cb[i].triangles))
            << p << " processes, cycle " << i;
        EXPECT_GE(cb[i].bytes_sent, cb[i].bytes_sent_largest) << p << " processes, cycle " << i;
        EXPECT_LE(cb[i].bytes_sent, p * cb[i].bytes_sent_largest) << p << " processes, cycle " << i;
        // The coarsening rounds and the exchanges: none on one process; on several, every
        // cycle exchanges (its parts are decided together), and a cycle whose adaptation
        // removed vertices took at least one round, one that removed none took none. (Each
        // process counts its own; the run stops with an error where they differ, so a run
        // that ended normally had the same counts on every process.) The first report of a
        // moving peak also counts the settling's rounds, whose removals it does not report.
        EXPECT_EQ(ca[i].coarsening_rounds, 0.0) << "cycle " << i;
        EXPECT_EQ(ca[i].exchanges, 0.0) << "cycle " << i;
        ASSERT_TRUE(std::isfinite(cb[i].coarsening_rounds)) << p << " processes, cycle " << i << ": no coarsening_rounds";
        EXPECT_GE(cb[i].exchanges, 1.0) << p << " processes, cycle " << i;
        if (cb[i].removals > 0) {
          EXPECT_GE(cb[i].coarsening_rounds, 1.0) << p << " processes, cycle " << i;
        } else if (i > 0) {
          EXPECT_EQ(cb[i].coarsening_rounds, 0.0) << p << " processes, cycle " << i;
        }
        rounds += cb[i].coarsening_rounds;
      }
      if (removals) {
        EXPECT_GE(rounds, 2.0) << p << " processes: a run that coarsens in every cycle takes rounds";
      }
      // Every cycle's system was solved on all processes (the distributed multigrid).
      const std::string text = read_text(dir + "/report.json");
      std::size_t distributed = 0;
      for (std::size_t at = text.find("\"solver\": \"amg\""); at != std::string::npos;
           at = text.find("\"solver\": \"amg\"", at + 1))
        ++distributed;
      EXPECT_GE(distributed, ca.size()) << p << " processes";
      // The whole mesh is written only where every process holds it (runs that coarsen); a
      // distributed mesh's cycles are the pieces alone.
      EXPECT_EQ(fs::exists(dir + "/" + last + ".vtp"), whole_mesh) << p << " processes";
      if (whole_mesh) {
        EXPECT_EQ(triangles_of(serial + "/" + last + ".vtp"), triangles_of(dir + "/" + last + ".vtp")) << p << " processes";
      }
      // The pieces: the summary joins them into the serial mesh, each triangle once, with a
      // "rank" array naming every process; the series lists the summaries.
      const vtkSmartPointer<vtkPolyData> joined = read_pvtp(dir + "/" + last + ".pvtp");
      const std::array<std::size_t, 2> differing = triangles_differing(read_vtp(serial + "/" + last + ".vtp"), joined);
      EXPECT_EQ(differing[0], 0u) << p << " processes: triangles the serial run does not have";
      EXPECT_EQ(differing[1], 0u) << p << " processes: triangles of the serial run missing";
      EXPECT_EQ(joined->GetNumberOfCells(), read_vtp(serial + "/" + last + ".vtp")->GetNumberOfCells());
      vtkDataArray* rank = joined->GetCellData()->GetArray("rank");
      ASSERT_NE(rank, nullptr);
      std::set<int> ranks;
      for (vtkIdType c = 0; c < rank->GetNumberOfTuples(); ++c) ranks.insert(static_cast<int>(rank->GetTuple1(c)));
      EXPECT_EQ(ranks.size(), static_cast<std::size_t>(p));
      EXPECT_NE(read_text(dir + "/solution.pvd").find(last + ".pvtp"), std::string::npos);
      // Balance: in every cycle, the most triangles on one process at most 1.2 times the mean
      // (the partition is made anew each cycle, weighted by the triangles of each unit).
      std::size_t summaries = 0;
      for (const auto& entry : fs::directory_iterator(dir)) {
        if (entry.path().extension() != ".pvtp") continue;
        ++summaries;
        const vtkSmartPointer<vtkPolyData> cycle = read_pvtp(entry.path().string());
        vtkDataArray* owner = cycle->GetCellData()->GetArray("rank");
        ASSERT_NE(owner, nullptr) << entry.path();
        std::vector<double> count(static_cast<std::size_t>(p), 0.0);
        for (vtkIdType c = 0; c < owner->GetNumberOfTuples(); ++c) count[static_cast<std::size_t>(owner->GetTuple1(c))] += 1;
        const double mean = static_cast<double>(owner->GetNumberOfTuples()) / p;
        EXPECT_LE(*std::max_element(count.begin(), count.end()), 1.2 * mean) << entry.path();
      }
      EXPECT_EQ(summaries, ca.size()) << p << " processes";
    }
  }
};

TEST_F(Mpi, SpherePeakAboveAFloorIsTheSerialRun) {
  expect_same_runs("adapt --min-level 2 --cycles 12", "cycle_011");
}

TEST_F(Mpi, AGaussianOnATorusWithAHoleIsTheSerialRun) {
  // The torus less two adjacent triangles: one boundary loop, genus 1.
  const BaseMesh torus = rgbmesh::testing::torus(12, 8);
  std::ofstream obj(path("holed_torus.obj"));
  for (const auto& p : torus.points) obj << "v " << p.x << " " << p.y << " " << p.z << "\n";
  for (std::size_t t = 2; t < torus.triangles.size(); ++t)
    obj << "f " << torus.triangles[t][0] + 1 << " " << torus.triangles[t][1] + 1 << " " << torus.triangles[t][2] + 1 << "\n";
  obj.close();
  expect_same_runs("adapt --mesh " + path("holed_torus.obj") + " --cycles 10", "cycle_009");
}

TEST_F(Mpi, ACreasedCubeIsTheSerialRun) {
  // Sharp features (issue 42) travel with the pieces' states: the cube of 12 triangles with its
  // edges at 30 degrees, the same cycles and meshes on every number of processes.
  std::ofstream off(path("cube.off"));
  off << "OFF\n8 12 0\n";
  for (int i = 0; i < 8; ++i) off << (i & 1) << " " << ((i >> 1) & 1) << " " << ((i >> 2) & 1) << "\n";
  off << "3 0 2 3\n3 0 3 1\n3 4 5 7\n3 4 7 6\n3 0 1 5\n3 0 5 4\n3 2 6 7\n3 2 7 3\n3 0 4 6\n3 0 6 2\n3 1 3 7\n3 1 7 5\n";
  off.close();
  expect_same_runs("adapt --mesh " + path("cube.off") + " --sharp-angle 30 --min-level 2 --cycles 8", "cycle_007");
  // The pieces carry each point's rule (no process holds the whole crease lines): the points
  // of the joined pieces with their rules are the serial mesh's.
  const auto rules = [](vtkPolyData* mesh) {
    std::set<std::array<long long, 4>> out;
    vtkDataArray* rule = mesh->GetPointData()->GetArray("vertex_rule");
    if (rule == nullptr) return out;
    for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i) {
      double x[3];
      mesh->GetPoint(i, x);
      out.insert({std::llround(x[0] * 1e9), std::llround(x[1] * 1e9), std::llround(x[2] * 1e9),
                  static_cast<long long>(rule->GetTuple1(i))});
    }
    return out;
  };
  const auto serial = rules(read_vtp(path("serial/cycle_007.vtp")));
  std::size_t corners = 0;
  for (const auto& r : serial) corners += r[3] == 3 ? 1 : 0;
  EXPECT_EQ(corners, 8u);
  EXPECT_EQ(rules(read_pvtp(path("p3/cycle_007.pvtp"))), serial);
}

TEST_F(Mpi, AMovingPeakWithCoarseningIsTheSerialRun) {
  // Removals decided by the owners, the ghost layers made exact again after each round: the
  // serial steps, and pieces only.
  expect_same_runs("adapt --problem moving-peak --steps 6 --min-level 3", "step_006", false, true);
}

TEST_F(Mpi, CompactingTheViewsChangesNoResultAndShrinksThem) {
  // Each process compacts its view when it shrank (--compact-below): 1 compacts it at every
  // cycle, 0 never; the reports agree digit for digit, and the compacted views are smaller.
  std::string json[2];
  const char* setting[2] = {"0", "1"};
  for (int k = 0; k < 2; ++k) {
    const std::string dir = path(std::string("c") + setting[k]);
    const RunResult r = run_on(2, std::string("adapt --problem moving-peak --steps 5 --min-level 3 --compact-below ") +
                                      setting[k] + " --out " + dir);
    ASSERT_EQ(r.code, 0) << r.err;
    json[k] = read_text(dir + "/report.json");
  }
  const auto values = printed_values;
  for (const char* key : {"dofs", "triangles", "estimate", "error_h1", "solver_iterations", "removals"}) {
    EXPECT_EQ(values(json[0], key), values(json[1], key)) << key;
    EXPECT_GE(values(json[0], key).size(), 6u) << key;
  }
  const std::vector<std::string> never = values(json[0], "mesh_mb"), always = values(json[1], "mesh_mb");
  ASSERT_EQ(never.size(), always.size());
  ASSERT_GE(never.size(), 2u);
  EXPECT_LT(std::stod(always.back()), std::stod(never.back())) << json[1];
}

TEST_F(Mpi, CoarseningOnATorusWithAHoleIsTheSerialRun) {
  // Refinement and coarsening in every cycle (a fraction marked, every vertex whose indicators
  // are below 0.8 times the smallest marked one removed), across a boundary and genus.
  const BaseMesh torus = rgbmesh::testing::torus(12, 8);
  std::ofstream obj(path("holed_torus.obj"));
  for (const auto& p : torus.points) obj << "v " << p.x << " " << p.y << " " << p.z << "\n";
  for (std::size_t t = 2; t < torus.triangles.size(); ++t)
    obj << "f " << torus.triangles[t][0] + 1 << " " << torus.triangles[t][1] + 1 << " "
        << torus.triangles[t][2] + 1 << "\n";
  obj.close();
  expect_same_runs("adapt --mesh " + path("holed_torus.obj") +
                       " --min-level 1 --coarsen 0.8 --marking fraction --theta 0.25 --cycles 9",
                   "cycle_008", false, true);
}

TEST_F(Mpi, ADistributedRunResumesFromItsPiecesOnAnyNumberOfProcesses) {
  // The moving peak on 3 processes, interrupted after 3 of 8 steps: each piece carries its
  // part's vertices with their ancestors, which --resume joins into the whole mesh; resumed
  // on 2 processes and on 1, every step is the uninterrupted run's.
  const std::string args = "adapt --problem moving-peak --steps 8 --min-level 3";
  const std::string full = path("full"), part = path("part"), one = path("one"), edited = path("edited");
  ASSERT_EQ(run_on(3, args + " --out " + full).code, 0);
  fs::copy(full, part);
  interrupt_after(part, 3, "step_");
  fs::copy(part, one);
  fs::copy(part, edited);
  ASSERT_FALSE(fs::exists(part + "/step_002.vtp")) << "pieces only";
  const RunResult two = run_on(2, "adapt --resume " + part);
  ASSERT_EQ(two.code, 0) << two.err;
  const RunResult alone = run("adapt --resume " + one);
  ASSERT_EQ(alone.code, 0) << alone.err;
  const std::vector<Cycle> a = cycles_of(report_of(full));
  ASSERT_EQ(a.size(), 9u);
  for (const std::string& dir : {part, one}) {
    const std::vector<Cycle> b = cycles_of(report_of(dir));
    ASSERT_EQ(b.size(), a.size()) << dir;
    long removed = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].dofs, b[i].dofs) << dir << ", step " << i;
      EXPECT_EQ(a[i].triangles, b[i].triangles) << dir << ", step " << i;
      EXPECT_NEAR(a[i].estimate, b[i].estimate, 1e-7 * a[i].estimate) << dir << ", step " << i;
      EXPECT_EQ(a[i].time, b[i].time) << dir << ", step " << i;
      if (i >= 3) removed += b[i].removals;
    }
    EXPECT_GT(removed, 1000) << dir << ": the resumed steps coarsen behind the peak";
  }
  // The last mesh: the whole mesh the run resumed alone wrote, the uninterrupted run's pieces
  // and those of the run resumed on 2 processes are one mesh. (The whole mesh first: the
  // comparison finds points by position, and joined pieces repeat their interfaces' points.)
  const vtkSmartPointer<vtkPolyData> last = read_vtp(one + "/step_008.vtp");
  for (const std::string& dir : {full, part}) {
    const vtkSmartPointer<vtkPolyData> pieces = read_pvtp(dir + "/step_008.pvtp");
    const std::array<std::size_t, 2> differing = triangles_differing(last, pieces);
    EXPECT_EQ(differing[0] + differing[1], 0u) << dir;
    EXPECT_EQ(pieces->GetNumberOfCells(), last->GetNumberOfCells()) << dir;
  }
  // A piece whose Points were edited is refused, naming it, before anything is written.
  const std::string piece = edited + "/step_002_r1.vtp";
  const vtkSmartPointer<vtkPolyData> data = read_vtp(piece);
  ASSERT_GT(data->GetNumberOfPoints(), 0);
  double p[3];
  data->GetPoint(0, p);
  data->GetPoints()->SetPoint(0, p[0] + 0.1, p[1], p[2]);
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(data);
  writer->SetFileName(piece.c_str());
  ASSERT_EQ(writer->Write(), 1);
  const RunResult refused = run_on(2, "adapt --resume " + edited);
  EXPECT_EQ(refused.code, 2) << refused.err;
  EXPECT_NE(refused.err.find(piece + ": inconsistent RGB state: point 0"), std::string::npos) << refused.err;
  EXPECT_FALSE(fs::exists(edited + "/step_003.pvtp"));
}

TEST_F(Mpi, QuadraticElementsWithCoarseningResumeOnMoreProcesses) {
  // P2 with --coarsen: 4 cycles on 3 processes, resumed to 8 on 4; the serial run's cycles.
  const std::string args = "adapt --order 2 --min-level 1 --coarsen 0.8 --marking fraction --theta 0.25";
  const std::string serial = path("serial"), dir = path("p3");
  ASSERT_EQ(run(args + " --cycles 8 --out " + serial).code, 0);
  ASSERT_EQ(run_on(3, args + " --cycles 4 --out " + dir).code, 0);
  const RunResult r = run_on(4, "adapt --resume " + dir + " --cycles 8");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Cycle> a = cycles_of(report_of(serial)), b = cycles_of(report_of(dir));
  ASSERT_EQ(a.size(), 8u);
  ASSERT_EQ(b.size(), a.size());
  long removed = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].dofs, b[i].dofs) << "cycle " << i;
    EXPECT_EQ(a[i].triangles, b[i].triangles) << "cycle " << i;
    EXPECT_NEAR(a[i].estimate, b[i].estimate, 1e-7 * a[i].estimate) << "cycle " << i;
    removed += a[i].removals;
  }
  EXPECT_GT(removed, 100) << "the serial run hardly coarsens";
  EXPECT_TRUE(fs::exists(dir + "/cycle_007_p2_r3.vtu"));
}

TEST_F(Mpi, MoreProcessesThanUnitsIsTheSerialRunToo) {
  // Two triangles, all four vertices on the boundary, on three processes: one process owns
  // nothing and its view has no free unknown, yet it takes part in every collective step
  // (found: it skipped the solve and the others waited forever).
  std::ofstream obj(path("diamond.obj"));
  obj << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0.2\nf 1 2 3\nf 2 4 3\n";
  obj.close();
  const std::string args = "adapt --mesh " + path("diamond.obj") + " --cycles 8";
  ASSERT_EQ(run(args + " --out " + path("serial")).code, 0);
  const RunResult many = run_on(3, args + " --out " + path("p3"));
  ASSERT_EQ(many.code, 0) << many.err;
  const std::vector<Cycle> a = cycles_of(report_of(path("serial"))), b = cycles_of(report_of(path("p3")));
  ASSERT_EQ(a.size(), 8u);
  ASSERT_EQ(b.size(), a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].dofs, b[i].dofs) << "cycle " << i;
    EXPECT_EQ(a[i].triangles, b[i].triangles) << "cycle " << i;
    EXPECT_NEAR(a[i].estimate, b[i].estimate, 1e-7 * a[i].estimate) << "cycle " << i;
  }
}

TEST_F(Mpi, QuadraticElementsAreTheSerialRunToo) {
  // P2: the curved elements' matrices, residuals and edge jumps computed in parts.
  const std::string args = "adapt --order 2 --min-level 1 --cycles 7";
  ASSERT_EQ(run(args + " --out " + path("serial")).code, 0);
  const RunResult many = run_on(3, args + " --out " + path("p3"));
  ASSERT_EQ(many.code, 0) << many.err;
  const std::vector<Cycle> a = cycles_of(report_of(path("serial"))), b = cycles_of(report_of(path("p3")));
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GE(a.size(), 6u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].dofs, b[i].dofs) << "cycle " << i;
    EXPECT_NEAR(a[i].estimate, b[i].estimate, 1e-7 * a[i].estimate) << "cycle " << i;
    EXPECT_NEAR(a[i].error_h1, b[i].error_h1, 1e-7 * a[i].error_h1) << "cycle " << i;
    EXPECT_GE(b[i].bytes_sent, 16.0 * static_cast<double>(b[i].triangles)) << "cycle " << i;
  }
  // The output: each process's piece of curved triangles and the summary that joins them,
  // which the series lists: the serial run's cells, quadratic, each with its process.
  const std::string last = "cycle_006_p2";
  EXPECT_NE(read_text(path("p3") + "/solution.pvd").find(last + ".pvtu"), std::string::npos);
  auto whole = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  whole->SetFileName((path("serial") + "/" + last + ".vtu").c_str());
  whole->Update();
  auto joined = vtkSmartPointer<vtkXMLPUnstructuredGridReader>::New();
  joined->SetFileName((path("p3") + "/" + last + ".pvtu").c_str());
  joined->Update();
  vtkUnstructuredGrid* grid = joined->GetOutput();
  ASSERT_GT(whole->GetOutput()->GetNumberOfCells(), 0);
  EXPECT_EQ(grid->GetNumberOfCells(), whole->GetOutput()->GetNumberOfCells());
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) ASSERT_EQ(grid->GetCellType(c), VTK_QUADRATIC_TRIANGLE);
  vtkDataArray* owner = grid->GetCellData()->GetArray("rank");
  ASSERT_NE(owner, nullptr);
  std::set<int> ranks;
  for (vtkIdType c = 0; c < owner->GetNumberOfTuples(); ++c) ranks.insert(static_cast<int>(owner->GetTuple1(c)));
  EXPECT_EQ(ranks.size(), 3u);
  ASSERT_NE(grid->GetPointData()->GetArray("solution"), nullptr);
  // A later run on fewer processes leaves no piece of the third.
  ASSERT_EQ(run_on(2, args + " --out " + path("p3")).code, 0);
  EXPECT_TRUE(fs::exists(path("p3") + "/" + last + "_r1.vtu"));
  EXPECT_FALSE(fs::exists(path("p3") + "/" + last + "_r2.vtu"));
}

TEST_F(Mpi, AProcessFailingAloneEndsTheRunWithItsError) {
  // Process 1 is given an output folder that does not exist (its piece cannot be written), while
  // the others wait for it in the next cycle's collective operations: the run must end, with
  // process 1's error and the exit code of an output failure, not hang.
  const std::string good = path("good"), missing = path("missing");
  const RunResult r = run_with(std::string(RGBMESH_MPIEXEC) + " --oversubscribe -np 2 sh -c '" + RGBMESH_CLI +
                                   " adapt --cycles 6 --out \"$([ \"$OMPI_COMM_WORLD_RANK\" = 0 ] && echo " + good +
                                   " || echo " + missing + ")\"'",
                               "");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("rgbmesh (process 1 of 2): error: " + missing + "/cycle_000_r1.vtp"), std::string::npos) << r.err;
  // Every process failing alike (the same bad input) ends normally, with rank 0's one line.
  const RunResult bad = run_on(3, "adapt --mesh " + path("nothing.obj"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("rgbmesh: error: " + path("nothing.obj")), std::string::npos) << bad.err;
  EXPECT_EQ(bad.err.find("MPI_ABORT"), std::string::npos) << bad.err;
  // A solver that several processes cannot use is refused, not silently replaced by amg.
  const RunResult ldlt = run_on(2, "adapt --cycles 2 --solver ldlt --out " + path("ldlt"));
  EXPECT_EQ(ldlt.code, 2) << ldlt.err;
  EXPECT_NE(ldlt.err.find("--solver ldlt: a run on 2 processes solves with amg"), std::string::npos) << ldlt.err;
  EXPECT_FALSE(fs::exists(path("ldlt")));
  EXPECT_EQ(run_on(2, "adapt --cycles 2 --solver amg --out " + path("amg")).code, 0);
}

TEST_F(Mpi, ARunOnFewerProcessesLeavesNoPiecesOfTheLastOne) {
  const std::string dir = path("run");
  ASSERT_EQ(run_on(4, "adapt --cycles 3 --out " + dir).code, 0);
  ASSERT_TRUE(fs::exists(dir + "/cycle_002_r3.vtp"));
  ASSERT_EQ(run_on(2, "adapt --cycles 3 --out " + dir).code, 0);
  EXPECT_TRUE(fs::exists(dir + "/cycle_002_r1.vtp"));
  EXPECT_FALSE(fs::exists(dir + "/cycle_002_r2.vtp"));
  EXPECT_FALSE(fs::exists(dir + "/cycle_002_r3.vtp"));
}

}  // namespace
