#pragma once
// The command-line tool run as a user would run it, for the CLI tests: a temporary folder per
// test, the tool's exit code, standard output and standard error, and readers for its files.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>

namespace rgbmesh::testing {

namespace fs = std::filesystem;

// A VTP file as VTK's own XML reader sees it.
inline vtkSmartPointer<vtkPolyData> read_vtp(const std::string& file) {
  auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  reader->SetFileName(file.c_str());
  reader->Update();
  return reader->GetOutput();
}

// A whole text file.
inline std::string read_text(const std::string& file) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct RunResult {
  int code = -1;
  std::string out, err;
};

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rgbmesh_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  RunResult run(const std::string& args) const { return run_with(RGBMESH_CLI, args); }
  // A command line (e.g. the tool under mpirun) and its arguments.
  RunResult run_with(const std::string& program, const std::string& args) const {
    const std::string err_file = path("stderr.txt");
    const std::string cmd = program + " " + args + " 2>" + err_file;
    RunResult r;
    FILE* pipe = ::popen(cmd.c_str(), "r");
    char buf[4096];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) r.out.append(buf, n);
    const int status = ::pclose(pipe);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.err = read_text(err_file);
    return r;
  }

  // An octahedron as OFF text (8 triangles, 6 vertices), optionally with extra lines.
  std::string write_octahedron(const std::string& name) const {
    std::ofstream f(path(name));
    f << "OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n"
      << "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n";
    return path(name);
  }

  // Standard error without the note that a base mesh's limit surface rounds its edges (a coarse
  // polyhedron such as write_octahedron's always gets it; tests/test_cli_sharp.cpp checks it).
  static std::string without_rounding_note(const std::string& err) {
    std::string out, line;
    for (std::size_t start = 0; start < err.size();) {
      const std::size_t end = err.find('\n', start);
      line = err.substr(start, end == std::string::npos ? std::string::npos : end - start + 1);
      if (line.find("the Loop limit surface lies") == std::string::npos) out += line;
      if (end == std::string::npos) break;
      start = end + 1;
    }
    return out;
  }

  static std::string last_line(const std::string& s) {
    std::string t = s;
    while (!t.empty() && t.back() == '\n') t.pop_back();
    const auto p = t.rfind('\n');
    return p == std::string::npos ? t : t.substr(p + 1);
  }

  // The integer value of "key": N in a flat JSON line.
  static long json_int(const std::string& json, const std::string& key) {
    const auto p = json.find("\"" + key + "\": ");
    EXPECT_NE(p, std::string::npos) << key << " in " << json;
    if (p == std::string::npos) return -1;
    return std::stol(json.substr(p + key.size() + 4));
  }

  fs::path dir_;
};

// The arrays of a VTP file, read with VTK's own reader: name -> components, per point / cell.
struct VtpArrays {
  vtkIdType points = 0, cells = 0;
  std::map<std::string, int> point_arrays, cell_arrays;
};
inline VtpArrays read_vtp_arrays(const std::string& file) {
  const vtkSmartPointer<vtkPolyData> pd = read_vtp(file);
  VtpArrays out;
  out.points = pd->GetNumberOfPoints();
  out.cells = pd->GetNumberOfCells();
  for (int i = 0; i < pd->GetPointData()->GetNumberOfArrays(); ++i)
    out.point_arrays[pd->GetPointData()->GetArrayName(i)] = pd->GetPointData()->GetArray(i)->GetNumberOfComponents();
  for (int i = 0; i < pd->GetCellData()->GetNumberOfArrays(); ++i)
    out.cell_arrays[pd->GetCellData()->GetArrayName(i)] = pd->GetCellData()->GetArray(i)->GetNumberOfComponents();
  return out;
}

}  // namespace rgbmesh::testing
