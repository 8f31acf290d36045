#pragma once
// Atomic replacement of output files: write a hidden temporary sibling, flush it to disk,
// rename it onto the target. The temporary is removed on every failure, and on SIGINT, SIGTERM
// and SIGHUP while it exists (rgbmesh::remove_temporaries_on_signals in vtk_io.hpp).

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <string_view>

namespace rgbmesh::detail {

// Runs write(temp), then renames the temporary onto the target; on any failure the temporary
// is removed, the target left as it was, and an OutputError naming the target thrown (an
// InputError or std::invalid_argument from `write` passes through unchanged). A target that is
// a symbolic link stays one: the file it leads to is replaced.
void replace_atomically(const std::filesystem::path& target, const std::function<void(const std::filesystem::path&)>& write);

// A new file written through a buffer, with every failure (full disk, size limit) reported as
// std::runtime_error.
class CheckedFile {
 public:
  explicit CheckedFile(const std::filesystem::path& file);
  void append(std::string_view text);
  void close();

 private:
  void flush();
  std::ofstream out_;
  std::string buffer_;
};

void write_bytes(const std::filesystem::path& file, std::string_view contents);

}  // namespace rgbmesh::detail
