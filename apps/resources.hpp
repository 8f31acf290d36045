#pragma once
// Memory: what the machine has, the ceiling the tool works under, and figures for messages.
//
// The ceiling is on the process's resident memory. By default it is 80% of the memory
// available when the tool starts (Linux MemAvailable, lowered to a cgroup's limit when one is
// set) plus what the process already holds; `--memory-limit` sets it (bytes with an optional
// K/M/G/T suffix, or a percentage of the available memory). Predictable work (a uniform level,
// a triangle budget) is refused up front when its estimate passes the ceiling; open-ended
// refinement stops at it. Either way: a ResourceError naming the figures (exit code 3).

#include <cstddef>
#include <string>

namespace rgbmesh::cli {

// Bytes the kernel says can be allocated without swapping (MemAvailable), lowered to the
// cgroup's remaining allowance when the process runs under a memory limit; 0 if unknown.
std::size_t available_memory_bytes();

// The memory of the machine (MemTotal), lowered to the cgroup's limit when the process runs
// under one; 0 if unknown.
std::size_t machine_memory_bytes();

// The process's resident memory now (0 if unknown).
std::size_t resident_memory_bytes();

// Gives the allocator's free pages back to the system (glibc: malloc_trim). Small blocks freed
// in the middle of the heap stay resident otherwise: after a moving feature's largest cycle
// (940,000 unknowns) the run went on holding 330 MB for a mesh a fifth that size.
void release_free_memory();

// "13.1 GB", "512 MB", "740 kB".
std::string human_bytes(double bytes);

class MemoryCeiling {
 public:
  // From the option's text: "" (the default: 80% of the available memory), "75%", "8G",
  // "512M", "1000000". InputError for anything else. A size above the machine's memory is
  // capped at it, with a note() saying so: an estimate that no machine could hold would
  // otherwise never be refused up front.
  static MemoryCeiling from_option(const std::string& text);
  // "" or one line for standard error, to print once.
  const std::string& note() const { return note_; }

  std::size_t bytes() const { return bytes_; }
  // What the limit is, for messages: "7.5 GB (80% of the available memory; --memory-limit to
  // change)" or "2 GB (--memory-limit)".
  std::string describe() const;
  // The bytes still free under the ceiling for work that has not started yet.
  std::size_t headroom() const;

 private:
  std::size_t bytes_ = 0;
  std::string origin_, note_;
};

}  // namespace rgbmesh::cli
