#pragma once
/// \file
/// The three kinds of failure a user can act on, each with its own exit code in the CLI:
///
/// \verbatim
///   InputError     bad input or arguments (a file, a mesh, an option): exit code 2
///     MeshDefectError  a defect of the mesh itself that a repair can fix (rgbmesh::repair)
///   OutputError    an output could not be written (folder, disk full, size limit): exit code 1
///   ResourceError  the work needs more than the machine has (memory): exit code 3
/// \endverbatim
///
/// Anything else that escapes (std::bad_alloc, std::logic_error, solver failures) is an
/// internal failure or an exhausted resource: exit code 3 too. Messages are one line and name
/// the file, element or option concerned.

#include <stdexcept>
#include <string>

namespace rgbmesh {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A defect of the mesh itself (a degenerate or duplicate triangle, a non-manifold edge or vertex,
/// a non-orientable surface) rather than of the file: a repair (rgbmesh::repair, the tool's
/// --repair) removes it. hint() says how, in a few words that callers put after their own way of
/// asking for the repair ("--repair collapses degenerate triangles").
class MeshDefectError : public InputError {
 public:
  /// `hint` must be a string literal (stored as a pointer, so that copying never throws).
  MeshDefectError(const std::string& message, const char* hint) : InputError(message), hint_(hint) {}
  const char* hint() const noexcept { return hint_; }

 private:
  const char* hint_;
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
