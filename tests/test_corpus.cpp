// The corpus of malformed input files (tests/corpus, made by make_corpus.py) run through the
// command-line tool as a user would: `rgbmesh info FILE`, `rgbmesh convert FILE OUT.vtp` and,
// where the file is damaged at the reading level, `rgbmesh fit --target FILE --out DIR`. Each
// must exit with code 2 after printing exactly one line that names the file (and, where the
// manifest says, the problem), without a crash, a hang or anything left in its folder. Plus what
// a repository cannot hold: FIFOs, devices, symbolic-link loops and 2 GB sparse files, which must
// be refused at once with little memory.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path corpus_dir = fs::path(RGBMESH_TEST_DATA_DIR).parent_path() / "corpus" / "files";

struct Case {
  std::string name;
  std::vector<std::string> commands;  // info, convert, fit
  std::string expected;               // a text the error line must contain; may be empty
};

std::vector<Case> manifest() {
  std::vector<Case> cases;
  std::ifstream in(corpus_dir / "MANIFEST.tsv");
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    Case c;
    std::string commands;
    std::getline(fields, c.name, '\t');
    std::getline(fields, commands, '\t');
    std::getline(fields, c.expected);
    std::istringstream words(commands);
    for (std::string w; words >> w;) c.commands.push_back(w);
    cases.push_back(c);
  }
  return cases;
}

struct ToolRun {
  int code = -1;   // exit code, or -1 when killed by a signal
  int signal = 0;  // the signal that ended it
  bool timed_out = false;
  std::string out, err;
  long peak_rss_kb = 0;
  double seconds = 0;
};

std::string contents(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs the tool with `args` in `dir`, without a shell, killing it after `timeout_s`.
ToolRun run_tool(const std::vector<std::string>& args, const fs::path& dir, double timeout_s = 30) {
  const fs::path out_file = dir.parent_path() / (dir.filename().string() + ".out");
  const fs::path err_file = dir.parent_path() / (dir.filename().string() + ".err");
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (::chdir(dir.c_str()) != 0) ::_exit(126);
    const int out = ::open(out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int err = ::open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int none = ::open("/dev/null", O_RDONLY);
    if (out < 0 || err < 0 || none < 0) ::_exit(126);
    ::dup2(none, 0);
    ::dup2(out, 1);
    ::dup2(err, 2);
    std::vector<char*> argv;
    static std::string tool = RGBMESH_CLI;
    argv.push_back(tool.data());
    std::vector<std::string> copies = args;
    for (std::string& a : copies) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(tool.c_str(), argv.data());
    ::_exit(127);
  }
  ToolRun r;
  int status = 0;
  rusage usage{};
  for (;;) {
    const pid_t done = ::wait4(pid, &status, WNOHANG, &usage);
    if (done == pid) break;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (elapsed > timeout_s && !r.timed_out) {
      r.timed_out = true;
      ::kill(pid, SIGKILL);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.peak_rss_kb = usage.ru_maxrss;
  if (WIFEXITED(status)) r.code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.out = contents(out_file);
  r.err = contents(err_file);
  fs::remove(out_file);
  fs::remove(err_file);
  return r;
}

class Corpus : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    base_ = fs::temp_directory_path() / ("rgbmesh_corpus_" + std::to_string(::getpid()) + "_" + GetParam());
    fs::remove_all(base_);
    fs::create_directories(base_);
  }
  void TearDown() override { fs::remove_all(base_); }

  // A fresh, empty folder for one command: whatever is in it afterwards was left behind.
  fs::path fresh_dir() {
    const fs::path dir = base_ / ("run" + std::to_string(++runs_));
    fs::create_directories(dir);
    return dir;
  }

  // One command on `file`: exit code 2, one line naming the file (and `expected`), no output,
  // nothing left behind.
  void expect_refused(const std::string& command, const fs::path& file, const std::string& expected,
                      const std::string& label) {
    const fs::path dir = fresh_dir();
    std::vector<std::string> args;
    if (command == "info") args = {"info", file.string()};
    if (command == "convert") args = {"convert", file.string(), (dir / "out.vtp").string()};
    if (command == "fit") args = {"fit", "--target", file.string(), "--out", (dir / "fit").string()};
    if (command == "refine") args = {"refine", file.string(), (dir / "out.vtp").string(), "--uniform", "1"};
    if (command == "adapt") args = {"adapt", "--mesh", file.string(), "--out", (dir / "adapt").string()};
    ASSERT_FALSE(args.empty()) << command;
    const ToolRun r = run_tool(args, dir);
    const std::string what = label + ": rgbmesh " + command + ": ";
    EXPECT_FALSE(r.timed_out) << what << "did not finish";
    EXPECT_EQ(r.signal, 0) << what << "killed by signal " << r.signal;
    EXPECT_EQ(r.code, 2) << what << r.err;
    EXPECT_EQ(r.out, "") << what;
    ASSERT_FALSE(r.err.empty()) << what << "printed nothing";
    EXPECT_EQ(r.err.back(), '\n') << what << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << what << "more than one line:\n" << r.err;
    EXPECT_NE(r.err.find(file.string()), std::string::npos) << what << "the file is not named: " << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << what << "'" << expected << "' not in: " << r.err;
    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(dir)) left.push_back(e.path().filename().string());
    EXPECT_TRUE(left.empty()) << what << "left " << left.front();
  }

  fs::path base_;
  int runs_ = 0;
};

std::string extension_of(const std::string& name) { return name.substr(name.rfind('.') + 1); }

bool is_point_cloud_only(const std::string& ext) { return ext == "xyz" || ext == "pwn"; }

TEST_P(Corpus, EveryFileIsOneLineErrorWithExitCode2) {
  const std::string ext = GetParam();
  std::size_t files = 0;
  for (const Case& c : manifest()) {
    if (extension_of(c.name) != ext) continue;
    ++files;
    const fs::path file = corpus_dir / c.name;
    ASSERT_TRUE(fs::is_regular_file(file)) << file;
    std::vector<std::string> commands = c.commands;
    // refine and adapt read meshes as info does (the manifest names the commands of the reading
    // paths; these two run every mesh file too, as a user would).
    if (!is_point_cloud_only(ext) && std::find(commands.begin(), commands.end(), "info") != commands.end()) {
      commands.push_back("refine");
      commands.push_back("adapt");
    }
    for (const std::string& command : commands) {
      // info and convert read meshes: a point-cloud format is an unknown mesh format to them.
      const std::string expected =
          is_point_cloud_only(ext) && command != "fit" ? "unknown mesh format" : c.expected;
      expect_refused(command, file, expected, c.name);
    }
  }
  EXPECT_GE(files, 10u) << "too few ." << ext << " files in " << corpus_dir;
}

// What a repository cannot hold: special files, links that lead nowhere.
TEST_P(Corpus, SpecialFilesAreRefusedAndNamed) {
  const std::string ext = GetParam();
  const std::vector<std::string> commands = is_point_cloud_only(ext)
                                                ? std::vector<std::string>{"fit"}
                                                : std::vector<std::string>{"info", "convert", "fit"};
  const fs::path fifo = base_ / ("fifo." + ext);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const fs::path device = base_ / ("null." + ext);
  fs::create_symlink("/dev/null", device);
  const fs::path loop_a = base_ / ("loop_a." + ext), loop_b = base_ / ("loop_b." + ext);
  fs::create_symlink(loop_b, loop_a);
  fs::create_symlink(loop_a, loop_b);
  const fs::path dangling = base_ / ("dangling." + ext);
  fs::create_symlink(base_ / "nowhere", dangling);
  const fs::path folder = base_ / ("folder." + ext);
  fs::create_directories(folder);
  for (const std::string& command : commands) {
    expect_refused(command, fifo, "is a FIFO (named pipe), not a regular file", "fifo");
    expect_refused(command, device, "is a character device, not a regular file", "/dev/null");
    expect_refused(command, loop_a, "is a symbolic-link loop", "loop");
    expect_refused(command, dangling, "is a symbolic link to a file that does not exist", "dangling");
    expect_refused(command, folder, "is a directory, not a regular file", "folder");
    expect_refused(command, base_ / ("missing." + ext), "file does not exist", "missing");
  }
}

// A 2 GB file of zeros (sparse: it takes no disk) is refused without being read into memory (its
// time, a few hundredths of a second, is recorded, not asserted: speed belongs to benchmarks).
TEST_P(Corpus, HugeGarbageFileIsRefusedAtOnceWithLittleMemory) {
  const std::string ext = GetParam();
  const fs::path file = base_ / ("huge." + ext);
  { std::ofstream(file).put('\0'); }
  fs::resize_file(file, std::uintmax_t{2} << 30);
  const fs::path dir = fresh_dir();
  const std::vector<std::string> args =
      is_point_cloud_only(ext)
          ? std::vector<std::string>{"fit", "--target", file.string(), "--out", (dir / "fit").string()}
          : std::vector<std::string>{"info", file.string()};
  const ToolRun r = run_tool(args, dir);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(file.string()), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  RecordProperty("seconds", std::to_string(r.seconds));
  // The tool itself (VTK's libraries loaded) takes about 30 MB; a file read into memory 2 GB.
  EXPECT_LT(r.peak_rss_kb, 200 * 1024) << ext << ": peak RSS " << r.peak_rss_kb << " kB";
  RecordProperty("peak_rss_kb", std::to_string(r.peak_rss_kb));
}

INSTANTIATE_TEST_SUITE_P(Formats, Corpus,
                         ::testing::Values("obj", "off", "ply", "stl", "vtk", "vtp", "vtu", "xyz", "pwn"),
                         [](const ::testing::TestParamInfo<std::string>& param_info) {
                           return param_info.param;
                         });

}  // namespace
