#include "write_progress.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <memory>

namespace rgbmesh::cli {

namespace {

class WriteProgress {
 public:
  explicit WriteProgress(std::string path) : path_(std::move(path)), start_(clock::now()), tty_(isatty(2) != 0) {}

  void update(double fraction) {
    const double t = std::chrono::duration<double>(clock::now() - start_).count();
    const bool done = fraction >= 1.0;
    if (done ? !printed_ : (t < 2.0 || t < next_)) return;
    next_ = t + (tty_ ? 1.0 : 5.0);
    std::fprintf(stderr, "%srgbmesh: writing %s: %.0f%%, %.1f s%s", tty_ ? "\r" : "", path_.c_str(),
                 100.0 * fraction, t, tty_ && !done ? "" : "\n");
    std::fflush(stderr);
    printed_ = true;
  }

 private:
  using clock = std::chrono::steady_clock;
  std::string path_;
  clock::time_point start_;
  bool tty_;
  bool printed_ = false;
  double next_ = 0;
};

}  // namespace

WriteOptions output_options(const std::string& path, Compression compression) {
  WriteOptions options;
  options.compression = compression;
  // Shared: WriteOptions (and its std::function) may be copied.
  auto progress = std::make_shared<WriteProgress>(path);
  options.progress = [progress](double fraction) { progress->update(fraction); };
  return options;
}

}  // namespace rgbmesh::cli
