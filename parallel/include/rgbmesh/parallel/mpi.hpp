#pragma once
/// \file
/// Running on several MPI processes: starting MPI and PETSc, and the linear solver of an MPI
/// run. Built with MPI and PETSc (Debian: libopenmpi-dev, libpetsc-real-dev); without them,
/// every call says one process.
///
/// Two ways to run the adaptive loop on all processes: with the mesh itself distributed
/// (distributed_mesh.hpp: each process its part and two ghost layers) or with the whole mesh
/// on every process and the finite-element work divided (adaptive.hpp: each process assembles
/// and estimates its own triangles through shared_amg, sum and gather). Either way the bytes
/// each process hands to MPI are counted (bytes_sent).

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rgbmesh/fem/solver.hpp"

namespace rgbmesh::parallel {

/// Whether this build can run on several processes.
bool mpi_available();
/// Whether the process was started by an MPI launcher (mpirun, mpiexec: their environment).
bool launched_by_mpi();
/// Starts MPI and PETSc (once), and finishes both at exit. With MPI unavailable: nothing.
void initialize(int* argc, char*** argv);
/// This process's rank and the number of processes (0 and 1 before initialize or without MPI).
int rank();
int processes();

/// At a failure: whether every process comes to this call within `seconds` (all failed alike,
/// for instance on the same bad input, and can finish normally). If not, the others may wait
/// forever in a collective operation for this one: call abort_all. Without MPI: true.
bool every_process_stops(double seconds);
/// Ends every process of the run with this exit code (MPI_Abort). Without MPI: std::exit.
[[noreturn]] void abort_all(int code);

/// The linear solver of an MPI run (fem::SolveOptions::linear_solver): every process passes
/// the same system; each owns a contiguous block of rows of the distributed matrix; CG with
/// BoomerAMG (fem::amg_options) solves on all processes, and every process gets the whole
/// solution. Throws std::runtime_error when it does not converge.
fem::LinearSolver distributed_amg();

/// The linear solver of a system assembled in parts (fem::SolveOptions::shared_solver): each
/// process passes its own triangles' contributions; they go to the processes owning their rows
/// (row_part), which add them up in rank order; CG with BoomerAMG solves on all processes, and
/// every process gets the whole solution and the relative residual of the summed system.
fem::SharedLinearSolver shared_amg();

/// Adds values across all processes, in place; every process passes the same count (the sum
/// of adapt::AdaptOptions::sum_over_parts). Without MPI: nothing.
void sum(double* values, std::size_t count);
/// Per-element values, `width` numbers per element, each element computed by the process
/// part[e] (the same part on every process): every process sends its own elements' values and
/// receives the others' into `values` (adapt::AdaptOptions::gather_over_parts).
void gather(double* values, std::size_t width, const std::vector<std::int32_t>& part);

/// The bytes this process has handed to MPI so far: its point-to-point messages to other
/// processes and its contributions to collectives, PETSc's and hypre's included (counted
/// through MPI's profiling interface, traffic.cpp). 0 without MPI.
std::uint64_t bytes_sent();
/// Called by every process at the same point: the bytes sent since the previous call (or the
/// start), added over the processes, and the most by one process.
std::array<std::uint64_t, 2> bytes_sent_since_last();

}  // namespace rgbmesh::parallel
