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
#include "rgbmesh/fem/petsc_cg_amg.hpp"

namespace rgbmesh::fem::detail {
namespace {

void check(PetscErrorCode code, const char* what) { petsc::check(code, "amg", what); }

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

}  // namespace

bool amg_available() { return true; }

AmgSolution solve_amg(const SparseMatrix& a, const Eigen::VectorXd& b, const Eigen::VectorXd* guess,
                      double tolerance) {
  initialize_petsc();
  const auto n = static_cast<PetscInt>(a.rows());
  if (!a.isCompressed()) throw std::logic_error("amg: the matrix must be compressed");
  AmgSolution out;
  out.x = (guess != nullptr && guess->size() == b.size()) ? *guess : Eigen::VectorXd::Zero(b.size());
  petsc::Objects o;
  // The matrix is symmetric, so Eigen's column-major arrays are also its rows. PETSc only reads
  // them (the arrays are borrowed, not copied; the Mat is destroyed before they are).
  check(MatCreateSeqAIJWithArrays(PETSC_COMM_SELF, n, n, const_cast<int*>(a.outerIndexPtr()),
                                  const_cast<int*>(a.innerIndexPtr()), const_cast<double*>(a.valuePtr()), &o.a),
        "creating the matrix");
  check(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n, b.data(), &o.b), "creating the right-hand side");
  check(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n, out.x.data(), &o.x), "creating the solution");
  out.iterations = petsc::solve_cg_amg(PETSC_COMM_SELF, o, tolerance, out.x.any(), "amg", "; the system may be singular");
  return out;
}

}  // namespace rgbmesh::fem::detail
