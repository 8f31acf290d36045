#pragma once
// The control net of the adaptive Loop space as build_adaptive_loop_space finds it (the
// control vertices level by level, with their rules), its cells, and the pieces of the space
// built from them in more than one file (loop_adaptive.cpp, loop_thb.cpp).

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "rgbmesh/fem/loop_adaptive.hpp"

namespace rgbmesh::fem::detail {

// The control vertices as they are found, level by level: each one's rule (weights of
// control vertices one level up) and point of the surface's control net.
struct ControlNet {
  std::vector<AdaptiveLoopSpace::ControlVertex> vertex;
  std::vector<std::size_t> rule_start{0};
  std::vector<std::pair<std::int32_t, double>> rule;
  std::vector<Vec3> point;
  std::vector<std::int32_t> even_child;                       // control vertex -> the same point a level down
  std::unordered_map<std::uint64_t, std::int32_t> odd_child;  // edge (a, b) -> its midpoint a level down

  std::int32_t add(const AdaptiveLoopSpace::ControlVertex& v, const Vec3& p) {
    vertex.push_back(v);
    point.push_back(p);
    rule_start.push_back(rule.size());
    even_child.push_back(-1);
    return static_cast<std::int32_t>(vertex.size() - 1);
  }
};

// A cell: a triangle of the Loop hierarchy with its patch (vertices: control vertices).
struct Cell {
  // The patch: its connectivity (shared: a base patch, or a LoopChildPatch's, whose vertex
  // numbers are local) and its control vertices.
  const LoopPatch* shape = nullptr;
  std::vector<std::int32_t> vertices;
  std::int32_t node = -1;  // in AdaptiveLoopSpace::tree
  std::array<VertexHandle, 3> anchors;
};

/// The control values' expansion in the coefficients (see loop_adaptive.cpp).
SparseMatrix expand(const ControlNet& net, const std::vector<std::int32_t>& own,
                    const std::vector<char>& predicted, std::size_t n);

/// The truncated hierarchical basis's cells from the full tree (loop_thb.cpp).
void integrate_whole(AdaptiveLoopSpace& space, std::size_t roots, std::vector<std::int32_t>& whole,
                     std::vector<Cell>& kept, const std::vector<int>& kept_level, std::vector<Cell>& leaves,
                     std::vector<int>& leaf_level);

/// The truncated hierarchical basis on the cells found (loop_thb.cpp).
void truncated_hierarchical_basis(const ControlNet& net, const RgbMesh& mesh, const std::vector<Cell>& cells,
                                  AdaptiveLoopSpace& space);

}  // namespace rgbmesh::fem::detail
