// OpenSubdiv's topology refiner for a triangle base mesh under Loop's rules, with boundary
// vertices interpolated along their edges (as RgbMesh does) and the mesh's creases, corners and
// creasing method: the reference that the Loop tests refine, evaluate and limit.
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
  std::vector<int> crease_ends, corners;
  std::vector<float> crease_weights, corner_weights;
  for (const SharpEdge& e : base.sharp.edges) {
    crease_ends.push_back(e.a);
    crease_ends.push_back(e.b);
    crease_weights.push_back(e.sharpness);
  }
  for (const SharpVertex& v : base.sharp.vertices) {
    corners.push_back(v.v);
    corner_weights.push_back(v.sharpness);
  }
  desc.numCreases = static_cast<int>(crease_weights.size());
  desc.creaseVertexIndexPairs = crease_ends.data();
  desc.creaseWeights = crease_weights.data();
  desc.numCorners = static_cast<int>(corners.size());
  desc.cornerVertexIndices = corners.data();
  desc.cornerWeights = corner_weights.data();
  Sdc::Options options;
  options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  options.SetCreasingMethod(base.sharp.method == CreaseMethod::chaikin ? Sdc::Options::CREASE_CHAIKIN
                                                                        : Sdc::Options::CREASE_UNIFORM);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  // Create copies the topology: the descriptor's arrays may go when it returns.
  return std::unique_ptr<Far::TopologyRefiner>(
      Factory::Create(desc, Factory::Options(Sdc::SCHEME_LOOP, options)));
}

}  // namespace rgbmesh::testing
