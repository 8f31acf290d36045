// Fuzz target through a file: VTP or VTU (RGBMESH_FUZZ_EXTENSION), whose reading path needs a
// file name since VTK's XML readers open the file themselves. Each input is written to a
// per-process scratch file and read as a mesh and as a point cloud.

#include <cstdint>
#include <string>

#include "fuzz_support.hpp"
#include "rgbmesh/vtk_io.hpp"

using namespace rgbmesh;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fuzz::ScratchInput input(RGBMESH_FUZZ_EXTENSION, data, size);
  fuzz::accepted([&] { read_polygon_soup(input.path()); });
  PointCloud cloud;
  if (fuzz::accepted([&] { cloud = read_point_cloud(input.path()); })) {
    // read_point_cloud's contract: one normal per point, or none.
    if (!cloud.normals.empty() && cloud.normals.size() != cloud.points.size())
      fuzz::finding("read_point_cloud gave " + std::to_string(cloud.normals.size()) + " normals for " +
                    std::to_string(cloud.points.size()) + " points");
  }
  return 0;
}
