#include "run_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <thread>

#include "one_line.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh::cli {

namespace {

namespace fs = std::filesystem;

// The process id that a lock file holds; 0 if it holds none.
long holder_in(int fd) {
  char text[32] = {};
  const ssize_t n = ::pread(fd, text, sizeof text - 1, 0);
  if (n <= 0) return 0;
  const long pid = std::strtol(text, nullptr, 10);
  return pid > 0 ? pid : 0;
}

// The holder of a lock we could not take. It writes its id just after locking, so an empty
// file means "a moment": wait for the id rather than name no process.
long holder_of_busy_lock(int fd) {
  for (int i = 0; i < 100; ++i) {
    if (const long pid = holder_in(fd); pid > 0) return pid;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return 0;
}

// Whether `fd` is still the file at `path`. A run that ends removes its lock file; one that
// opened the file just before and locked it just after would hold a lock on a file no other
// run can see.
bool still_linked(int fd, const fs::path& path) {
  struct stat opened {}, named {};
  return ::fstat(fd, &opened) == 0 && ::stat(path.c_str(), &named) == 0 && opened.st_dev == named.st_dev &&
         opened.st_ino == named.st_ino;
}

[[noreturn]] void cannot_lock(const fs::path& dir, const std::string& why) {
  throw OutputError(dir.string() + ": cannot lock the run folder (" + kRunLockFile + "): " + why);
}

[[noreturn]] void busy(const fs::path& dir, long holder) {
  const std::string who = holder > 0 ? "process " + std::to_string(holder) : "a process";
  throw InputError(dir.string() + ": another rgbmesh run (" + who +
                   ") is writing into this folder: wait for it to end, or use another folder");
}

}  // namespace

RunLock::RunLock(const fs::path& dir) : file_(dir / kRunLockFile) {
  for (int attempt = 0;; ++attempt) {
    fd_ = ::open(file_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) cannot_lock(dir, std::strerror(errno));
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      const long holder = error == EWOULDBLOCK ? holder_of_busy_lock(fd_) : 0;
      ::close(fd_);
      fd_ = -1;
      if (error == EWOULDBLOCK) busy(dir, holder);
      if (error == ENOLCK || error == EOPNOTSUPP) {
        // A file system without locks (some network mounts): the run goes ahead unguarded
        // rather than not at all.
        ::unlink(file_.c_str());
        std::cerr << "rgbmesh: note: " << one_line(dir.string())
                  << ": cannot lock the run folder (the file system has no locks): a second run into it would not "
                     "be refused\n";
        return;
      }
      cannot_lock(dir, std::strerror(error));
    }
    if (still_linked(fd_, file_)) break;
    ::close(fd_);
    if (attempt == 100) cannot_lock(dir, "the lock file keeps disappearing");
  }
  // Held now. An id in the file is a run that ended without removing it: killed.
  const long previous = holder_in(fd_);
  if (previous > 0 && previous != static_cast<long>(::getpid()))
    std::cerr << "rgbmesh: note: " << one_line(dir.string()) << ": took over the lock of process " << previous
              << ", which ended without releasing it (killed?)\n";
  // Written before the old contents are cut, so a reader always finds an id.
  const std::string id = std::to_string(::getpid()) + "\n";
  if (::pwrite(fd_, id.data(), id.size(), 0) != static_cast<ssize_t>(id.size()) ||
      ::ftruncate(fd_, static_cast<off_t>(id.size())) != 0) {
    const int error = errno;
    ::unlink(file_.c_str());
    ::close(fd_);
    cannot_lock(dir, std::strerror(error));
  }
  signal_registration_ = remove_on_signals(file_);
}

RunLock::~RunLock() {
  if (fd_ < 0) return;  // unguarded (no locks on the file system)
  forget_on_signals(signal_registration_);
  // Removed while still locked: a run that opens the file now finds it gone once it holds
  // the lock (still_linked), and starts over with a new one.
  ::unlink(file_.c_str());
  ::close(fd_);
}

}  // namespace rgbmesh::cli
