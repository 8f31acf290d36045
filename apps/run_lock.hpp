#pragma once
// One run per folder. Two `adapt` runs (or a run and a `--resume` of it) writing into the
// same folder would leave a report of one and cycle files of the other, each run sure of
// its results. So a run holds a lock on its folder while it works: the file
// DIR/.rgbmesh-run.lock, locked with flock(2) and holding the process id (for the message
// of the run that is refused).
//
// flock locks end with the process, however it ends: a lock file left by a killed run
// (SIGKILL, a crash; the file stays, the lock does not) is taken over by the next run, with
// a note naming the process that left it. A run removes the file when it ends, also when
// SIGINT, SIGTERM or SIGHUP end it (remove_on_signals).

#include <filesystem>

namespace rgbmesh::cli {

inline constexpr const char* kRunLockFile = ".rgbmesh-run.lock";

class RunLock {
 public:
  // Locks the folder `dir`, which must exist. InputError (exit code 2: the run is refused,
  // nothing is written) naming the process that holds it; OutputError when the lock file
  // cannot be created (an unwritable folder). On a file system without locks: a note, and
  // the run goes ahead unguarded.
  explicit RunLock(const std::filesystem::path& dir);
  ~RunLock();
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

 private:
  std::filesystem::path file_;
  int fd_ = -1;
  int signal_registration_ = -1;
};

}  // namespace rgbmesh::cli
