#pragma once
// The complete RGB state of a mesh as plain arrays, so that a mesh written to a file can be
// read back into an RgbMesh identical to the one written: same triangles, colours, levels,
// control points and limit positions, and the same behaviour under further refinement and
// coarsening (coarsening everything returns exactly the base mesh).
//
// What is saved, and why that is enough: an RGB mesh is determined by its base mesh Σ0, the
// set of vertices it holds and, found by tests/test_rgb_state.cpp, one choice that the set
// leaves open: a parent triangle with two split edges is a green corner plus a trapezoid,
// and which diagonal of the trapezoid is the red edge depends on the order of the insertions
// (the control points and limit positions do not). A vertex of level l > 0 is the midpoint
// of the green edge of level l-1 between its two parents, so the set is written as one pair
// of parents per inserted vertex; Σ0 is saved exactly (control points as doubles, triangles);
// the diagonals are read off the file's own triangles. Colours, levels, control points and
// limit positions are recomputed, never taken from the file, and compared with it.
//
// Restoring rebuilds Σ0 with RgbMesh::from_triangles and inserts the saved vertices, parents
// first, each with split_edge on the edge between its parents. split_edge may insert other
// vertices on the way: forced splits, which must be saved vertices, and helpers that a Loop
// stencil needs for a limit position (the original process needed others, in its order),
// which are removed again at the end. Then each trapezoid whose diagonal differs from the
// file's is swapped (swap_rb), and the triangles, levels and colours must be the file's.
// Anything else is an inconsistent state: InputError.
//
// Handles are not preserved: the restored mesh numbers its vertices in insertion order (the
// points' order in the file when parents come first, which is the usual case). Files carry no
// free slots, observers, properties or operation counters.

#include <array>
#include <cstdint>
#include <vector>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/snapshot.hpp"  // RgbState, the arrays themselves

namespace rgbmesh {

// The state of `mesh` for a snapshot of it (points named by snapshot.vertex_handle, which must
// list every live vertex once). std::invalid_argument if the snapshot does not.
RgbState save_state(const RgbMesh& mesh, const MeshSnapshot& snapshot);

// A piece's state (a distributed run's output: each process writes its own triangles): the
// entries of `points` first, in that order, then the ancestors of those that are not among
// them (each entry's parents are earlier or later entries of the same state). The base mesh
// is the whole one. std::invalid_argument if a point is not a live vertex or is listed twice.
RgbState save_piece_state(const RgbMesh& mesh, const std::vector<VertexHandle>& points);

// The pieces' states joined into the whole mesh's (each vertex once, identified by its
// ancestry: canonical.hpp's names), for restore_state; entry_of[k][i] is where piece k's entry
// i went. InputError (one line, naming the piece) where a piece is inconsistent: sizes,
// indices, parents that form a cycle, or a base mesh that differs from the first piece's.
RgbState join_piece_states(const std::vector<RgbState>& pieces,
                           std::vector<std::vector<std::int32_t>>& entry_of);

// What restore_state checks the rebuilt mesh against (all optional: empty means unchecked).
// Indices are the state's point indices.
struct RestoreExpectations {
  std::vector<std::array<std::int32_t, 3>> triangles;  // the file's triangles (any rotation)
  std::vector<std::uint8_t> vertex_level;              // per point
  std::vector<std::uint8_t> triangle_level;            // per triangle above
  std::vector<std::uint8_t> triangle_color;            // per triangle above (0 green, 1 red, 2 blue)
  // Per point: the shown control point and the limit position the file has for it; they must
  // agree with the rebuilt mesh within 1e-9 of the points' bounding-box diagonal (they catch
  // edited base points).
  std::vector<Vec3> control_points;
  std::vector<Vec3> limits;
};

// The restored mesh, and where each of the state's points went.
struct RestoredMesh {
  RgbMesh mesh;
  std::vector<VertexHandle> vertex;  // state point i -> its vertex in `mesh`
};

// Rebuilds the mesh. InputError (one line saying what is wrong, without a file name: the
// caller prefixes it) when the state is inconsistent: sizes, indices out of range, a base
// vertex missing or listed twice, parents that form a cycle or are not joined by an edge,
// a forced vertex the state does not list, a vertex listed twice, levels, triangles or colours
// that differ from the expectations, or a mesh that fails validate().
RestoredMesh restore_state(const RgbState& state, const RestoreExpectations& expected = {});

}  // namespace rgbmesh
