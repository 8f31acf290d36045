#include "vtk_messages.hpp"

#include <vtkObjectFactory.h>

#include "rgbmesh/soup.hpp"

namespace rgbmesh::detail {

vtkStandardNewMacro(MessageCollector)

void run_reader(vtkAlgorithm& reader, const std::filesystem::path& path) {
  CapturedVtkMessages messages;
  try {
    reader.Update();
  } catch (const std::bad_alloc&) {
    // VTK allocates what the file announces; a corrupt count asks for more than there is.
    throw InputError(path.string() + ": cannot read: the file announces more data than fits in memory");
  }
  std::string error = messages.first_error();
  if (error.empty() && reader.GetErrorCode() != vtkErrorCode::NoError)
    error = vtkErrorCode::GetStringFromErrorCode(reader.GetErrorCode());
  if (!error.empty()) throw InputError(path.string() + ": cannot read: " + error);
}

}  // namespace rgbmesh::detail
