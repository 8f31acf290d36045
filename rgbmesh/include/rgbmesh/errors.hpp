#pragma once
/// \file
/// The three kinds of failure a user can act on, each with its own exit code in the CLI:
///
/// \verbatim
///   InputError     bad input or arguments (a file, a mesh, an option): exit code 2
///   OutputError    an output could not be written (folder, disk full, size limit): exit code 1
///   ResourceError  the work needs more than the machine has (memory): exit code 3
/// \endverbatim
///
/// Anything else that escapes (std::bad_alloc, std::logic_error, solver failures) is an
/// internal failure or an exhausted resource: exit code 3 too. Messages are one line and name
/// the file, element or option concerned.

#include <stdexcept>

namespace rgbmesh {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ResourceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rgbmesh
