// The PETSc solver module (rgbmesh/fem/petsc_module.hpp): CG preconditioned by hypre's BoomerAMG,
// on one process or on MPI_COMM_WORLD. The only source that includes PETSc's headers; built as
// librgbmesh_petsc.so and loaded with dlopen by fem (amg_petsc.cpp) when a solve needs it.

#include <petscksp.h>

#include <stdexcept>
#include <string>
#include <type_traits>

#include "rgbmesh/fem/petsc_module.hpp"

namespace {

using rgbmesh::fem::petsc::ModuleApi;
using rgbmesh::fem::petsc::Result;
using rgbmesh::fem::petsc::System;

static_assert(std::is_same_v<PetscInt, int> && std::is_same_v<PetscScalar, double>,
              "the callers' int and double arrays are handed to PETSc as they are");

void check(PetscErrorCode code, const char* solver, const char* what) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw std::runtime_error(std::string(solver) + ": " + what + " failed (PETSc: " + (text ? text : "unknown error") + ")");
}

// A solve's PETSc objects, destroyed on every path.
struct Objects {
  Mat a = nullptr;
  Vec x = nullptr, b = nullptr, residual = nullptr;
  KSP ksp = nullptr;
  ~Objects() {
    KSPDestroy(&ksp);
    VecDestroy(&residual);
    VecDestroy(&x);
    VecDestroy(&b);
    MatDestroy(&a);
  }
};

void initialize(const std::array<const char*, 2>* options, std::size_t count) {
  PetscBool initialized = PETSC_FALSE;
  check(PetscInitialized(&initialized), "amg", "asking whether PETSc is initialized");
  if (initialized) return;
  // PETSc's signal handlers would replace the tool's (which remove temporary files).
  check(PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr), "amg", "setting options");
  check(PetscInitializeNoArguments(), "amg", "initializing PETSc");
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  for (std::size_t i = 0; i < count; ++i) check(PetscOptionsSetValue(nullptr, options[i][0], options[i][1]), "amg", "setting options");
}

void finalize() {
  PetscBool initialized = PETSC_FALSE, finalized = PETSC_FALSE;
  PetscInitialized(&initialized);
  PetscFinalized(&finalized);
  if (initialized && !finalized) PetscFinalize();
}

Result solve(const System& s) {
  const char* solver = s.solver;
  const MPI_Comm comm = s.distributed ? PETSC_COMM_WORLD : PETSC_COMM_SELF;
  const PetscInt m = s.local_rows, n = s.global_rows;
  Objects o;
  // PETSc only reads the borrowed arrays (the objects are destroyed before the caller's arrays).
  auto* rows = const_cast<PetscInt*>(s.row_starts);
  auto* columns = const_cast<PetscInt*>(s.columns);
  auto* values = const_cast<PetscScalar*>(s.values);
  if (s.distributed) {
    check(MatCreateMPIAIJWithArrays(comm, m, m, n, n, rows, columns, values, &o.a), solver, "creating the matrix");
    if (s.matrix_copied != nullptr) s.matrix_copied(s.context);
    check(VecCreateMPIWithArray(comm, 1, m, n, s.rhs, &o.b), solver, "creating the right-hand side");
    check(VecCreateMPIWithArray(comm, 1, m, n, s.x, &o.x), solver, "creating the solution");
  } else {
    check(MatCreateSeqAIJWithArrays(comm, n, n, rows, columns, values, &o.a), solver, "creating the matrix");
    check(VecCreateSeqWithArray(comm, 1, n, s.rhs, &o.b), solver, "creating the right-hand side");
    check(VecCreateSeqWithArray(comm, 1, n, s.x, &o.x), solver, "creating the solution");
  }
  check(KSPCreate(comm, &o.ksp), solver, "creating the solver");
  check(KSPSetOperators(o.ksp, o.a, o.a), solver, "setting the operator");
  check(KSPSetType(o.ksp, KSPCG), solver, "choosing CG");
  PC pc = nullptr;
  check(KSPGetPC(o.ksp, &pc), solver, "getting the preconditioner");
  check(PCSetType(pc, PCHYPRE), solver, "choosing hypre");
  check(PCHYPRESetType(pc, "boomeramg"), solver, "choosing BoomerAMG");
  // The relative residual of the system itself, as the other solvers measure it.
  check(KSPSetNormType(o.ksp, KSP_NORM_UNPRECONDITIONED), solver, "setting the norm");
  check(KSPSetTolerances(o.ksp, s.tolerance, 0.0, PETSC_DEFAULT, 10000), solver, "setting the tolerances");
  check(KSPSetInitialGuessNonzero(o.ksp, s.nonzero_guess ? PETSC_TRUE : PETSC_FALSE), solver,
        "setting the initial guess");
  check(KSPSetOptionsPrefix(o.ksp, "rgbmesh_amg_"), solver, "setting the options prefix");
  check(KSPSetFromOptions(o.ksp), solver, "reading the options");
  check(KSPSolve(o.ksp, o.b, o.x), solver, "solving");
  KSPConvergedReason reason;
  check(KSPGetConvergedReason(o.ksp, &reason), solver, "asking why it stopped");
  PetscInt iterations = 0;
  check(KSPGetIterationNumber(o.ksp, &iterations), solver, "counting iterations");
  if (reason < 0)
    throw std::runtime_error(std::string(solver) + ": no convergence to " + std::to_string(s.tolerance) + " after " +
                             std::to_string(iterations) + " iterations (PETSc's reason " +
                             std::to_string(static_cast<int>(reason)) + ")" + s.hint);
  Result out;
  out.iterations = static_cast<int>(iterations);
  if (s.measure_residual) {
    PetscReal rn = 0, bn = 0;
    check(VecDuplicate(o.b, &o.residual), solver, "creating the residual");
    check(MatMult(o.a, o.x, o.residual), solver, "measuring the residual");
    check(VecAYPX(o.residual, -1.0, o.b), solver, "measuring the residual");
    check(VecNorm(o.residual, NORM_2, &rn), solver, "measuring the residual");
    check(VecNorm(o.b, NORM_2, &bn), solver, "measuring the residual");
    out.relative_residual = bn > 0 ? rn / bn : rn;
  }
  return out;
}

const ModuleApi api = {rgbmesh::fem::petsc::kModuleAbi, initialize, finalize, solve};

}  // namespace

extern "C" __attribute__((visibility("default"))) const ModuleApi* rgbmesh_petsc_module_api() { return &api; }
