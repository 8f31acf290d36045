#include "write_progress.hpp"

#include <unistd.h>

#include <cstdio>
#include <memory>

#include "one_line.hpp"

namespace rgbmesh::cli {

ProgressLine::ProgressLine(std::string task) : task_(one_line(task)), start_(clock::now()), tty_(isatty(2) != 0) {}

void ProgressLine::print(double fraction, double seconds, bool last) {
  if (fraction >= 0)
    std::fprintf(stderr, "%srgbmesh: %s: %.0f%%, %.1f s%s", tty_ ? "\r" : "", task_.c_str(), 100.0 * fraction, seconds,
                 tty_ && !last ? "" : "\n");
  else
    std::fprintf(stderr, "%srgbmesh: %s: %.1f s%s", tty_ ? "\r" : "", task_.c_str(), seconds,
                 tty_ && !last ? "" : "\n");
  std::fflush(stderr);
  printed_ = true;
}

void ProgressLine::update(double fraction) {
  if (finished_) return;
  const double t = std::chrono::duration<double>(clock::now() - start_).count();
  last_fraction_ = fraction;
  if (fraction >= 1.0) {
    finish();
    return;
  }
  if (t < 2.0 || t < next_) return;
  next_ = t + (tty_ ? 1.0 : 5.0);
  print(fraction, t, false);
}

void ProgressLine::finish() {
  if (finished_) return;
  finished_ = true;
  if (!printed_) return;
  const double t = std::chrono::duration<double>(clock::now() - start_).count();
  print(last_fraction_ >= 0 ? 1.0 : -1.0, t, true);
}

WriteOptions output_options(const std::string& path, Compression compression) {
  WriteOptions options;
  options.compression = compression;
  // Shared: WriteOptions (and its std::function) may be copied.
  auto progress = std::make_shared<ProgressLine>("writing " + path);
  options.progress = [progress](double fraction) { progress->update(fraction); };
  return options;
}

}  // namespace rgbmesh::cli
