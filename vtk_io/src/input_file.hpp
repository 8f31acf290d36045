#pragma once
// An input file opened for reading: refused unless it is a regular file, then mapped into memory
// read-only so that the parsers work on its bytes without copying them. Pages are read from disk
// only when a parser touches them, so a huge file that is rejected on its first bytes costs
// neither time nor memory, and a file that is read costs what its pages cost, once.

#include <cstddef>
#include <filesystem>
#include <string_view>

namespace rgbmesh::detail {

class InputFile {
 public:
  // InputError naming `path` and the reason: it does not exist, is a dangling symbolic link or
  // a symbolic-link loop, cannot be opened (permissions), or is not a regular file (a directory,
  // FIFO, socket or device, named as such). An empty file gives an empty view.
  explicit InputFile(const std::filesystem::path& path);
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  // The whole file. A file truncated by another process while it is mapped makes reading the
  // lost pages raise SIGBUS; that race is accepted (every reader of a changing file loses).
  std::string_view bytes() const { return {static_cast<const char*>(data_), size_}; }
  std::size_t size() const { return size_; }

 private:
  void* data_ = nullptr;
  std::size_t size_ = 0;
};

// A UTF-8 byte-order mark, which some editors put at the start of text files. Text formats skip
// it (it is not part of the first line); binary formats never call this.
std::string_view without_utf8_bom(std::string_view text);

}  // namespace rgbmesh::detail
