// SolverKind::amg through the PETSc solver module (amg.hpp, rgbmesh/fem/petsc_module.hpp): the
// module is loaded with dlopen on the first solve that needs it, so that runs without one (a
// refinement, a direct solve) never map PETSc and the hundred libraries it brings.
//
// Where the module is looked for, in order: $RGBMESH_PETSC_MODULE alone when set; beside the
// object this code is linked into (the Python extension's directory), then ../lib/rgbmesh and
// ../<libdir>/rgbmesh from it (a program in bin/ of the build or of the installation); then by
// its file name alone (the program's run path, which the installed package config gives the
// programs linking rgbmesh::fem, and LD_LIBRARY_PATH); then the build tree's and the
// installation's paths compiled in. A module of another build (its ABI number differs) is
// passed over.

#include <dlfcn.h>

#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "amg.hpp"
#include "rgbmesh/fem/petsc_module.hpp"
#include "rgbmesh/soup.hpp"

namespace rgbmesh::fem {
namespace petsc {
namespace {

constexpr const char* kFileName = "librgbmesh_petsc.so";

std::string directory_of(const std::string& path) {
  const auto slash = path.rfind('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

std::vector<std::string> candidates() {
  if (const char* chosen = std::getenv("RGBMESH_PETSC_MODULE"); chosen != nullptr && *chosen != '\0') return {chosen};
  std::vector<std::string> paths;
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&candidates), &info) != 0 && info.dli_fname != nullptr) {
    const std::string here = directory_of(info.dli_fname);
    paths.push_back(here + "/" + kFileName);
    paths.push_back(here + "/../lib/rgbmesh/" + kFileName);
    paths.push_back(here + "/../" RGBMESH_INSTALL_LIBDIR "/rgbmesh/" + kFileName);
  }
  paths.emplace_back(kFileName);
  paths.emplace_back(RGBMESH_PETSC_MODULE_BUILD_PATH);
  paths.emplace_back(RGBMESH_PETSC_MODULE_INSTALL_PATH);
  return paths;
}

void (*after_load)() = nullptr;

struct Loaded {
  const ModuleApi* api = nullptr;
  std::string failure;  // why not, when api is null
};

Loaded load() {
  Loaded out;
  std::string tried;
  for (const std::string& path : candidates()) {
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* why = dlerror();
      // A missing file is the normal case for all but one candidate; report the others' reasons.
      if (why != nullptr && std::string(why).find("No such file") == std::string::npos) tried += std::string("; ") + why;
      continue;
    }
    using Entry = const ModuleApi* (*)();
    auto entry = reinterpret_cast<Entry>(dlsym(handle, kModuleEntry));
    const ModuleApi* api = entry != nullptr ? entry() : nullptr;
    if (api == nullptr || api->abi != kModuleAbi) {
      tried += "; " + path + " is of another rgbmesh build";
      dlclose(handle);
      continue;
    }
    out.api = api;  // never unloaded: PETSc is finalized at exit
    if (after_load != nullptr) after_load();
    return out;
  }
  std::string where;
  for (const std::string& path : candidates()) where += (where.empty() ? "" : ", ") + path;
  out.failure = "the AMG solver's module " + std::string(kFileName) + " could not be loaded (looked for " + where +
                ")" + tried + "; use another solver (--solver cg or cholmod) or set RGBMESH_PETSC_MODULE to its path";
  return out;
}

const Loaded& loaded() {
  static const Loaded once = load();
  return once;
}

}  // namespace

void set_after_load(void (*hook)()) { after_load = hook; }

bool module_available() { return loaded().api != nullptr; }

const ModuleApi& module() {
  const Loaded& l = loaded();
  if (l.api == nullptr) throw InputError(l.failure);
  static std::once_flag initialized;
  std::call_once(initialized, [&] {
    const auto& options = amg_options();
    l.api->initialize(options.data(), options.size());
    std::atexit([] { loaded().api->finalize(); });
  });
  return *l.api;
}

}  // namespace petsc

namespace detail {

bool amg_available() { return petsc::module_available(); }

AmgSolution solve_amg(const SparseMatrix& a, const Eigen::VectorXd& b, const Eigen::VectorXd* guess,
                      double tolerance) {
  const petsc::ModuleApi& module = petsc::module();
  if (!a.isCompressed()) throw std::logic_error("amg: the matrix must be compressed");
  AmgSolution out;
  out.x = (guess != nullptr && guess->size() == b.size()) ? *guess : Eigen::VectorXd::Zero(b.size());
  // The matrix is symmetric, so Eigen's column-major arrays are also its rows.
  const auto n = static_cast<int>(a.rows());
  petsc::System s = petsc::compressed_rows(n, n, a.outerIndexPtr(), a.innerIndexPtr(), a.valuePtr(), b.data(),
                                           out.x.data(), tolerance);
  s.nonzero_guess = out.x.any();
  s.solver = "amg";
  s.hint = "; the system may be singular";
  out.iterations = module.solve(s).iterations;
  return out;
}

}  // namespace detail
}  // namespace rgbmesh::fem
