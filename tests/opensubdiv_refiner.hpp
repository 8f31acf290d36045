// OpenSubdiv's topology refiner for a triangle base mesh under Loop's rules, with boundary
// vertices interpolated along their edges (as RgbMesh does): the reference that the Loop tests
// refine, evaluate and limit.
#pragma once

#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <memory>
#include <vector>

#include "test_meshes.hpp"

namespace rgbmesh::testing {

inline std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> loop_refiner(const BaseMesh& base) {
  using namespace OpenSubdiv;
  std::vector<int> counts(base.triangles.size(), 3), indices;
  for (const auto& t : base.triangles) indices.insert(indices.end(), t.begin(), t.end());
  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(base.points.size());
  desc.numFaces = static_cast<int>(base.triangles.size());
  desc.numVertsPerFace = counts.data();
  desc.vertIndicesPerFace = indices.data();
  Sdc::Options options;
  options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  // Create copies the topology: the descriptor's arrays may go when it returns.
  return std::unique_ptr<Far::TopologyRefiner>(
      Factory::Create(desc, Factory::Options(Sdc::SCHEME_LOOP, options)));
}

}  // namespace rgbmesh::testing
