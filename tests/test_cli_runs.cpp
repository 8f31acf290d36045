// Runs and their folders, where a user could lose work (issue 24): two runs on one folder
// (the second is refused, naming the first's process; a killed run's lock is taken over), a
// run that fails while writing (its report says so), paths that would break a message in
// two or are empty, and a --memory-limit above what the machine has.

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "cli_fixture.hpp"

namespace {

using namespace rgbmesh::testing;

constexpr const char* kLock = "/.rgbmesh-run.lock";

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

// The lock of `dir` held by this test process, as a running `adapt` holds it.
class HeldLock {
 public:
  explicit HeldLock(const std::string& dir) : fd_(::open((dir + kLock).c_str(), O_RDWR | O_CREAT, 0644)) {
    EXPECT_GE(fd_, 0);
    EXPECT_EQ(::flock(fd_, LOCK_EX | LOCK_NB), 0);
    const std::string id = std::to_string(::getpid()) + "\n";
    EXPECT_EQ(::write(fd_, id.data(), id.size()), static_cast<ssize_t>(id.size()));
  }
  ~HeldLock() { ::close(fd_); }

 private:
  int fd_;
};

// A long moving-peak run writing into `dir`, started in the background; its process id once
// the folder's lock exists, or -1 (the run ended) if it never does.
pid_t start_long_run(const std::string& dir) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::freopen("/dev/null", "w", stdout);
    std::freopen("/dev/null", "w", stderr);
    ::execl(RGBMESH_CLI, RGBMESH_CLI, "adapt", "--problem", "moving-peak", "--steps", "100000", "--out", dir.c_str(),
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!fs::exists(dir + kLock) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  if (fs::exists(dir + kLock)) return pid;
  ::kill(pid, SIGKILL);
  ::waitpid(pid, nullptr, 0);
  return -1;
}

TEST_F(Cli, ASecondRunOnTheSameFolderIsRefusedNamingTheFirst) {
  // Both used to exit 0, leaving the report of one run beside the cycles of the other.
  const std::string dir = path("run");
  const pid_t first = start_long_run(dir);
  ASSERT_GT(first, 0);
  const RunResult second = run("adapt --cycles 3 --out " + dir);
  const RunResult resumed = run("adapt --resume " + dir + " --cycles 30");
  ::kill(first, SIGTERM);
  int status = 0;
  ::waitpid(first, &status, 0);
  for (const RunResult* r : {&second, &resumed}) {
    EXPECT_EQ(r->code, 2) << r->err;
    EXPECT_EQ(lines(r->err), 1) << r->err;
    EXPECT_NE(r->err.find(dir + ": another rgbmesh run (process " + std::to_string(first) + ") is writing into this folder"),
              std::string::npos)
        << r->err;
  }
  EXPECT_FALSE(fs::exists(dir + "/cycle_002.vtp")) << "the refused run wrote nothing";
  // Ended by SIGTERM, the first run removed its lock (and died of the signal, as before).
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_FALSE(fs::exists(dir + kLock));
}

TEST_F(Cli, ALockHeldElsewhereRefusesNewResumedAndFitRuns) {
  const std::string dir = path("run");
  ASSERT_EQ(run("adapt --cycles 3 --out " + dir).code, 0);
  EXPECT_FALSE(fs::exists(dir + kLock)) << "a run that ends removes its lock";
  const std::string report = read_text(dir + "/report.json");
  {
    const HeldLock held(dir);
    const std::string octa = write_octahedron("octa.off");
    for (const std::string& args : {"adapt --cycles 2 --out " + dir, "adapt --resume " + dir + " --cycles 5",
                                    "fit --target " + octa + " --iterations 1 --out " + dir}) {
      const RunResult r = run(args);
      EXPECT_EQ(r.code, 2) << args << ": " << r.err;
      // (fit may note what it makes of the target first)
      EXPECT_EQ(last_line(r.err).rfind("rgbmesh: error: " + dir + ": another rgbmesh run (process " +
                                           std::to_string(::getpid()) + ")",
                                       0),
                0u)
          << args << ": " << r.err;
    }
    EXPECT_EQ(read_text(dir + "/report.json"), report) << "nothing was removed or rewritten";
    EXPECT_TRUE(fs::exists(dir + "/cycle_002.vtp"));
  }
  // Released: the resumed run goes ahead.
  ASSERT_EQ(run("adapt --resume " + dir + " --cycles 5").code, 0);
}

TEST_F(Cli, AKilledRunsLockIsTakenOverWithANote) {
  // SIGKILL leaves the lock file (not the lock): the next run takes it over and says whose
  // it was.
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ::waitpid(dead, nullptr, 0);
  const std::string dir = path("run");
  fs::create_directories(dir);
  std::ofstream(dir + kLock) << dead << "\n";
  const RunResult r = run("adapt --cycles 2 --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("rgbmesh: note: " + dir + ": took over the lock of process " + std::to_string(dead) +
                       ", which ended without releasing it"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir + kLock));
  // The same for a resumed run.
  std::ofstream(dir + kLock) << dead << "\n";
  const RunResult resumed = run("adapt --resume " + dir + " --cycles 3");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_NE(resumed.err.find("took over the lock of process " + std::to_string(dead)), std::string::npos) << resumed.err;
}

TEST_F(Cli, AWriteFailureLeavesAReportThatSaysFailedAndWhy) {
  // A full disk, as the file-size limit simulates it (1 MB: the later cycles' files are
  // larger, the report is not): the report said "running" after the run had ended.
  const std::string dir = path("run");
  const std::string cmd = "bash -c 'ulimit -f 200; exec " + std::string(RGBMESH_CLI) + " adapt --out " + dir +
                          "' >/dev/null 2>" + path("err.txt");
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1) << "an output that cannot be written";
  const std::string err = read_text(path("err.txt")), report = read_text(dir + "/report.json");
  EXPECT_EQ(lines(err), 1) << err;
  EXPECT_NE(report.find("\"status\": \"failed\", \"stopped\": \"error\""), std::string::npos) << report;
  const auto said = err.find(dir + "/cycle_");
  ASSERT_NE(said, std::string::npos) << err;
  EXPECT_NE(report.find("\"stop_message\": \"" + err.substr(said, err.size() - said - 1) + "\""), std::string::npos)
      << "the report gives the reason the tool printed: " << err << "\n" << report;
  EXPECT_FALSE(fs::exists(dir + kLock));
  // The cycles it finished are there to resume from.
  const RunResult resumed = run("adapt --resume " + dir);
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_NE(read_text(dir + "/report.json").find("\"status\": \"finished\""), std::string::npos);
}

TEST_F(Cli, APathWithANewlineGivesOneLine) {
  // Paths are the user's: a newline in one used to split the error in two.
  const std::string odd = path("no\nsuch");
  for (const std::string& args : {"info \"" + odd + ".obj\"", "adapt --resume \"" + odd + "\"",
                                  "adapt --mesh \"" + odd + ".off\" --out " + path("a"),
                                  "refine \"" + odd + ".obj\" " + path("x.vtp") + " --uniform 1"}) {
    const RunResult r = run(args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("no\\nsuch"), std::string::npos) << args << ": " << r.err;
  }
  // An output folder named so still works: only messages escape the name.
  const RunResult r = run("adapt --cycles 1 --out \"" + odd + "\"");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(odd + "/cycle_000.vtp"));
}

TEST_F(Cli, EveryPathRefusesAnEmptyValue) {
  // An unset shell variable: adapt --mesh "" ran the embedded icosahedron and fit --base ""
  // built a base of its own, without a word; the others named a format ''.
  const std::string octa = write_octahedron("octa.off");
  for (const std::string& args :
       {"adapt --mesh \"\" --cycles 1 --out " + path("a"), "fit --target " + octa + " --base \"\" --out " + path("f"),
        "fit --target \"\" --out " + path("f"), std::string("info \"\""), "convert \"\" " + path("x.obj"),
        "convert " + octa + " \"\"", "refine \"\" " + path("x.obj") + " --uniform 1",
        "refine " + octa + " \"\" --uniform 1"}) {
    const RunResult r = run(args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("must name a file or folder, got an empty string"), std::string::npos) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(path("a")) || fs::exists(path("f")) || fs::exists(path("x.obj"))) << args;
  }
}

TEST_F(Cli, AMemoryLimitAboveTheMachinesIsCappedWithANote) {
  // 64 TB, or a number far past any machine: the up-front refusals used to be switched off.
  const std::string octa = write_octahedron("octa.off");
  for (const char* limit : {"64T", "99999999999999999999T"}) {
    const RunResult r = run(std::string("--memory-limit ") + limit + " refine " + octa + " - --uniform 30");
    EXPECT_EQ(r.code, 3) << limit << ": " << r.err;
    EXPECT_NE(r.err.find(std::string("rgbmesh: note: --memory-limit ") + limit + " is more than the "),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("of memory the machine has: the ceiling is "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("stage --uniform 30: the mesh at level 30 would have"), std::string::npos) << r.err;
    EXPECT_EQ(lines(without_rounding_note(r.err)), 2) << r.err;
  }
  // A limit the machine has is taken as given, without a note.
  const RunResult fits = run("--memory-limit 500M refine " + octa + " - --uniform 2");
  EXPECT_EQ(fits.code, 0) << fits.err;
  EXPECT_EQ(without_rounding_note(fits.err), "");
}

}  // namespace
