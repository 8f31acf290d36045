#include "resources.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <limits>
#include <sstream>

#include "rgbmesh/errors.hpp"

namespace rgbmesh::cli {

namespace {

// The first number in a one-line file ("max" and unreadable files: none).
bool read_number(const char* path, double& value) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text)) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0' && std::isfinite(value);
}

}  // namespace

std::size_t available_memory_bytes() {
  double available = 0;
  std::ifstream meminfo("/proc/meminfo");
  for (std::string key; meminfo >> key;) {
    double kb = 0;
    std::string unit;
    meminfo >> kb >> unit;
    if (key == "MemAvailable:") {
      available = kb * 1024.0;
      break;
    }
  }
  // A cgroup (v2, then v1) may allow less than the machine has.
  double limit = 0, used = 0;
  if (read_number("/sys/fs/cgroup/memory.max", limit) && read_number("/sys/fs/cgroup/memory.current", used)) {
    available = available > 0 ? std::min(available, std::max(0.0, limit - used)) : std::max(0.0, limit - used);
  } else if (read_number("/sys/fs/cgroup/memory/memory.limit_in_bytes", limit) &&
             read_number("/sys/fs/cgroup/memory/memory.usage_in_bytes", used) && limit < 1e18) {
    available = available > 0 ? std::min(available, std::max(0.0, limit - used)) : std::max(0.0, limit - used);
  }
  return static_cast<std::size_t>(available);
}

std::size_t machine_memory_bytes() {
  double total = 0;
  std::ifstream meminfo("/proc/meminfo");
  for (std::string key; meminfo >> key;) {
    double kb = 0;
    std::string unit;
    meminfo >> kb >> unit;
    if (key == "MemTotal:") {
      total = kb * 1024.0;
      break;
    }
  }
  double limit = 0;
  if (read_number("/sys/fs/cgroup/memory.max", limit) ||
      (read_number("/sys/fs/cgroup/memory/memory.limit_in_bytes", limit) && limit < 1e18))
    total = total > 0 ? std::min(total, limit) : limit;
  return static_cast<std::size_t>(total);
}

std::size_t resident_memory_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t pages_total = 0, pages_resident = 0;
  if (!(statm >> pages_total >> pages_resident)) return 0;
  return pages_resident * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
}

void release_free_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

std::string human_bytes(double bytes) {
  const char* units[] = {"bytes", "kB", "MB", "GB", "TB", "PB", "EB"};
  int u = 0;
  while (bytes >= 1000.0 && u < 6) {
    bytes /= 1000.0;
    ++u;
  }
  char buf[64];
  if (u == 6 && bytes >= 1000.0)
    std::snprintf(buf, sizeof buf, "%.2g EB", bytes);
  else
    std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : (bytes < 10 ? "%.1f %s" : "%.0f %s"), bytes, units[u]);
  return buf;
}

MemoryCeiling MemoryCeiling::from_option(const std::string& text) {
  MemoryCeiling c;
  const double available = static_cast<double>(available_memory_bytes());
  const double resident = static_cast<double>(resident_memory_bytes());
  auto bad = [&] {
    return InputError("--memory-limit: '" + text + "' is not a size (e.g. 8G, 512M, 75%)");
  };
  double fraction = 0.8;
  if (!text.empty() && text.back() == '%') {
    char* end = nullptr;
    const double percent = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size() - 1 || !(percent > 0 && percent <= 100)) throw bad();
    fraction = percent / 100.0;
  } else if (!text.empty()) {
    char* end = nullptr;
    double value = std::strtod(text.c_str(), &end);
    const std::string suffix(end);
    const double scale = suffix.empty() ? 1.0
                         : suffix == "K" || suffix == "k" ? 1e3
                         : suffix == "M" ? 1e6
                         : suffix == "G" ? 1e9
                         : suffix == "T" ? 1e12
                                          : -1.0;
    value *= scale;
    if (end == text.c_str() || !(scale > 0) || !(value >= 1e6) || !std::isfinite(value)) throw bad();
    c.origin_ = "--memory-limit";
    const double machine = static_cast<double>(machine_memory_bytes());
    if (machine > 0 && value > machine) {
      c.note_ = "--memory-limit " + text + " is more than the " + human_bytes(machine) +
                " of memory the machine has: the ceiling is " + human_bytes(machine);
      value = machine;
      c.origin_ = "the machine's memory; --memory-limit " + text + " is more";
    }
    c.bytes_ = static_cast<std::size_t>(std::min(value, 9e18));
    return c;
  }
  if (available <= 0) {
    // Unknown (not Linux?): no ceiling rather than a made-up one.
    c.bytes_ = std::numeric_limits<std::size_t>::max();
    c.origin_ = "unknown: the available memory could not be read";
    return c;
  }
  c.bytes_ = static_cast<std::size_t>(resident + fraction * available);
  char origin[96];
  std::snprintf(origin, sizeof origin, "%.0f%% of the %s available; --memory-limit to change", 100 * fraction,
                human_bytes(available).c_str());
  c.origin_ = origin;
  return c;
}

std::string MemoryCeiling::describe() const {
  if (bytes_ == std::numeric_limits<std::size_t>::max()) return "none (" + origin_ + ")";
  return human_bytes(static_cast<double>(bytes_)) + " (" + origin_ + ")";
}

std::size_t MemoryCeiling::headroom() const {
  const std::size_t resident = resident_memory_bytes();
  return resident < bytes_ ? bytes_ - resident : 0;
}

}  // namespace rgbmesh::cli
