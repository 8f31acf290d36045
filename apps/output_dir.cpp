#include "output_dir.hpp"

#include <signal.h>

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <iostream>
#include <stdexcept>

#include "one_line.hpp"
#include "rgbmesh/errors.hpp"
#include <system_error>
#include <vector>

namespace rgbmesh::cli {

namespace fs = std::filesystem;

namespace {

// "prefix" + at least one digit + suffix.
bool is_numbered(const std::string& name, const std::string& prefix, const std::string& suffix = ".vtp") {
  if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return false;
  for (std::size_t i = prefix.size(); i < name.size() - suffix.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(name[i]))) return false;
  }
  return true;
}

// A temporary of an atomic write (".NAME.tmp-PID-N.EXT") whose process no longer runs: left by
// a kill that no handler can catch (SIGKILL, a power cut).
bool is_orphaned_temporary(const std::string& name) {
  const auto at = name.find(".tmp-");
  if (name.empty() || name[0] != '.' || at == std::string::npos) return false;
  char* end = nullptr;
  const long pid = std::strtol(name.c_str() + at + 5, &end, 10);
  if (pid <= 0 || end == nullptr || *end != '-') return false;
  return ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

}  // namespace

bool is_run_output(const std::string& name) {
  static const char* const fixed[] = {"solution.pvd",  "fitted_base.obj", "limit_surface.vtp", "initial_limit_surface.vtp",
                                      "targets.vtp",   "base.obj",        "report.json"};
  for (const char* f : fixed) {
    if (name == f) return true;
  }
  for (const char* prefix : {"cycle_", "step_"}) {
    if (is_numbered(name, prefix) || is_numbered(name, prefix, "_p2.vtu") || is_numbered(name, prefix, ".pvtp") ||
        is_numbered(name, prefix, "_p2.pvtu"))
      return true;
    // A process's piece of a cycle: prefix + digits + "_r" + digits + ".vtp", or for P2
    // prefix + digits + "_p2_r" + digits + ".vtu".
    const auto r = name.rfind("_r");
    if (r != std::string::npos && is_numbered(name.substr(0, r) + ".vtp", prefix) && is_numbered(name.substr(r), "_r"))
      return true;
    const auto r2 = name.rfind("_p2_r");
    if (r2 != std::string::npos && is_numbered(name.substr(0, r2) + ".vtp", prefix) &&
        is_numbered(name.substr(r2 + 3), "_r", ".vtu"))
      return true;
  }
  return false;
}

void create_output_directory(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw OutputError(dir.string() + ": cannot write the outputs there: it exists and is not a folder");
  fs::create_directories(dir, ec);
  if (ec) throw OutputError(dir.string() + ": cannot create the output folder: " + ec.message());
}

void prepare_output_directory(const fs::path& dir) {
  create_output_directory(dir);
  std::error_code ec;
  std::vector<fs::path> old;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file(ec) && (is_run_output(name) || is_orphaned_temporary(name))) old.push_back(entry.path());
  }
  if (ec) throw OutputError(dir.string() + ": cannot list the output folder: " + ec.message());
  for (const auto& p : old) {
    if (!fs::remove(p, ec) || ec)
      throw OutputError(p.string() + ": cannot remove this output of a previous run: " + ec.message());
  }
  if (!old.empty())
    std::cerr << "rgbmesh: note: removed " << old.size() << " file" << (old.size() == 1 ? "" : "s")
              << " of a previous run from " << one_line(dir.string()) << "\n";
}

}  // namespace rgbmesh::cli
