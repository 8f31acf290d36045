#include "atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>
#include <stdexcept>

#include "rgbmesh/errors.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Temporaries in flight, for the signal handler. The handler may only use async-signal-safe
// calls, so the paths sit in fixed buffers claimed through atomic flags (no allocation, no lock).

struct TemporarySlot {
  std::atomic<bool> used{false};
  char path[4096] = {};
};
std::array<TemporarySlot, 32> temporaries;

// Claims a slot for `path`; -1 if all are taken (the file is then only cleaned up by the normal
// error path) or the path is too long for the buffer.
int register_temporary(const fs::path& path) {
  const std::string text = path.string();
  if (text.size() + 1 > sizeof(TemporarySlot::path)) return -1;
  for (std::size_t i = 0; i < temporaries.size(); ++i) {
    bool expected = false;
    if (!temporaries[i].used.load() && temporaries[i].used.compare_exchange_strong(expected, true)) {
      // The flag is set before the path is complete: the handler may unlink an empty or partial
      // name, which names no file of ours (a partial name would need our ".tmp-PID-N" suffix).
      std::memcpy(temporaries[i].path, text.c_str(), text.size() + 1);
      return static_cast<int>(i);
    }
  }
  return -1;
}

void unregister_temporary(int slot) {
  if (slot < 0) return;
  temporaries[static_cast<std::size_t>(slot)].path[0] = '\0';
  temporaries[static_cast<std::size_t>(slot)].used.store(false);
}

extern "C" void remove_temporaries_and_die(int signal_number) {
  for (TemporarySlot& slot : temporaries) {
    if (slot.used.load() && slot.path[0] != '\0') ::unlink(slot.path);
  }
  // Die of the same signal, so that the parent sees what happened (shells print it, and
  // exit status 128 + N follows).
  ::signal(signal_number, SIG_DFL);
  ::raise(signal_number);
}

// A hidden sibling with the same extension (writers pick formats by it), unique per process and
// call so that concurrent writes do not collide.
fs::path temporary_path_for(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  const std::string name = "." + target.stem().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                           std::to_string(counter++) + target.extension().string();
  return target.parent_path() / name;
}

// Without this the rename can reach the disk before the data, and a crash leaves an empty
// target.
void flush_to_disk(const fs::path& file) {
  const int fd = ::open(file.c_str(), O_RDONLY);
  if (fd < 0) throw std::runtime_error(std::string("cannot reopen the written file: ") + std::strerror(errno));
  const int synced = ::fsync(fd);
  const int sync_errno = errno;
  ::close(fd);
  if (synced != 0) throw std::runtime_error(std::string("cannot flush to disk: ") + std::strerror(sync_errno));
}

// The file a target path finally names: a symbolic link (or a chain of them) is followed, so
// that the link survives the rename and leads to the new content. A link to a missing file
// leads to where that file will be.
fs::path final_target(const fs::path& target) {
  fs::path path = target;
  for (int hops = 0; hops < 40; ++hops) {
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(path, ec))) return path;
    const fs::path next = fs::read_symlink(path, ec);
    if (ec) throw std::runtime_error("cannot follow the symbolic link: " + ec.message());
    path = next.is_absolute() ? next : path.parent_path() / next;
  }
  throw std::runtime_error("too many levels of symbolic links");
}

}  // namespace

void remove_temporaries_on_signals() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (const int s : {SIGINT, SIGTERM, SIGHUP}) {
      struct sigaction current {};
      if (::sigaction(s, nullptr, &current) != 0) continue;
      // A signal the host ignores (nohup) or handles itself is left alone.
      if (current.sa_handler != SIG_DFL || (current.sa_flags & SA_SIGINFO) != 0) continue;
      struct sigaction action {};
      action.sa_handler = remove_temporaries_and_die;
      sigemptyset(&action.sa_mask);
      ::sigaction(s, &action, nullptr);
    }
    // Exceeding the file-size limit (ulimit -f) raises SIGXFSZ, whose default action kills the
    // process before any cleanup. Ignored, the write fails with EFBIG instead, and the normal
    // error path removes the temporary and reports the failure (exit code 1).
    struct sigaction current {};
    if (::sigaction(SIGXFSZ, nullptr, &current) == 0 && current.sa_handler == SIG_DFL) {
      struct sigaction ignore {};
      ignore.sa_handler = SIG_IGN;
      sigemptyset(&ignore.sa_mask);
      ::sigaction(SIGXFSZ, &ignore, nullptr);
    }
  });
}

int remove_on_signals(const fs::path& path) { return register_temporary(path); }

void forget_on_signals(int registration) { unregister_temporary(registration); }

namespace detail {

void replace_atomically(const fs::path& requested, const std::function<void(const fs::path&)>& write) {
  fs::path target;
  try {
    target = final_target(requested);
  } catch (const std::exception& e) {
    throw OutputError(requested.string() + ": cannot write: " + e.what());
  }
  std::error_code status_error;
  if (fs::is_directory(target, status_error))
    throw OutputError(requested.string() + ": cannot write: it is a folder");
  const fs::path temp = temporary_path_for(target);
  const int slot = register_temporary(temp);
  const auto discard = [&] {
    std::error_code ignored;
    fs::remove(temp, ignored);
    unregister_temporary(slot);
  };
  try {
    // Created here first, so that a folder the process cannot write to is reported with the
    // system's reason and the folder's name, whatever writer comes next (VTK's name only the
    // temporary file, without a reason).
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
      const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
      throw std::runtime_error("cannot create a file in the folder " + folder.string() + ": " + std::strerror(errno));
    }
    ::close(fd);
    write(temp);
    if (!fs::is_regular_file(temp)) throw std::runtime_error("the writer created no file");
    flush_to_disk(temp);
    std::error_code ec;
    fs::rename(temp, target, ec);
    if (ec) throw std::runtime_error("cannot rename the temporary file onto it: " + ec.message());
    unregister_temporary(slot);
  } catch (const InputError&) {
    discard();
    throw;
  } catch (const std::invalid_argument&) {
    discard();
    throw;
  } catch (const std::bad_alloc&) {
    discard();
    throw;
  } catch (const std::exception& e) {
    discard();
    throw OutputError(requested.string() + ": cannot write: " + e.what());
  }
}

CheckedFile::CheckedFile(const fs::path& file) : out_(file, std::ios::binary) {
  if (!out_) throw std::runtime_error(std::string("cannot create the file: ") + std::strerror(errno));
}

void CheckedFile::append(std::string_view text) {
  buffer_ += text;
  if (buffer_.size() >= (1u << 20)) flush();
}

void CheckedFile::close() {
  flush();
  out_.close();
  if (!out_) throw std::runtime_error(std::string("write failed: ") + std::strerror(errno));
}

void CheckedFile::flush() {
  out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  buffer_.clear();
  if (!out_) throw std::runtime_error(std::string("write failed: ") + std::strerror(errno));
}

void write_bytes(const fs::path& file, std::string_view contents) {
  CheckedFile out(file);
  out.append(contents);
  out.close();
}

}  // namespace detail
}  // namespace rgbmesh
