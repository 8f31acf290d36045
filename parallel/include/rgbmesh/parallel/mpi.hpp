#pragma once
/// \file
/// Running on several MPI processes: starting MPI and PETSc, and the linear solver of an MPI
/// run. Built with MPI and PETSc (Debian: libopenmpi-dev, libpetsc-real-dev); without them,
/// every call says one process.
///
/// The first step of issue 13 distributes the linear solve: every process holds the same mesh
/// and adapts it alike (the marks come from the same indicators), assembles the same system,
/// and owns a contiguous block of its rows for CG with BoomerAMG on all processes.

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

/// The linear solver of an MPI run (fem::SolveOptions::linear_solver): every process passes
/// the same system; each owns a contiguous block of rows of the distributed matrix; CG with
/// BoomerAMG (fem::amg_options) solves on all processes, and every process gets the whole
/// solution. Throws std::runtime_error when it does not converge.
fem::LinearSolver distributed_amg();

}  // namespace rgbmesh::parallel
