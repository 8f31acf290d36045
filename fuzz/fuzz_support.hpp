#pragma once
// What the fuzz targets share: which outcomes are normal, how a broken invariant is reported,
// and the scratch file of the targets that read through a file.
//
// Normal: the reader accepts the input, or refuses it with an InputError. Everything else is a
// finding: a sanitizer report, a crash, a timeout, a memory blow-up (libFuzzer's -rss_limit_mb
// and -malloc_limit_mb), any other exception, and the invariants checked here.

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "rgbmesh/errors.hpp"

namespace rgbmesh::fuzz {

// A broken invariant that no sanitizer sees: printed, then abort(), which libFuzzer reports as a
// crash and saves the input for.
[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "rgbmesh fuzz finding: %s\n", what.c_str());
  std::abort();
}

// Runs `read`; false when it refuses the input with an InputError. Any other exception is not
// caught anywhere: with no handler on the stack, std::terminate runs at the throw itself, so the
// crash report's stack trace shows where it was thrown.
template <class Read>
bool accepted(Read&& read) {
  try {
    read();
    return true;
  } catch (const InputError&) {
    return false;
  }
}

// One file per process (its pid in the name), in /dev/shm when it can be written (no disk
// writes for millions of inputs), else in $TMPDIR or /tmp. Each input is written, read, and
// removed again by ScratchInput.
inline const std::filesystem::path& scratch_path(const char* extension) {
  static const std::filesystem::path path = [extension] {
    std::string dir = "/tmp";
    if (::access("/dev/shm", W_OK) == 0)
      dir = "/dev/shm";
    else if (const char* tmp = std::getenv("TMPDIR"); tmp != nullptr && *tmp != '\0')
      dir = tmp;
    return std::filesystem::path(dir) / ("rgbmesh-fuzz-" + std::to_string(::getpid()) + extension);
  }();
  return path;
}

class ScratchInput {
 public:
  ScratchInput(const char* extension, const std::uint8_t* data, std::size_t size)
      : path_(scratch_path(extension)) {
    const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd < 0) environment_failure("cannot create");
    for (std::size_t done = 0; done < size;) {
      const ::ssize_t n = ::write(fd, data + done, size - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) environment_failure("cannot write");
      done += static_cast<std::size_t>(n);
    }
    if (::close(fd) != 0) environment_failure("cannot write");
  }
  ~ScratchInput() { ::unlink(path_.c_str()); }
  ScratchInput(const ScratchInput&) = delete;
  ScratchInput& operator=(const ScratchInput&) = delete;

  const std::filesystem::path& path() const { return path_; }

 private:
  // Not a finding: the machine, not rgbmesh, failed (a full /dev/shm). Exits without the
  // abort() that would make libFuzzer save the input as a crash.
  [[noreturn]] void environment_failure(const char* what) const {
    std::fprintf(stderr, "rgbmesh fuzz: %s the scratch file %s: %s\n", what, path_.c_str(),
                 std::strerror(errno));
    std::_Exit(75);
  }

  const std::filesystem::path& path_;
};

}  // namespace rgbmesh::fuzz
