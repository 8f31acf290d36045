#pragma once
/// \file
/// The PETSc solver module: conjugate gradients preconditioned by hypre's BoomerAMG through
/// PETSc, built as a shared module of its own (librgbmesh_petsc.so) and loaded only when a solve
/// asks for it: fem's amg solver on one process, rgbmesh::parallel's distributed solvers.
///
/// Why a module: PETSc and what it loads (hypre, MUMPS, SuperLU_DIST, ScaLAPACK, Trilinos, HDF5,
/// Fortran runtimes: about a hundred libraries) take 31 MB of resident memory as soon as they are
/// mapped, whether or not a solve ever runs; that is 20 bytes per vertex of a 1.5-million-vertex
/// refinement, which needs no solver at all (issue 44.3). Nothing in this header needs PETSc.

#include <array>
#include <cstddef>

namespace rgbmesh::fem::petsc {

/// One system for the module: rows [first, first + local_rows) of a global_rows x global_rows
/// symmetric positive definite matrix, in compressed rows with global column numbers. On one
/// process (distributed false) these are all the rows and PETSc works on PETSC_COMM_SELF;
/// otherwise every process of MPI_COMM_WORLD calls with its own block, in rank order.
struct System {
  bool distributed = false;
  int local_rows = 0, global_rows = 0;
  const int* row_starts = nullptr;  // local_rows + 1 offsets into columns and values
  const int* columns = nullptr;
  const double* values = nullptr;
  const double* rhs = nullptr;  // local_rows values
  double* x = nullptr;          // local_rows values: the guess in (when nonzero_guess), the solution out
  double tolerance = 1e-10;     // relative residual of the system itself
  bool nonzero_guess = false;
  bool measure_residual = false;  // compute ‖b - A x‖ / ‖b‖ anew after the solve
  const char* solver = "amg";     // the name that starts error messages
  const char* hint = "";          // appended to the no-convergence message
  /// Distributed only: called once PETSc has copied the matrix's arrays (row_starts, columns,
  /// values are not read again), so that the caller frees them before the AMG setup, the
  /// solve's peak of memory. (On one process PETSc borrows them until the solve returns.)
  void (*matrix_copied)(void* context) = nullptr;
  void* context = nullptr;
};

/// A System of these compressed rows, right-hand side and solution (the rest as defaults).
inline System compressed_rows(int local_rows, int global_rows, const int* row_starts, const int* columns,
                              const double* values, const double* rhs, double* x, double tolerance) {
  System s;
  s.local_rows = local_rows;
  s.global_rows = global_rows;
  s.row_starts = row_starts;
  s.columns = columns;
  s.values = values;
  s.rhs = rhs;
  s.x = x;
  s.tolerance = tolerance;
  return s;
}

struct Result {
  int iterations = 0;
  double relative_residual = -1.0;  // when measure_residual
};

/// The module's functions. Errors are std::runtime_error "SOLVER: WHAT failed (PETSc: reason)".
struct ModuleApi {
  int abi;  // kModuleAbi of the module's build
  /// Initializes PETSc once (MPI as a singleton process where the program has not initialized
  /// it), without PETSc's signal handlers (the tool's remove temporary files), errors returned
  /// as codes; then sets `count` (name, value) options.
  void (*initialize)(const std::array<const char*, 2>* options, std::size_t count);
  /// Finalizes PETSc if it was initialized and is not yet finalized (MPI is the caller's).
  void (*finalize)();
  Result (*solve)(const System& system);
};

/// Changes whenever ModuleApi or System changes, so that a module of another build is refused.
inline constexpr int kModuleAbi = 1;

/// The name the module exports its ModuleApi under (extern "C").
inline constexpr const char* kModuleEntry = "rgbmesh_petsc_module_api";

/// A function to run right after the module is mapped, before PETSc is initialized: a library it
/// brings (SuperLU_DIST) changes malloc's settings as it loads (no mappings for large blocks, no
/// trimming of the heap), so a program with settings of its own (the tool's) restores them here.
/// Set it before the first solve.
void set_after_load(void (*hook)());

/// Whether the module can be loaded (it loads it: once, on the first call).
bool module_available();

/// The loaded and initialized module (PETSc initialized, with fem::amg_options set, finalized at
/// exit). Throws InputError naming the paths tried and the loader's message where it cannot be
/// loaded, or where rgbmesh was built without PETSc.
const ModuleApi& module();

}  // namespace rgbmesh::fem::petsc
