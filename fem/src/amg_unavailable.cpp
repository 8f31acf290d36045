// SolverKind::amg in a build without PETSc (amg.hpp, rgbmesh/fem/petsc_module.hpp).

#include "amg.hpp"
#include "rgbmesh/fem/petsc_module.hpp"
#include "rgbmesh/soup.hpp"

namespace rgbmesh::fem {
namespace {
constexpr const char* kWithoutPetsc =
    "solver 'amg' is not available: rgbmesh was built without PETSc (Debian: libpetsc-real-dev)";
}

namespace petsc {
void set_after_load(void (*)()) {}
bool module_available() { return false; }
const ModuleApi& module() { throw InputError(kWithoutPetsc); }
}  // namespace petsc

namespace detail {
bool amg_available() { return false; }
AmgSolution solve_amg(const SparseMatrix&, const Eigen::VectorXd&, const Eigen::VectorXd*, double) {
  throw InputError(kWithoutPetsc);
}
}  // namespace detail
}  // namespace rgbmesh::fem
