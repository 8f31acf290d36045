// `rgbmesh adapt --resume DIR` and `adapt --mesh saved.vtp`: a run interrupted after K cycles
// and resumed repeats the uninterrupted run (unknowns, errors and estimates, the final mesh),
// for a stationary problem with Dörfler marking and for the moving peak with coarsening; a
// finished run extends with more cycles or unknowns; options that contradict the run, and
// damaged or missing run folders, are refused with one line and exit code 2.

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <vector>

#include <vtkCellArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkXMLPolyDataWriter.h>

#include "../apps/json_read.hpp"
#include "cli_fixture.hpp"
#include "cli_reports.hpp"

namespace {

using namespace rgbmesh::testing;
using rgbmesh::cli::JsonReader;
using rgbmesh::cli::JsonValue;

bool close(double a, double b, double relative = 1e-9) {
  return std::abs(a - b) <= relative * std::max(std::abs(a), std::abs(b));
}

// The same unknowns, triangles and figures per cycle (relative 1e-9; error_l2 to
// `l2_relative`).
void expect_same_cycles(const std::vector<Cycle>& a, const std::vector<Cycle>& b, double l2_relative = 1e-9) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].dofs, b[i].dofs) << "cycle " << i;
    EXPECT_EQ(a[i].triangles, b[i].triangles) << "cycle " << i;
    EXPECT_TRUE(close(a[i].estimate, b[i].estimate)) << "cycle " << i << ": " << a[i].estimate << " " << b[i].estimate;
    EXPECT_TRUE(close(a[i].error_l2, b[i].error_l2, l2_relative))
        << "cycle " << i << ": " << a[i].error_l2 << " " << b[i].error_l2;
    EXPECT_TRUE(close(a[i].error_h1, b[i].error_h1)) << "cycle " << i << ": " << a[i].error_h1 << " " << b[i].error_h1;
    EXPECT_EQ(a[i].time, b[i].time) << "cycle " << i;
  }
}

// A file's triangles as sets of their corners' positions: the mesh, whatever its numbering.
int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

class Resume : public Cli {};

TEST_F(Resume, ASpherePeakRunResumedRepeatsTheUninterruptedRun) {
  // Dörfler marking, 12 cycles; the interrupted run did 5 (it finished them: its --cycles).
  const std::string full = path("full"), part = path("part");
  ASSERT_EQ(run("adapt --cycles 12 --out " + full).code, 0);
  ASSERT_EQ(run("adapt --cycles 5 --out " + part).code, 0);
  const RunResult r = run("adapt --resume " + part + " --cycles 12 --report " + path("copy.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("resuming " + part + " after cycle 4"), std::string::npos) << r.out;
  const JsonValue a = report_of(full), b = report_of(part);
  const std::vector<Cycle> ca = cycles_of(a), cb = cycles_of(b);
  ASSERT_EQ(cb.size(), 12u);
  expect_same_cycles(ca, cb);
  EXPECT_GT(ca.back().dofs, 3 * ca[5].dofs) << "the resumed cycles refined";
  EXPECT_EQ(triangles_of(full + "/cycle_011.vtp"), triangles_of(part + "/cycle_011.vtp"));
  EXPECT_EQ(b.find("status")->string, "finished");
  EXPECT_EQ(b.find("max_cycles")->number, 12);
  ASSERT_NE(b.find("resumed"), nullptr);
  EXPECT_EQ(b.find("resumed")->array.size(), 1u);
  EXPECT_EQ(b.find("command")->string.find("--resume"), std::string::npos) << "the command that started the run";
  EXPECT_EQ(read_text(path("copy.json")), read_text(part + "/report.json"));
  const std::string pvd = read_text(part + "/solution.pvd");
  for (const char* f : {"cycle_000.vtp", "cycle_004.vtp", "cycle_005.vtp", "cycle_011.vtp"})
    EXPECT_NE(pvd.find(f), std::string::npos) << f << " in " << pvd;

  // Resumed again without more cycles: nothing to do, said in one line.
  const RunResult again = run("adapt --resume " + part);
  EXPECT_EQ(again.code, 2);
  EXPECT_EQ(lines(again.err), 1) << again.err;
  EXPECT_NE(again.err.find("--cycles"), std::string::npos) << again.err;
}

TEST_F(Resume, AnIterativeSolverRunResumedMatchesToTheSolversTolerance) {
  // CG stops at a tolerance, from the previous cycle's solution. The resumed run solves its
  // last cycle again without that guess, so the solutions differ within the tolerance: the
  // same unknowns, meshes and estimates, and error_l2 (the most sensitive figure) within
  // 1e-8 relative (3.3e-10 measured over 20 cycles, 2e-9 reported; docs/adaptation.md, Resuming a run).
  const std::string full = path("full"), part = path("part");
  ASSERT_EQ(run("adapt --solver cg --cycles 14 --out " + full).code, 0);
  ASSERT_EQ(run("adapt --solver cg --cycles 5 --out " + part).code, 0);
  const RunResult r = run("adapt --resume " + part + " --cycles 14");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Cycle> a = cycles_of(report_of(full)), b = cycles_of(report_of(part));
  expect_same_cycles(a, b, 1e-8);
  EXPECT_EQ(triangles_of(full + "/cycle_013.vtp"), triangles_of(part + "/cycle_013.vtp"));
}

TEST_F(Resume, AMaxDofsStopExtendsWithMoreUnknowns) {
  const std::string full = path("full"), part = path("part");
  ASSERT_EQ(run("adapt --max-dofs 1500 --out " + full).code, 0);
  ASSERT_EQ(run("adapt --max-dofs 300 --out " + part).code, 0);
  EXPECT_EQ(report_of(part).find("stopped")->string, "max-dofs");
  const RunResult same = run("adapt --resume " + part + " --max-dofs 300");
  EXPECT_EQ(same.code, 2);
  EXPECT_NE(same.err.find("--max-dofs"), std::string::npos) << same.err;
  const RunResult r = run("adapt --resume " + part + " --max-dofs 1500");
  ASSERT_EQ(r.code, 0) << r.err;
  expect_same_cycles(cycles_of(report_of(full)), cycles_of(report_of(part)));
  EXPECT_EQ(report_of(part).find("max_dofs")->number, 1500);
}

// With P1 and with Loop elements (whose steps also write the smooth picture), in both bases.
class MovingResume : public Resume, public ::testing::WithParamInterface<const char*> {};

TEST_P(MovingResume, AMovingPeakRunResumedRepeatsTheUninterruptedRun) {
  // Equidistribution with coarsening (0.25, the default) above a floor at level 2, 8 steps;
  // interrupted after 3.
  const std::string full = path("mfull"), part = path("mpart");
  ASSERT_EQ(run("adapt --problem moving-peak --steps 8 --min-level 2 --out " + full + GetParam()).code, 0);
  fs::copy(full, part);
  interrupt_after(part, 3, "step_");
  ASSERT_FALSE(fs::exists(part + "/step_003.vtp"));
  const RunResult r = run("adapt --resume " + part);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("after step 2"), std::string::npos) << r.out;
  const JsonValue a = report_of(full), b = report_of(part);
  const std::vector<Cycle> ca = cycles_of(a), cb = cycles_of(b);
  ASSERT_EQ(cb.size(), 9u);
  expect_same_cycles(ca, cb);
  EXPECT_EQ(cb[3].time, 3.0 / 8) << "the time goes on";
  long removals = 0;
  for (std::size_t i = 3; i < cb.size(); ++i) removals += cb[i].removals;
  EXPECT_GT(removals, 0) << "the resumed steps coarsened behind the peak";
  EXPECT_EQ(a.find("target_estimate")->number, b.find("target_estimate")->number);
  EXPECT_EQ(b.find("min_level")->number, 2);
  EXPECT_EQ(triangles_of(full + "/step_008.vtp"), triangles_of(part + "/step_008.vtp"));
  EXPECT_EQ(b.find("stopped")->string, "steps");
  if (std::string(GetParam()).find("loop") != std::string::npos) {
    for (int step = 0; step <= 8; ++step) {
      EXPECT_TRUE(fs::exists(part + "/step_00" + std::to_string(step) + "_smooth.vtp")) << step;
    }
  }
  // All steps done: a moving run does not extend.
  const RunResult more = run("adapt --resume " + part);
  EXPECT_EQ(more.code, 2);
  EXPECT_EQ(lines(more.err), 1) << more.err;
}

INSTANTIATE_TEST_SUITE_P(Resume, MovingResume,
                         ::testing::Values("", " --element loop", " --element loop --loop-basis thb"),
                         [](const ::testing::TestParamInfo<const char*>& p) {
                           const std::string args = p.param;
                           return std::string(args.empty()                             ? "P1"
                                              : args.find("thb") != std::string::npos ? "LoopThb"
                                                                                       : "Loop");
                         });

TEST_F(Resume, ConflictingOptionsAndDamagedFoldersAreRefused) {
  const std::string dir = path("run");
  ASSERT_EQ(run("adapt --cycles 3 --theta 0.4 --out " + dir).code, 0);
  const std::string report = read_text(dir + "/report.json");
  const auto refused = [&](const std::string& args, const std::string& says) {
    const RunResult r = run("adapt --resume " + args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << args << ": " << r.err;
  };
  refused(dir + " --cycles 5 --theta 0.5", "--theta 0.5: conflicts");
  refused(dir + " --cycles 5 --problem moving-peak", "--problem moving-peak: conflicts");
  refused(dir + " --cycles 5 --estimator zz", "--estimator zz: conflicts");
  refused(dir + " --cycles 5 --min-level 1", "--min-level 1: conflicts");
  refused(dir + " --cycles 5 --mesh " + dir + "/cycle_002.vtp", "--mesh: does not apply with --resume");
  refused(dir + " --cycles 5 --out " + path("elsewhere"), "--out");
  refused(dir, "has done 3 cycles");
  refused(path("nowhere") + " --cycles 5", "no such folder");
  // An unset shell variable (--resume "$RUN") is no folder either: it used to start a new run
  // in the default folder, over whatever run was there.
  refused("\"\" --cycles 5 --out " + dir, "--resume: must name a file or folder, got an empty string");
  EXPECT_EQ(read_text(dir + "/report.json"), report) << "refusals write nothing";
  // The same value as the run's is no conflict.
  ASSERT_EQ(run("adapt --resume " + dir + " --cycles 4 --theta 0.4").code, 0);
  EXPECT_EQ(cycles_of(report_of(dir)).size(), 4u);

  // Damaged folders.
  fs::create_directories(path("empty"));
  refused(path("empty") + " --cycles 5", "report.json: missing");
  std::ofstream(dir + "/report.json") << report.substr(0, report.size() / 2);
  refused(dir + " --cycles 5", "not valid JSON");
  std::ofstream(dir + "/report.json") << report;
  fs::remove(dir + "/cycle_002.vtp");
  refused(dir + " --cycles 5", "cycle_002.vtp: missing");
  fs::copy_file(dir + "/cycle_000.vtp", dir + "/cycle_002.vtp");
  refused(dir + " --cycles 5", "cycle_002.vtp: cannot resume from this run");
}

TEST_F(Resume, ACycleWhosePointsWereEditedIsRefused) {
  // Moving points in ParaView and saving the cycle: the edit used to be dropped without a
  // word, the run resumed from the positions the state gives.
  const std::string dir = path("run");
  ASSERT_EQ(run("adapt --cycles 3 --out " + dir).code, 0);
  const std::string last = dir + "/cycle_002.vtp";
  const vtkSmartPointer<vtkPolyData> data = read_vtp(last);
  vtkNew<vtkPoints> scaled;
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i) {
    double p[3];
    data->GetPoint(i, p);
    scaled->InsertNextPoint(2 * p[0], 2 * p[1], 2 * p[2]);
  }
  data->SetPoints(scaled);
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(data);
  writer->SetFileName(last.c_str());
  ASSERT_EQ(writer->Write(), 1);
  for (const std::string& args : {"adapt --resume " + dir + " --cycles 5", "adapt --mesh " + last + " --out " + path("new")}) {
    const RunResult r = run(args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find(last + ": inconsistent RGB state: point 0: its position (Points)"), std::string::npos)
        << args << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(dir + "/cycle_003.vtp"));
}

TEST_F(Resume, ANewRunStartsFromASavedAdaptedMesh) {
  const std::string first = path("first");
  ASSERT_EQ(run("adapt --cycles 7 --out " + first).code, 0);
  const std::vector<Cycle> before = cycles_of(report_of(first));
  // The restored mesh is cycle 6's (not its base): the same unknowns, the same solution.
  const RunResult r = run("adapt --problem sphere-peak --mesh " + first + "/cycle_006.vtp --cycles 2 --out " + path("next"));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Cycle> after = cycles_of(report_of(path("next")));
  ASSERT_EQ(after.size(), 2u);
  EXPECT_EQ(after[0].dofs, before[6].dofs);
  EXPECT_TRUE(close(after[0].estimate, before[6].estimate)) << after[0].estimate << " " << before[6].estimate;
  EXPECT_GT(after[1].dofs, after[0].dofs);
  EXPECT_EQ(triangles_of(first + "/cycle_006.vtp"), triangles_of(path("next") + "/cycle_000.vtp"));
}

}  // namespace
