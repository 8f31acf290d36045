// rgbmesh::parallel with MPI and PETSc (mpi.hpp).

#include <mpi.h>
#include <petscksp.h>

#include <algorithm>
#include <cstdlib>
#include <thread>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "rgbmesh/fem/petsc_cg_amg.hpp"
#include "rgbmesh/parallel.hpp"
#include "rgbmesh/parallel/mpi.hpp"
#include "rgbmesh/parallel/partition.hpp"

namespace rgbmesh::parallel {

namespace {

void check(PetscErrorCode code, const char* what) { fem::petsc::check(code, "distributed amg", what); }

bool started = false;

fem::LinearSolution solve(const fem::SparseMatrix& a, const Eigen::VectorXd& b, const Eigen::VectorXd* guess,
                          double tolerance) {
  if (!started) throw std::logic_error("distributed amg: parallel::initialize was not called");
  const int p = processes(), r = rank();
  const auto n = static_cast<std::size_t>(a.rows());
  // Each process's rows: a METIS part of the matrix's graph (the same on every process),
  // numbered part after part so that each process holds a contiguous block.
  const Partition parts = partition_rows(a, p);
  std::vector<int> counts(static_cast<std::size_t>(p), 0), offsets(static_cast<std::size_t>(p), 0);
  for (const std::int32_t q : parts.part_of) ++counts[static_cast<std::size_t>(q)];
  for (int q = 1; q < p; ++q) offsets[static_cast<std::size_t>(q)] = offsets[static_cast<std::size_t>(q - 1)] + counts[static_cast<std::size_t>(q - 1)];
  std::vector<PetscInt> to_new(n), to_old(n);
  {
    std::vector<int> next = offsets;
    for (std::size_t i = 0; i < n; ++i) {
      const int k = next[static_cast<std::size_t>(parts.part_of[i])]++;
      to_new[i] = k;
      to_old[static_cast<std::size_t>(k)] = static_cast<PetscInt>(i);
    }
  }
  const PetscInt first = offsets[static_cast<std::size_t>(r)], m = counts[static_cast<std::size_t>(r)];
  // The matrix is symmetric: Eigen's columns are its rows. This process's rows, in the new
  // numbering (local rows, global columns).
  std::vector<PetscInt> rows(static_cast<std::size_t>(m) + 1, 0), columns;
  std::vector<PetscScalar> values;
  const int* outer = a.outerIndexPtr();
  for (PetscInt k = 0; k < m; ++k) {
    const PetscInt i = to_old[static_cast<std::size_t>(first + k)];
    for (int e = outer[i]; e < outer[i + 1]; ++e) {
      columns.push_back(to_new[static_cast<std::size_t>(a.innerIndexPtr()[e])]);
      values.push_back(a.valuePtr()[e]);
    }
    rows[static_cast<std::size_t>(k) + 1] = static_cast<PetscInt>(columns.size());
  }
  Eigen::VectorXd rhs(static_cast<Eigen::Index>(n)), x(static_cast<Eigen::Index>(n));
  const bool with_guess = guess != nullptr && guess->size() == b.size() && guess->any();
  for (std::size_t i = 0; i < n; ++i) {
    rhs[to_new[i]] = b[static_cast<Eigen::Index>(i)];
    x[to_new[i]] = with_guess ? (*guess)[static_cast<Eigen::Index>(i)] : 0.0;
  }
  fem::petsc::Objects o;
  const auto N = static_cast<PetscInt>(n);
  check(MatCreateMPIAIJWithArrays(PETSC_COMM_WORLD, m, m, N, N, rows.data(), columns.data(), values.data(), &o.a),
        "creating the matrix");
  check(VecCreateMPIWithArray(PETSC_COMM_WORLD, 1, m, N, rhs.data() + first, &o.b), "creating the right-hand side");
  check(VecCreateMPIWithArray(PETSC_COMM_WORLD, 1, m, N, x.data() + first, &o.x), "creating the solution");
  fem::LinearSolution out;
  out.iterations = fem::petsc::solve_cg_amg(PETSC_COMM_WORLD, o, tolerance, with_guess, "distributed amg", "");
  // Every process gets the whole solution: the blocks, gathered in rank order, then numbered
  // as the caller's unknowns.
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, x.data(), counts.data(), offsets.data(), MPI_DOUBLE,
                 PETSC_COMM_WORLD);
  out.x.resize(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) out.x[static_cast<Eigen::Index>(i)] = x[to_new[i]];
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
  // The processes on this machine share its cores: each takes its share for its loops.
  MPI_Comm local = MPI_COMM_NULL;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &local);
  int here = 1;
  MPI_Comm_size(local, &here);
  MPI_Comm_free(&local);
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  rgbmesh::detail::thread_cap = std::max(1u, cores / static_cast<unsigned>(std::max(1, here)));
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

void sum(double* values, std::size_t count) {
  // In slices that an int counts.
  constexpr std::size_t kSlice = std::size_t{1} << 30;
  for (std::size_t first = 0; first < count; first += kSlice) {
    const auto n = static_cast<int>(std::min(kSlice, count - first));
    MPI_Allreduce(MPI_IN_PLACE, values + first, n, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
  }
}

void gather(double* values, std::size_t width, const std::vector<std::int32_t>& part) {
  const int p = processes(), r = rank();
  std::vector<int> counts(static_cast<std::size_t>(p), 0), offsets(static_cast<std::size_t>(p), 0);
  for (const std::int32_t q : part) counts[static_cast<std::size_t>(q)] += static_cast<int>(width);
  for (int q = 1; q < p; ++q) offsets[static_cast<std::size_t>(q)] = offsets[static_cast<std::size_t>(q - 1)] + counts[static_cast<std::size_t>(q - 1)];
  // Every process's elements in element order, its block after the lower ranks' blocks.
  std::vector<double> all(part.size() * width);
  std::vector<int> next = offsets;
  for (std::size_t e = 0; e < part.size(); ++e) {
    if (part[e] != r) continue;
    std::copy(values + e * width, values + (e + 1) * width, all.begin() + next[static_cast<std::size_t>(r)]);
    next[static_cast<std::size_t>(r)] += static_cast<int>(width);
  }
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, all.data(), counts.data(), offsets.data(), MPI_DOUBLE,
                 PETSC_COMM_WORLD);
  next = offsets;
  for (std::size_t e = 0; e < part.size(); ++e) {
    const auto q = static_cast<std::size_t>(part[e]);
    std::copy(all.begin() + next[q], all.begin() + next[q] + static_cast<std::ptrdiff_t>(width), values + e * width);
    next[q] += static_cast<int>(width);
  }
}

std::array<std::uint64_t, 2> bytes_sent_since_last() {
  static std::uint64_t before = 0;
  const std::uint64_t now = bytes_sent();
  const unsigned long long mine = now - before;
  unsigned long long total = 0, largest = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, PETSC_COMM_WORLD);
  MPI_Allreduce(&mine, &largest, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, PETSC_COMM_WORLD);
  before = bytes_sent();  // these two reductions belong to the next interval
  return {total, largest};
}

}  // namespace rgbmesh::parallel
