// rgbmesh::parallel::distribute (adaptive.hpp): the hooks of adapt::AdaptOptions for a run on
// all processes.

#include "rgbmesh/parallel/adaptive.hpp"

#include "rgbmesh/parallel/mpi.hpp"
#include "rgbmesh/parallel/partition.hpp"

namespace rgbmesh::parallel {

void distribute(adapt::AdaptOptions& options) {
  const int parts = processes();
  if (parts <= 1) return;
  const int floor = options.min_level;
  // The floor's uniform mesh is kept from cycle to cycle (FloorCache).
  options.distribution.partition = [floor, parts, cache = make_floor_cache()](const RgbMesh& mesh,
                                                                              const fem::SurfaceMesh& fe) {
    return triangle_parts(mesh, fe, floor, parts, cache.get());
  };
  options.distribution.share.process = rank();
  options.distribution.share.sum = sum;
  options.distribution.share.gather = gather;
  options.distribution.bytes_sent = bytes_sent_since_last;
  options.solve.shared_solver = shared_amg();  // (the systems are always assembled in parts here)
}

}  // namespace rgbmesh::parallel
