#include <iostream>

#include "one_line.hpp"
#include "processes.hpp"
#include "rgbmesh/parallel/mpi.hpp"
#include "rgbmesh/parallel/adaptive.hpp"
#include "rgbmesh/parallel/distributed_mesh.hpp"

namespace rgbmesh::cli {

Processes start_processes(int* argc, char*** argv) {
  Processes p;
  if (!parallel::launched_by_mpi()) return p;
  parallel::initialize(argc, argv);
  p.rank = parallel::rank();
  p.count = parallel::processes();
  if (p.rank != 0) {
    std::cout.setstate(std::ios::badbit);
    std::cerr.setstate(std::ios::badbit);
  }
  return p;
}

void distribute(AdaptArgs& args, const Processes& processes) {
  if (processes.count <= 1) return;
  args.writes = processes.rank == 0;
  args.processes = processes.count;
  args.rank = processes.rank;
  args.distribute = [](adapt::AdaptOptions& o, bool may_distribute_mesh) {
    adapt::AdaptOptions probe = o;
    probe.control.resumable = false;  // a distributed mesh's cycles are pieces, not resumable files
    if (may_distribute_mesh && parallel::mesh_can_be_distributed(probe)) {
      o.control.resumable = false;
      parallel::distribute_mesh(o);
    } else {
      parallel::distribute(o);
    }
  };
}

int finish(const Processes& processes, int code, const std::string& message) {
  if (code == 0 || processes.count <= 1) return code;
  if (parallel::every_process_stops(10.0)) return code;
  if (processes.rank != 0) {
    std::cerr.clear();
    std::cerr << "rgbmesh (process " << processes.rank << " of " << processes.count << "): " << one_line(message) << std::endl;
  }
  parallel::abort_all(code);
}

}  // namespace rgbmesh::cli
