#include "input_file.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "rgbmesh/errors.hpp"

namespace rgbmesh::detail {
namespace {

// What a file that is not a regular file is, for the message.
const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  return "not a regular file";
}

InputError not_regular(const std::string& path, mode_t mode) {
  return InputError(path + ": is " + kind_of(mode) + ", not a regular file: only regular files are read");
}

// The reason stat() or open() failed, in the words a user needs.
InputError unusable(const std::string& path, int error) {
  switch (error) {
    case ENOENT: {
      struct stat link {};
      if (::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode))
        return InputError(path + ": is a symbolic link to a file that does not exist");
      return InputError(path + ": file does not exist");
    }
    case ELOOP:
      return InputError(path + ": is a symbolic-link loop (too many levels of symbolic links)");
    case ENOTDIR:
      return InputError(path + ": file does not exist (a part of the path is not a directory)");
    default:
      return InputError(path + ": cannot open the file: " + std::strerror(error));
  }
}

}  // namespace

InputFile::InputFile(const std::filesystem::path& path) {
  const std::string name = path.string();
  // stat() first: opening a FIFO would wait for a writer, opening a device could have effects.
  struct stat status {};
  if (::stat(name.c_str(), &status) != 0) throw unusable(name, errno);
  if (!S_ISREG(status.st_mode)) throw not_regular(name, status.st_mode);
  // O_NONBLOCK: should the file have been replaced by a FIFO since, open() must not wait; the
  // fstat() below refuses it.
  const int fd = ::open(name.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) throw unusable(name, errno);
  if (::fstat(fd, &status) != 0 || !S_ISREG(status.st_mode)) {
    const mode_t mode = status.st_mode;
    ::close(fd);
    throw not_regular(name, mode);
  }
  size_ = static_cast<std::size_t>(status.st_size);
  if (size_ == 0) {  // nothing to map (mmap refuses a length of 0)
    ::close(fd);
    return;
  }
  data_ = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
  const int map_error = errno;
  ::close(fd);  // the mapping keeps the file
  if (data_ == MAP_FAILED) {
    data_ = nullptr;
    throw InputError(name + ": cannot read the file: " + std::strerror(map_error));
  }
  // The parsers read front to back: let the kernel read ahead and drop pages behind.
  ::madvise(data_, size_, MADV_SEQUENTIAL);
}

InputFile::~InputFile() {
  if (data_ != nullptr) ::munmap(data_, size_);
}

std::string_view without_utf8_bom(std::string_view text) {
  constexpr std::string_view bom = "\xEF\xBB\xBF";
  if (text.substr(0, bom.size()) == bom) text.remove_prefix(bom.size());
  return text;
}

}  // namespace rgbmesh::detail
