// SolverKind::amg in a build without PETSc (amg.hpp).

#include "amg.hpp"

#include "rgbmesh/soup.hpp"

namespace rgbmesh::fem::detail {

bool amg_available() { return false; }

AmgSolution solve_amg(const SparseMatrix&, const Eigen::VectorXd&, const Eigen::VectorXd*, double) {
  throw InputError("solver 'amg' is not available: rgbmesh was built without PETSc (Debian: libpetsc-real-dev)");
}

}  // namespace rgbmesh::fem::detail
