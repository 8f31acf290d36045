#pragma once
/// \file
/// What one process of a distributed mesh holds: its own triangles and ghost layers as the
/// whole mesh has them, the rest as coarse as the RGB rules allow.

#include <array>
#include <cstdint>
#include <map>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "rgbmesh/canonical.hpp"
#include "rgbmesh/mesh.hpp"

namespace rgbmesh::parallel {

/// A copy of `mesh` coarsened away from the kept triangles (`keep`, per triangle slot): every
/// vertex above `floor` is removed, finest first and for as long as any can be, except the
/// corners of the kept triangles and of `ghost_layers` layers of triangles around them (each
/// layer: the triangles with a corner in the previous ones). The kept and ghost triangles stay
/// as they are (the same corners, handles and positions); elsewhere the mesh keeps only what
/// conformity and the RGB rules need between them and the floor. Its size against the whole
/// mesh's is the memory a process needs when the mesh is distributed.
RgbMesh local_view(const RgbMesh& mesh, const std::vector<char>& keep, int floor, int ghost_layers = 1);
/// The same in place: `view` coarsened away from its kept triangles and their ghost layers.
/// Returns the vertices removed.
std::size_t coarsen_away(RgbMesh& view, const std::vector<char>& keep, int floor, int ghost_layers = 1);

/// A vertex's name across the processes' views: a vertex of the start mesh (the one the views
/// were made from, whose vertices keep their slots in every view) by its slot, a vertex
/// inserted since by a 64-bit mix of its parents' keys (marked by the top bit), so that the
/// name does not depend on which process inserted it or in which order.
/// (The mix is canonical.hpp's child_name: keys and names differ only in the start vertices,
/// named by slot here and by base index there.)
using VertexKey = VertexName;
inline VertexKey child_key(VertexKey a, VertexKey b) { return child_name(a, b); }

/// The keys of a view's vertices; `start` lists the slots of its vertices that come from the
/// start mesh (those alive before it was refined).
struct VertexKeys {
  std::unordered_map<std::int32_t, VertexKey> of_slot;
  std::unordered_map<VertexKey, VertexHandle> vertex;
  std::unordered_map<VertexKey, std::array<VertexKey, 2>> parents;  ///< the inserted vertices'
};
VertexKeys vertex_keys(const RgbMesh& view, const std::unordered_set<std::int32_t>& start);
/// The slots of the mesh's live vertices.
std::unordered_set<std::int32_t> vertex_slots_alive(const RgbMesh& mesh);

/// The region of a set of start vertices: them, and every inserted vertex whose parents are
/// both in it (by keys).
std::unordered_set<VertexKey> key_region(const std::unordered_set<VertexKey>& start, const VertexKeys& keys);

/// Makes in a view the splits other processes made (key -> parents' keys) whose parents both
/// lie in its fine region (`fine`: its part's and ghost layers' start vertices, and what they
/// enclose), each with split_edge on the edge between the parents. Returns how many it made.
std::size_t make_splits(RgbMesh& view, const std::unordered_set<std::int32_t>& start,
                        const std::unordered_set<VertexKey>& fine,
                        const std::map<VertexKey, std::array<VertexKey, 2>>& splits);

/// After each process refined its view (start: its start vertices' slots; fine: its part's and
/// ghost layers' start vertices), hands every split each made to all (MPI), and makes those
/// whose parents lie in its fine region, round after round until no process changes: then
/// every part holds the triangles, and the positions, that refining the whole mesh gives.
/// Called by every process. Without MPI: nothing to hand over.
struct Reconciled {
  std::size_t made = 0;  ///< splits this process made for the others
  int rounds = 0;
};
Reconciled reconcile_splits(RgbMesh& view, const std::unordered_set<std::int32_t>& start,
                            const std::unordered_set<VertexKey>& fine);

}  // namespace rgbmesh::parallel
