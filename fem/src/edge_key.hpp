// The key of an unordered pair of indices (an edge by its ends), for hash maps inside fem.
#pragma once

#include <cstdint>
#include <utility>

namespace rgbmesh::fem::detail {

inline std::uint64_t edge_key(std::int32_t a, std::int32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

}  // namespace rgbmesh::fem::detail
