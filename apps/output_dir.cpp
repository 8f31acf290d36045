#include "output_dir.hpp"

#include <cctype>
#include <iostream>
#include <stdexcept>

#include "rgbmesh/errors.hpp"
#include <system_error>
#include <vector>

namespace rgbmesh::cli {

namespace fs = std::filesystem;

namespace {

// "prefix" + at least one digit + ".vtp".
bool is_numbered(const std::string& name, const std::string& prefix) {
  const std::string suffix = ".vtp";
  if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return false;
  for (std::size_t i = prefix.size(); i < name.size() - suffix.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(name[i]))) return false;
  }
  return true;
}

}  // namespace

bool is_run_output(const std::string& name) {
  static const char* const fixed[] = {"solution.pvd",  "fitted_base.obj", "limit_surface.vtp", "initial_limit_surface.vtp",
                                      "targets.vtp",   "base.obj",        "report.json"};
  for (const char* f : fixed) {
    if (name == f) return true;
  }
  return is_numbered(name, "cycle_") || is_numbered(name, "step_");
}

void prepare_output_directory(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw OutputError(dir.string() + ": cannot write the outputs there: it exists and is not a folder");
  fs::create_directories(dir, ec);
  if (ec) throw OutputError(dir.string() + ": cannot create the output folder: " + ec.message());
  std::vector<fs::path> old;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (entry.is_regular_file(ec) && is_run_output(entry.path().filename().string())) old.push_back(entry.path());
  }
  if (ec) throw OutputError(dir.string() + ": cannot list the output folder: " + ec.message());
  for (const auto& p : old) {
    if (!fs::remove(p, ec) || ec)
      throw OutputError(p.string() + ": cannot remove this output of a previous run: " + ec.message());
  }
  if (!old.empty())
    std::cerr << "rgbmesh: note: removed " << old.size() << " file" << (old.size() == 1 ? "" : "s")
              << " of a previous run from " << dir.string() << "\n";
}

}  // namespace rgbmesh::cli
