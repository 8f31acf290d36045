#pragma once
// Progress lines on stderr for work that takes more than two seconds: writing an output file
// (the compression of VTK XML files, --compression, goes with it), and the stages of `fit`.

#include <chrono>
#include <string>

#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh::cli {

// One task's progress: nothing during its first two seconds; after that "rgbmesh: TASK: 40%,
// 3.1 s" (or "rgbmesh: TASK: 3.1 s" when the fraction is unknown, negative), rewritten in place
// at most every second on a terminal, a new line every 5 seconds otherwise, and a last line
// once finish() is called or the fraction reaches 1, if anything was printed.
class ProgressLine {
 public:
  explicit ProgressLine(std::string task);
  void update(double fraction);
  void finish();
  const std::string& task() const { return task_; }

 private:
  using clock = std::chrono::steady_clock;
  void print(double fraction, double seconds, bool last);
  std::string task_;
  clock::time_point start_;
  bool tty_;
  bool printed_ = false, finished_ = false;
  double next_ = 0, last_fraction_ = -1;
};

// Options for writing `path`: the compression, and a ProgressLine "writing PATH".
WriteOptions output_options(const std::string& path, Compression compression);

}  // namespace rgbmesh::cli
