#pragma once
/// \file
/// Conjugate gradients with hypre's BoomerAMG through PETSc: the one solve that fem's amg solver
/// (one process) and rgbmesh::parallel's distributed solver share. Only for sources built with
/// PETSc (it includes PETSc's headers); nothing else includes it.

#include <petscksp.h>

#include <stdexcept>
#include <string>
#include <type_traits>

namespace rgbmesh::fem::petsc {

static_assert(std::is_same_v<PetscInt, int> && std::is_same_v<PetscScalar, double>,
              "Eigen's index and value arrays are handed to PETSc as they are");

/// Throws std::runtime_error "SOLVER: WHAT failed (PETSc: reason)" for a PETSc error code.
inline void check(PetscErrorCode code, const char* solver, const char* what) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw std::runtime_error(std::string(solver) + ": " + what + " failed (PETSc: " + (text ? text : "unknown error") + ")");
}

/// A solve's PETSc objects, destroyed on every path.
struct Objects {
  Mat a = nullptr;
  Vec x = nullptr, b = nullptr;
  KSP ksp = nullptr;
  ~Objects() {
    KSPDestroy(&ksp);
    VecDestroy(&x);
    VecDestroy(&b);
    MatDestroy(&a);
  }
};

/// Solves o.a o.x = o.b on `comm` by CG preconditioned by BoomerAMG (options under the prefix
/// rgbmesh_amg_, fem::amg_options) to the relative residual `tolerance` of the system itself,
/// from o.x when `nonzero_guess`; returns the iterations. No convergence: std::runtime_error
/// "SOLVER: no convergence ... (PETSc's reason R)" followed by `hint`.
inline int solve_cg_amg(MPI_Comm comm, Objects& o, double tolerance, bool nonzero_guess, const char* solver,
                        const char* hint) {
  check(KSPCreate(comm, &o.ksp), solver, "creating the solver");
  check(KSPSetOperators(o.ksp, o.a, o.a), solver, "setting the operator");
  check(KSPSetType(o.ksp, KSPCG), solver, "choosing CG");
  PC pc = nullptr;
  check(KSPGetPC(o.ksp, &pc), solver, "getting the preconditioner");
  check(PCSetType(pc, PCHYPRE), solver, "choosing hypre");
  check(PCHYPRESetType(pc, "boomeramg"), solver, "choosing BoomerAMG");
  // The relative residual of the system itself, as the other solvers measure it.
  check(KSPSetNormType(o.ksp, KSP_NORM_UNPRECONDITIONED), solver, "setting the norm");
  check(KSPSetTolerances(o.ksp, tolerance, 0.0, PETSC_DEFAULT, 10000), solver, "setting the tolerances");
  check(KSPSetInitialGuessNonzero(o.ksp, nonzero_guess ? PETSC_TRUE : PETSC_FALSE), solver, "setting the initial guess");
  check(KSPSetOptionsPrefix(o.ksp, "rgbmesh_amg_"), solver, "setting the options prefix");
  check(KSPSetFromOptions(o.ksp), solver, "reading the options");
  check(KSPSolve(o.ksp, o.b, o.x), solver, "solving");
  KSPConvergedReason reason;
  check(KSPGetConvergedReason(o.ksp, &reason), solver, "asking why it stopped");
  PetscInt iterations = 0;
  check(KSPGetIterationNumber(o.ksp, &iterations), solver, "counting iterations");
  if (reason < 0)
    throw std::runtime_error(std::string(solver) + ": no convergence to " + std::to_string(tolerance) + " after " +
                             std::to_string(iterations) + " iterations (PETSc's reason " +
                             std::to_string(static_cast<int>(reason)) + ")" + hint);
  return static_cast<int>(iterations);
}

}  // namespace rgbmesh::fem::petsc
