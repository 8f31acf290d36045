// rgbmesh::parallel without MPI and PETSc (mpi.hpp): one process.

#include <cstdlib>
#include <stdexcept>

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
  return [](const fem::SparseMatrix&, const Eigen::VectorXd&, const std::vector<std::int32_t>&, const Eigen::VectorXd*,
            double) -> fem::LinearSolution {
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

}  // namespace rgbmesh::parallel
