// SolverKind::amg with PETSc (amg.hpp): CG (KSPCG) preconditioned by hypre's BoomerAMG
// (PCHYPRE), on one process.
//
// PETSc is initialized on first use (which initializes MPI as a singleton process where the
// host program has not), without PETSc's signal handlers, which would replace the tool's
// (SIGINT and SIGTERM remove temporary files); it is finalized at exit. Errors come back as
// codes (PetscReturnErrorHandler), not as PETSc's printed tracebacks.

#include <petscksp.h>

#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "amg.hpp"

namespace rgbmesh::fem::detail {
namespace {

static_assert(std::is_same_v<PetscInt, int> && std::is_same_v<PetscScalar, double>,
              "Eigen's index and value arrays are handed to PETSc as they are");

void check(PetscErrorCode code, const char* what) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw std::runtime_error(std::string("amg: ") + what + " failed (PETSc: " + (text ? text : "unknown error") + ")");
}

void initialize_petsc() {
  static std::once_flag once;
  std::call_once(once, [] {
    static int argc = 2;
    static char program[] = "rgbmesh", no_signals[] = "-no_signal_handler";
    static char* arguments[] = {program, no_signals, nullptr};
    static char** argv = arguments;
    check(PetscInitialize(&argc, &argv, nullptr, nullptr), "initializing PETSc");
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
    for (const auto& option : amg_options()) check(PetscOptionsSetValue(nullptr, option[0], option[1]), "setting options");
    std::atexit([] { PetscFinalize(); });
  });
}

// PETSc objects destroyed on every path.
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

}  // namespace

bool amg_available() { return true; }

AmgSolution solve_amg(const SparseMatrix& a, const Eigen::VectorXd& b, const Eigen::VectorXd* guess,
                      double tolerance) {
  initialize_petsc();
  const auto n = static_cast<PetscInt>(a.rows());
  if (!a.isCompressed()) throw std::logic_error("amg: the matrix must be compressed");
  AmgSolution out;
  out.x = (guess != nullptr && guess->size() == b.size()) ? *guess : Eigen::VectorXd::Zero(b.size());
  Objects o;
  // The matrix is symmetric, so Eigen's column-major arrays are also its rows. PETSc only reads
  // them (the arrays are borrowed, not copied; the Mat is destroyed before they are).
  check(MatCreateSeqAIJWithArrays(PETSC_COMM_SELF, n, n, const_cast<int*>(a.outerIndexPtr()),
                                  const_cast<int*>(a.innerIndexPtr()), const_cast<double*>(a.valuePtr()), &o.a),
        "creating the matrix");
  check(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n, b.data(), &o.b), "creating the right-hand side");
  check(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n, out.x.data(), &o.x), "creating the solution");
  check(KSPCreate(PETSC_COMM_SELF, &o.ksp), "creating the solver");
  check(KSPSetOperators(o.ksp, o.a, o.a), "setting the operator");
  check(KSPSetType(o.ksp, KSPCG), "choosing CG");
  PC pc = nullptr;
  check(KSPGetPC(o.ksp, &pc), "getting the preconditioner");
  check(PCSetType(pc, PCHYPRE), "choosing hypre");
  check(PCHYPRESetType(pc, "boomeramg"), "choosing BoomerAMG");
  // The relative residual of the system itself, as the other solvers measure it.
  check(KSPSetNormType(o.ksp, KSP_NORM_UNPRECONDITIONED), "setting the norm");
  check(KSPSetTolerances(o.ksp, tolerance, 0.0, PETSC_DEFAULT, 10000), "setting the tolerances");
  check(KSPSetInitialGuessNonzero(o.ksp, out.x.any() ? PETSC_TRUE : PETSC_FALSE), "setting the initial guess");
  check(KSPSetOptionsPrefix(o.ksp, "rgbmesh_amg_"), "setting the options prefix");
  check(KSPSetFromOptions(o.ksp), "reading the options");
  check(KSPSolve(o.ksp, o.b, o.x), "solving");
  KSPConvergedReason reason;
  check(KSPGetConvergedReason(o.ksp, &reason), "asking why it stopped");
  PetscInt iterations = 0;
  check(KSPGetIterationNumber(o.ksp, &iterations), "counting iterations");
  out.iterations = static_cast<int>(iterations);
  if (reason < 0)
    throw std::runtime_error("amg: no convergence to " + std::to_string(tolerance) + " after " +
                             std::to_string(iterations) + " iterations (PETSc's reason " +
                             std::to_string(static_cast<int>(reason)) + "); the system may be singular");
  return out;
}

}  // namespace rgbmesh::fem::detail
