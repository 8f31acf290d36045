#pragma once
// The tool under an MPI launcher (mpirun -np P rgbmesh adapt ...): the processes of the run.
// processes_mpi.cpp (with rgbmesh::parallel's MPI) or processes_single.cpp (without) is built.

#include <string>

#include "adapt_command.hpp"

namespace rgbmesh::cli {

struct Processes {
  int rank = 0, count = 1;
};

// Starts MPI when an MPI launcher started the process; one process otherwise. The ranks
// other than 0 print nothing (their standard output and error are silenced): rank 0 speaks
// for the run.
Processes start_processes(int* argc, char*** argv);

// An adapt run on several processes: every process adapts the same mesh alike and the linear
// systems are solved on all of them (rgbmesh::parallel::distributed_amg); rank 0 writes.
void distribute(AdaptArgs& args, const Processes& processes);

// The exit code of the tool, after a failure on several processes: when all failed alike
// (within a few seconds of each other) they end normally, rank 0 having said why; a process
// that failed alone prints its error (which, on a rank other than 0, was silenced) and ends
// every process, which would otherwise wait for it forever.
int finish(const Processes& processes, int code, const std::string& message);

}  // namespace rgbmesh::cli
