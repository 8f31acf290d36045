// rgbmesh::parallel without MPI and PETSc (mpi.hpp): one process.

#include <cstdlib>
#include <stdexcept>

#include "collectives.hpp"
#include "rgbmesh/parallel/local_view.hpp"
#include "rgbmesh/parallel/mpi.hpp"

namespace rgbmesh::parallel {

bool mpi_available() { return false; }
bool launched_by_mpi() { return false; }
void initialize(int*, char***) {}
int rank() { return 0; }
int processes() { return 1; }
bool every_process_stops(double) { return true; }
void abort_all(int code) { std::exit(code); }

fem::LinearSolver distributed_amg() {
  return [](const fem::SparseMatrix&, const Eigen::VectorXd&, const Eigen::VectorXd*, double) -> fem::LinearSolution {
    throw std::runtime_error("distributed amg: rgbmesh was built without MPI and PETSc");
  };
}

fem::SharedLinearSolver shared_amg() {
  return [](const fem::SparseMatrix&, const Eigen::VectorXd&, const std::vector<std::int32_t>&,
            const std::vector<Eigen::Index>&, const Eigen::VectorXd*, double) -> fem::LinearSolution {
    throw std::runtime_error("shared amg: rgbmesh was built without MPI and PETSc");
  };
}

void sum(double*, std::size_t) {}
void gather(double*, std::size_t, const std::vector<std::int32_t>&) {}
std::uint64_t bytes_sent() { return 0; }
std::array<std::uint64_t, 2> bytes_sent_since_last() { return {0, 0}; }

Reconciled reconcile_splits(RgbMesh&, const std::unordered_set<std::int32_t>&, const std::unordered_set<VertexKey>&) {
  return {};
}

namespace detail {

void sum(std::uint64_t*, std::size_t) {}
std::vector<std::uint64_t> all_gather(const std::vector<std::uint64_t>& mine) { return mine; }
std::vector<std::vector<std::uint64_t>> all_to_all(const std::vector<std::vector<std::uint64_t>>& to) { return to; }
std::vector<std::vector<double>> all_to_all(const std::vector<std::vector<double>>& to) { return to; }
std::uint64_t exchanges() { return 0; }
OwnedRows solve_rows(std::vector<RowEntries>&, std::int64_t, std::int64_t, std::int64_t, const Eigen::VectorXd*, double) {
  throw std::runtime_error("distributed mesh: rgbmesh was built without MPI and PETSc");
}

}  // namespace detail

}  // namespace rgbmesh::parallel
