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
/// Anything else that escapes (std::bad_alloc, std::logic_error such as PreconditionError,
/// solver failures) is an internal failure or an exhausted resource: exit code 3 too. Messages are one line
/// and name the file, element or option concerned.

#include <stdexcept>
#include <string>
#include <vector>

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

/// A mesh operator was called where it does not apply (a dead or stale handle, the wrong
/// configuration): a programming error, not bad input (RgbMesh's operators check it).
class PreconditionError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

/// A name and what it stands for: a row of a table of named choices with nothing more to say
/// (adapt::strategy_table, the tool's --problem and --geometry).
template <class T>
struct Named {
  const char* name;
  T value;
};

/// The row whose `name` is `value` in a table of named choices (fem::estimator_table,
/// adapt::marking_table: rows with a `name` member); InputError "option: 'value' is not one of
/// a, b, c" otherwise. The command line and Python read the same tables through it.
template <class Row>
const Row& named_row(const std::vector<Row>& table, const std::string& value, const std::string& option) {
  std::string names;
  for (const Row& row : table) {
    if (value == row.name) return row;
    names += (names.empty() ? "" : ", ") + std::string(row.name);
  }
  throw InputError(option + ": '" + value + "' is not one of " + names);
}

}  // namespace rgbmesh
