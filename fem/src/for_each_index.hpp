#pragma once
// Per-triangle work on every core, with results independent of the number of threads: the
// work for each index is computed in parallel into per-index slots, and whatever is summed or
// scattered afterwards is done by the caller in index order, as a serial loop would. So the
// numbers are bit for bit those of one thread (runs resumed on another machine repeat the
// uninterrupted run).

#include <cstddef>

#include "rgbmesh/detail/parallel_for.hpp"

namespace rgbmesh::fem::detail {

// Calls work(i) for every i in [0, n) on every core, in blocks of `block` indices; work must
// only write to slots of its own index. Fewer than two blocks run on one thread: where each
// index is much work (an element's matrix), pass a smaller block.
template <class Work>
void for_each_index(std::size_t n, Work&& work, std::size_t block = 4096) {
  rgbmesh::detail::parallel_for(n, block, rgbmesh::detail::hardware_threads(),
                                [&work](std::size_t, std::size_t i) { work(i); });
}

}  // namespace rgbmesh::fem::detail
