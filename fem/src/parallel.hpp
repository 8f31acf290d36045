#pragma once
// Per-triangle work on every core, with results independent of the number of threads: the
// work for each index is computed in parallel into per-index slots, and whatever is summed or
// scattered afterwards is done by the caller in index order, as a serial loop would. So the
// numbers are bit for bit those of one thread (runs resumed on another machine repeat the
// uninterrupted run).

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace rgbmesh::fem::detail {

// Calls work(i) for every i in [0, n), on up to hardware_concurrency() threads in blocks of
// 4096 indices; work must only write to slots of its own index. The first exception is
// rethrown once every thread has stopped; where a thread cannot be started, the others do its
// share.
template <class Work>
void for_each_index(std::size_t n, Work&& work) {
  constexpr std::size_t kBlock = 4096;
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  const std::size_t threads = std::min<std::size_t>(std::max(1u, std::thread::hardware_concurrency()), blocks);
  if (threads <= 1) {
    for (std::size_t i = 0; i < n; ++i) work(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto run = [&] {
    for (std::size_t b; !failed.load() && (b = next.fetch_add(1)) < blocks;) {
      try {
        for (std::size_t i = b * kBlock, end = std::min(n, i + kBlock); i < end; ++i) work(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        failed.store(true);
      }
    }
  };
  std::vector<std::thread> pool;
  try {
    for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(run);
  } catch (const std::exception&) {
  }
  run();
  for (std::thread& thread : pool) thread.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace rgbmesh::fem::detail
