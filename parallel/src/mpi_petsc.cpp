// rgbmesh::parallel with MPI and PETSc (mpi.hpp).

#include <mpi.h>
#include <petscksp.h>

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "rgbmesh/parallel/mpi.hpp"

namespace rgbmesh::parallel {

namespace {

static_assert(std::is_same_v<PetscInt, int> && std::is_same_v<PetscScalar, double>,
              "Eigen's index and value arrays are handed to PETSc as they are");

void check(PetscErrorCode code, const char* what) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw std::runtime_error(std::string("distributed amg: ") + what + " failed (PETSc: " + (text ? text : "unknown error") +
                           ")");
}

bool started = false;

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

fem::LinearSolution solve(const fem::SparseMatrix& a, const Eigen::VectorXd& b, const Eigen::VectorXd* guess,
                          double tolerance) {
  if (!started) throw std::logic_error("distributed amg: parallel::initialize was not called");
  const int p = processes(), r = rank();
  const auto n = static_cast<long long>(a.rows());
  // This process's rows: a contiguous block of the unknowns.
  const auto first = static_cast<PetscInt>(n * r / p), last = static_cast<PetscInt>(n * (r + 1) / p);
  const PetscInt m = last - first;
  // The matrix is symmetric: Eigen's columns are its rows. Local rows, global columns.
  std::vector<PetscInt> rows(static_cast<std::size_t>(m) + 1, 0), columns;
  std::vector<PetscScalar> values;
  const int* outer = a.outerIndexPtr();
  columns.reserve(static_cast<std::size_t>(outer[last] - outer[first]));
  values.reserve(columns.capacity());
  for (PetscInt i = first; i < last; ++i) {
    for (int k = outer[i]; k < outer[i + 1]; ++k) {
      columns.push_back(a.innerIndexPtr()[k]);
      values.push_back(a.valuePtr()[k]);
    }
    rows[static_cast<std::size_t>(i - first) + 1] = static_cast<PetscInt>(columns.size());
  }
  fem::LinearSolution out;
  out.x = (guess != nullptr && guess->size() == b.size()) ? *guess : Eigen::VectorXd::Zero(b.size());
  const bool nonzero_guess = out.x.any();
  Objects o;
  const auto N = static_cast<PetscInt>(n);
  check(MatCreateMPIAIJWithArrays(PETSC_COMM_WORLD, m, m, N, N, rows.data(), columns.data(), values.data(), &o.a),
        "creating the matrix");
  check(VecCreateMPIWithArray(PETSC_COMM_WORLD, 1, m, N, b.data() + first, &o.b), "creating the right-hand side");
  check(VecCreateMPIWithArray(PETSC_COMM_WORLD, 1, m, N, out.x.data() + first, &o.x), "creating the solution");
  check(KSPCreate(PETSC_COMM_WORLD, &o.ksp), "creating the solver");
  check(KSPSetOperators(o.ksp, o.a, o.a), "setting the operator");
  check(KSPSetType(o.ksp, KSPCG), "choosing CG");
  PC pc = nullptr;
  check(KSPGetPC(o.ksp, &pc), "getting the preconditioner");
  check(PCSetType(pc, PCHYPRE), "choosing hypre");
  check(PCHYPRESetType(pc, "boomeramg"), "choosing BoomerAMG");
  check(KSPSetNormType(o.ksp, KSP_NORM_UNPRECONDITIONED), "setting the norm");
  check(KSPSetTolerances(o.ksp, tolerance, 0.0, PETSC_DEFAULT, 10000), "setting the tolerances");
  check(KSPSetInitialGuessNonzero(o.ksp, nonzero_guess ? PETSC_TRUE : PETSC_FALSE), "setting the initial guess");
  check(KSPSetOptionsPrefix(o.ksp, "rgbmesh_amg_"), "setting the options prefix");
  check(KSPSetFromOptions(o.ksp), "reading the options");
  check(KSPSolve(o.ksp, o.b, o.x), "solving");
  KSPConvergedReason reason;
  check(KSPGetConvergedReason(o.ksp, &reason), "asking why it stopped");
  PetscInt iterations = 0;
  check(KSPGetIterationNumber(o.ksp, &iterations), "counting iterations");
  out.iterations = static_cast<int>(iterations);
  if (reason < 0)
    throw std::runtime_error("distributed amg: no convergence to " + std::to_string(tolerance) + " after " +
                             std::to_string(iterations) + " iterations (PETSc's reason " +
                             std::to_string(static_cast<int>(reason)) + ")");
  // Every process gets the whole solution: the blocks, gathered in rank order.
  std::vector<int> counts(static_cast<std::size_t>(p)), offsets(static_cast<std::size_t>(p));
  for (int q = 0; q < p; ++q) {
    offsets[static_cast<std::size_t>(q)] = static_cast<int>(n * q / p);
    counts[static_cast<std::size_t>(q)] = static_cast<int>(n * (q + 1) / p) - offsets[static_cast<std::size_t>(q)];
  }
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, out.x.data(), counts.data(), offsets.data(), MPI_DOUBLE,
                 PETSC_COMM_WORLD);
  return out;
}

}  // namespace

bool mpi_available() { return true; }

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

void initialize(int* argc, char*** argv) {
  if (started) return;
  int done = 0;
  MPI_Initialized(&done);
  if (!done) {
    int provided = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  }
  // PETSc's signal handlers would replace the tool's (which remove temporary files).
  check(PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr), "setting options");
  check(PetscInitializeNoArguments(), "initializing PETSc");
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  for (const auto& option : fem::amg_options()) check(PetscOptionsSetValue(nullptr, option[0], option[1]), "setting options");
  started = true;
  std::atexit([] {
    PetscBool finalized = PETSC_FALSE;
    PetscFinalized(&finalized);
    if (!finalized) PetscFinalize();
    int mpi_finalized = 0;
    MPI_Finalized(&mpi_finalized);
    if (!mpi_finalized) MPI_Finalize();
  });
}

int rank() {
  if (!started) return 0;
  int r = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &r);
  return r;
}

int processes() {
  if (!started) return 1;
  int p = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &p);
  return p;
}

fem::LinearSolver distributed_amg() { return solve; }

}  // namespace rgbmesh::parallel
