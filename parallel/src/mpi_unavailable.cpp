// rgbmesh::parallel without MPI and PETSc (mpi.hpp): one process.

#include <stdexcept>

#include "rgbmesh/parallel/mpi.hpp"

namespace rgbmesh::parallel {

bool mpi_available() { return false; }
bool launched_by_mpi() { return false; }
void initialize(int*, char***) {}
int rank() { return 0; }
int processes() { return 1; }

fem::LinearSolver distributed_amg() {
  return [](const fem::SparseMatrix&, const Eigen::VectorXd&, const Eigen::VectorXd*, double) -> fem::LinearSolution {
    throw std::runtime_error("distributed amg: rgbmesh was built without MPI and PETSc");
  };
}

}  // namespace rgbmesh::parallel
