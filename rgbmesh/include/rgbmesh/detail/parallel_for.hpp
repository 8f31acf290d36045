#pragma once
/// \file
/// parallel_for: work on every core, for the modules' inner loops. Internal (namespace
/// detail): installed because the modules include it, not part of the API.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#if defined(__linux__)
#include <sched.h>
#endif

namespace rgbmesh::detail {

/// A cap on the threads of every loop (0: none). Several processes on one machine (an MPI
/// run) share its cores: rgbmesh::parallel sets the cores per process here.
inline std::atomic<unsigned> thread_cap{0};

/// The cores this thread may run on: the machine's, or fewer where its CPU affinity allows
/// fewer (taskset, a cpuset container, an MPI launcher that binds each process to a core, as
/// `mpirun -np 1` and `-np 2` do): threads beyond them only take turns on the same cores. At
/// least one.
inline unsigned allowed_cores() {
  const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
#if defined(__linux__)
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) {
    const int count = CPU_COUNT(&set);
    if (count > 0) return std::min(hardware, static_cast<unsigned>(count));
  }
#endif
  return hardware;
}

/// The threads worth starting: the cores this thread may run on (or the cap's, if fewer), at
/// least one.
inline std::size_t hardware_threads() {
  const unsigned cap = thread_cap.load(std::memory_order_relaxed);
  const unsigned cores = allowed_cores();
  return cap > 0 ? std::min(cap, cores) : cores;
}

/// Calls work(thread, i) for every i in [0, n), on up to `threads` threads (this one is thread
/// 0), handing out blocks of `block` consecutive indices. The first exception is rethrown once
/// every thread has stopped; where a thread cannot be started, the others do its share.
template <class Work>
void parallel_for(std::size_t n, std::size_t block, std::size_t threads, Work&& work) {
  const std::size_t blocks = (n + block - 1) / block;
  threads = std::min(threads, blocks);
  if (threads <= 1) {
    for (std::size_t i = 0; i < n; ++i) work(std::size_t{0}, i);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto run = [&](std::size_t thread) {
    for (std::size_t b; !failed.load() && (b = next.fetch_add(1)) < blocks;) {
      try {
        for (std::size_t i = b * block, end = std::min(n, i + block); i < end; ++i) work(thread, i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        failed.store(true);
      }
    }
  };
  std::vector<std::thread> pool;
  try {
    for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(run, t);
  } catch (const std::exception&) {
  }
  run(0);
  for (std::thread& thread : pool) thread.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace rgbmesh::detail
