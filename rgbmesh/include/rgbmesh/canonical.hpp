#pragma once
/// \file
/// What makes a mesh independent of the order of the operations that built it: names for
/// vertices that depend only on their ancestry, and one choice of every trapezoid's diagonal.
///
/// An RGB mesh is fixed by its base mesh, its set of vertices and one choice the set leaves
/// open (rgb_state.hpp): in a parent triangle with two split edges, which diagonal of the
/// trapezoid is the red edge, which depends on the order of the insertions. Processes of a
/// distributed run insert the same vertices in different orders; with the diagonals chosen
/// by names (canonical_diagonals) after each adaptation, they hold the triangles one process
/// holds.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

/// A vertex's name: a base vertex (level 0) by its slot, which is its index in the base mesh
/// for every copy of a mesh built from it; an inserted vertex by a 64-bit mix of its parents'
/// names, with the top bit set. Equal vertices of two meshes refined from one base in any
/// order have equal names (collisions of the mix, 2^-64 per pair, are not handled).
using VertexName = std::uint64_t;
VertexName child_name(VertexName a, VertexName b);
/// The names of the live vertices, by slot (free slots: 0).
std::vector<VertexName> vertex_names(const RgbMesh& mesh);

/// Makes every trapezoid's diagonal (a red edge between a red and a blue triangle of one
/// parent) the one that ends at the trapezoid's corner with the smallest name, with swap_rb.
/// Both diagonals are valid RGB configurations (section IV-B; the paper's RB-swap); choosing
/// one by names makes the mesh a function of its vertex set. Returns the swaps made.
std::size_t canonical_diagonals(RgbMesh& mesh, const std::vector<VertexName>& names);
inline std::size_t canonical_diagonals(RgbMesh& mesh) { return canonical_diagonals(mesh, vertex_names(mesh)); }
/// canonical_diagonals for the trapezoids that have a triangle at one of `vertices` (those an
/// operation inserted, or whose stars a removal changed): after each operation of a stage, so
/// that the mesh between operations, which the stage's criteria read, is a function of its
/// vertex set too. `names` by slot (vertex_names).
std::size_t canonical_diagonals_near(RgbMesh& mesh, const std::vector<VertexName>& names,
                                     const std::vector<VertexHandle>& vertices);

/// The live vertices in an order that depends on the mesh alone (as a set of named vertices),
/// never on handles: level by level, the base vertices by base index, every finer level by its
/// parents' positions in the order (the smaller first). Children of nearby parents stay nearby,
/// so numbering unknowns this way keeps their locality. Parents come before their children,
/// which is also the order restore_state needs.
std::vector<VertexHandle> canonical_vertex_order(const RgbMesh& mesh);
/// The live triangles in an order that depends on the mesh alone: by their corners' positions
/// in `vertex_order` (canonical_vertex_order), each triangle's corners rotated to start at the
/// first of them (the orientation kept), compared lexicographically.
std::vector<TriangleHandle> canonical_triangle_order(const RgbMesh& mesh, const std::vector<VertexHandle>& vertex_order);

}  // namespace rgbmesh
