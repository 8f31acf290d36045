#pragma once
// Per-triangle work on every core, with results independent of the number of threads: the
// work for each index is computed in parallel into per-index slots, and whatever is summed or
// scattered afterwards is done by the caller in index order, as a serial loop would. So the
// numbers are bit for bit those of one thread (runs resumed on another machine repeat the
// uninterrupted run).

#include <cstddef>

#include "rgbmesh/detail/parallel_for.hpp"

namespace rgbmesh::fem::detail {

// Calls work(i) for every i in [0, n) on every core, in blocks of 4096 indices; work must only
// write to slots of its own index.
template <class Work>
void for_each_index(std::size_t n, Work&& work) {
  rgbmesh::detail::parallel_for(n, 4096, rgbmesh::detail::hardware_threads(),
                                [&work](std::size_t, std::size_t i) { work(i); });
}

}  // namespace rgbmesh::fem::detail
