// The patch machinery that loop_basis.cpp (gathering, subdivision, evaluation) shares with
// loop_creases.cpp (the rules of sharp features): the rules of a corner with sharp edges need
// the fans as gathering finds them, and a step of subdivision asks them for the child's walls
// and rows. Internal: only those two files include it.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <utility>
#include <vector>

#include "rgbmesh/fem/loop_basis.hpp"
#include "rgbmesh/loop_rules.hpp"

namespace rgbmesh::fem::detail {

using Triangles = std::vector<std::array<int, 3>>;

// Per entry of a vertex's ring (as the ring oracle gave it): whether the edge to it is a wall,
// infinitely sharp, so that where a fan has two or more (its boundary edges counting) it is cut
// into sectors there. Called with the corner's index (0-2), its vertex and ring.
using WallOracle = std::function<void(int corner, std::int32_t vertex, const std::vector<std::int32_t>& ring,
                                      std::vector<char>& wall)>;

// What gathering found of a corner's fan: its ring oriented counter-clockwise from the next
// corner (the whole fan), each entry's place in the oracle's ring, the entries of the sector
// that holds the central triangle (from the next corner on), the patch vertex of each of those
// (-1 for the entries outside), and the entry after which an open fan has no triangle.
struct Fan {
  std::vector<std::int32_t> ring;
  std::vector<int> raw, sector, vertex;
  int boundary_gap = -1;
  bool boundary(std::size_t i) const {
    const int m = static_cast<int>(ring.size());
    return boundary_gap >= 0 &&
           (static_cast<int>(i) == boundary_gap || static_cast<int>(i) == (boundary_gap + 1) % m);
  }
};

// The patch of a triangle (see gather_loop_patch), its corners' fans cut at walls where
// `walls_of` is given, with what was found of them in `fans` (if given).
LoopPatch gather_patch(const std::array<std::int32_t, 3>& corners, const RingOracle& ring_of,
                       const WallOracle* walls_of, std::array<Fan, 3>* fans_out);

// Cuts a corner's fan into the sector of the central triangle. The fan's entry i is entry
// (start ± i) mod m of the oracle's ring `raw` (+ going `forward`), and fan.boundary_gap is
// set; `raw_wall` marks the oracle's entries that are walls (null: none but the boundary's).
// Fills fan.raw, fan.ring and fan.sector, the walls per fan entry and the sector's ring, and
// returns the entry after which the sector has no triangle (-1: a closed fan, whole).
int cut_fan(const std::vector<std::int32_t>& raw, const std::vector<char>* raw_wall, bool closed,
            std::size_t start, bool forward, Fan& fan, std::vector<char>& wall,
            std::vector<std::int32_t>& sector_ring);

// One Loop step of a patch, kept to one child of its central triangle.
struct Child {
  LoopPatch patch;
  Eigen::MatrixXd from_parent;             ///< patch values = from_parent * parent patch values
  std::vector<std::array<int, 2>> origin;  ///< per child vertex: {parent vertex, -1} or the edge's ends
};

// The patch of child `child` of a patch's central triangle.
Child subdivide(const LoopPatch& parent, int child);

// An edge of a patch being subdivided: its ends (a < b) and the vertices opposite it. Edge e's
// midpoint is vertex n + e of the subdivided patch (n: the patch's vertices).
struct PatchEdge {
  int a, b;
  std::vector<int> opposite;
};

// One step of a corner's rules: its sharp edges' sharpness now (s) and of their halves at the
// corner one level down (t), its own sharpness now and then, and its rule on both levels.
struct CornerStep {
  std::vector<float> s, t;
  float vs = 0, vt = 0;
  VertexRule rule = VertexRule::smooth, next = VertexRule::smooth;
};

// A row of a column-major matrix (strided).
using MatrixRow = Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>>;

// One step of subdivision of a patch with sharp features (LoopPatch::creases), one level of
// the rules at its corners as the RGB mesh's vertices evolve (rgbmesh/src/creases.cpp): what
// subdivide asks of the features in place of the plain rules.
class CreaseStep {
 public:
  explicit CreaseStep(const LoopCreases& creases);
  // The patch of the child whose corners are `corners` in the subdivided patch (whose rings
  // `fine_ring` gives; n: the parent's vertices, `edges` its edges, `midpoint` their indices by
  // their ends), its fans cut at the halves of the parent's walls, with its own features.
  LoopPatch gather_child(const std::array<int, 3>& corners, const RingOracle& fine_ring, int n,
                         const std::vector<PatchEdge>& edges,
                         const std::map<std::pair<int, int>, int>& midpoint) const;
  // Adds corner k's vertex rule to its row of the subdivision matrix.
  void add_even_row(int k, MatrixRow row) const;
  // The edge rule of the patch's edge ab (one end a corner).
  loop::OddMask odd_mask(int a, int b) const;

 private:
  const LoopCreases& creases_;
  std::array<CornerStep, 3> steps_;
};

// The limit mask at corner `corner` of a patch with sharp features (see loop_corner_limit).
Eigen::VectorXd crease_corner_limit(const LoopPatch& patch, int corner);

// The sharp features' part of the key of a patch's caches: the corners' rings and sharp edges,
// bit for bit.
std::vector<std::uint32_t> crease_key(const LoopCreases& creases);

}  // namespace rgbmesh::fem::detail
