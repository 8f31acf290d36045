#pragma once
/// \file
/// The unit of distribution: macro triangles (the triangles of the uniform level-K mesh) and
/// their partition among processes.
///
/// RGB refinement is local: under a floor at level K (no triangle coarser than K, as
/// adapt::AdaptOptions::min_level keeps it), every triangle of the mesh lies inside exactly
/// one triangle of the uniform level-K mesh, whatever was refined or coarsened above it. Those
/// macro triangles are the pieces a distributed run hands out, each with the refinement it
/// holds; their number grows by 4 per level, so K can be chosen for the number of processes
/// even when the user's base has a handful of triangles (macro_level_for).

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "rgbmesh/fem/solver.hpp"
#include "rgbmesh/fem/surface_mesh.hpp"
#include "rgbmesh/mesh.hpp"

namespace rgbmesh::parallel {

struct MacroTriangles {
  int level = 0;
  std::vector<std::array<VertexHandle, 3>> corners;  ///< per macro triangle, counter-clockwise
  std::vector<std::array<std::int32_t, 3>> across;   ///< the macro triangle across edge k (corner k to k+1); -1 on the boundary
  std::vector<std::int32_t> of_triangle;             ///< per triangle slot of the mesh: its macro triangle (-1: free slot)
  std::vector<std::size_t> triangles;                ///< per macro triangle: the mesh's triangles inside it
};

/// The macro triangles at `level` and which one holds each triangle of the mesh. Each vertex
/// is placed in the smallest cell of the level-`level` mesh that holds it (a macro vertex, the
/// inside of a macro edge, or of a macro triangle): a vertex above the level sits halfway
/// between its parents, so its cell is the smallest one holding both of theirs; a triangle
/// lies in the macro triangle that holds its three corners. Throws std::invalid_argument if a
/// triangle is coarser than `level`.
MacroTriangles macro_triangles(const RgbMesh& mesh, int level);

struct Partition {
  int parts = 1;
  std::vector<std::int32_t> part_of;  ///< per macro triangle, in [0, parts)
  std::vector<std::size_t> weight;    ///< per part: the mesh's triangles it holds
  double imbalance = 1;               ///< the largest part's weight over the mean
};

/// Splits the macro triangles into `parts` connected groups of nearly equal weight (the mesh's
/// triangles they hold) with few edges between them: METIS's k-way partition of their dual
/// graph, seeded for reproducible results. Throws std::invalid_argument for fewer macro
/// triangles than parts.
Partition partition(const MacroTriangles& macro, int parts);

/// Units of distribution finer than the macro triangles where the mesh is heavy: a macro
/// triangle at the floor holding more than `share` times the mean part's triangles (the mesh's
/// triangles over `parts`) is replaced by its four sub-triangles of the next level (the cells
/// of the uniform mesh one level down that hold its triangles), and so on down, as long as all
/// of a unit's triangles are finer than it (a forest of quadtrees over the macro triangles).
/// A refinement gathered in a few macro triangles is then still spread over many units.
struct Units {
  std::vector<int> level;                             ///< per unit: its level (the floor or finer)
  std::vector<std::int32_t> cell;                     ///< per unit: its cell among that level's triangles
  std::vector<std::size_t> triangles;                 ///< per unit: the mesh's triangles inside it
  std::vector<std::int32_t> of_triangle;              ///< per triangle slot: its unit (-1: free slot)
  std::vector<std::vector<std::int32_t>> neighbours;  ///< units sharing an edge of the mesh
  /// shared_units: the cells (level, cell) divided into units below them.
  std::vector<std::pair<int, std::int32_t>> split;
};
/// What units() keeps between calls on the meshes of one run: the uniform mesh of the floor
/// (whose making, a copy of the mesh coarsened to the floor, is most of units' time), made from
/// the first mesh holding the whole floor and used again for every mesh whose vertices at or
/// below the floor are among its own (found by their names, whatever their slots): the run's
/// later meshes, and the views of a distributed run, which hold the floor only near their part.
/// Without a cache a mesh must hold the whole floor. make_floor_cache() makes an empty one.
struct FloorCache;
std::shared_ptr<FloorCache> make_floor_cache();
Units units(const RgbMesh& mesh, int floor, int parts, double share = 0.1, FloorCache* cache = nullptr);
/// METIS's k-way partition of the units' graph, weighted by the triangles each holds.
Partition partition(const Units& units, int parts);

/// Collective operations among the processes of a run, for what every process computes from
/// its own share of a mesh (distributed_mesh.hpp); each is called by every process alike.
struct Collectives {
  std::function<void(std::uint64_t* values, std::size_t count)> sum;  ///< added over the processes, in place
  /// Every process's vector, concatenated in rank order.
  std::function<std::vector<std::uint64_t>(const std::vector<std::uint64_t>&)> all_gather;
};

/// The units of a mesh held in pieces (each process a view of it: its own triangles, flagged
/// per triangle slot in `counted`, exact, the rest of its view coarser): the units that units()
/// gives the whole mesh, agreed by all processes from their counted triangles. The cells are
/// numbered by their corners' names, the same on every process; the split cells are listed
/// (Units::split) so that locate_units can place triangles in them. of_triangle, per slot of
/// this view: its unit, -1 for a triangle coarser than the unit its place belongs to (only
/// away from the counted triangles and their neighbours).
Units shared_units(const RgbMesh& view, int floor, int parts, const std::vector<char>& counted, const Collectives& all,
                   FloorCache* cache = nullptr, double share = 0.1);
/// Each triangle's unit (per triangle slot, -1 as above) in a view of the same mesh, later
/// refined or holding other pieces: the units found by shared_units on an earlier view.
std::vector<std::int32_t> locate_units(const RgbMesh& view, int floor, const Units& units, FloorCache* cache = nullptr);

/// Each finite-element triangle's part among `parts` processes: the units above `floor`
/// (units), partitioned by METIS (partition), read through fe.triangle. What a run on several
/// processes writes as pieces, and what each process will own.
std::vector<std::int32_t> triangle_parts(const RgbMesh& mesh, const fem::SurfaceMesh& fe, int floor, int parts,
                                         FloorCache* cache = nullptr);

/// The rows of a symmetric sparse matrix (both triangles stored) in `parts` groups for the
/// processes of a distributed solve: METIS's k-way partition of the matrix's graph (rows
/// coupled by a nonzero), so that each process's rows are a compact patch of the mesh and few
/// couplings cross between processes. The same result on every process (seeded).
Partition partition_rows(const fem::SparseMatrix& a, int parts);

/// The smallest level at or above `min_level` whose uniform mesh has at least
/// `per_part` macro triangles per part (the granularity rebalancing needs when the refinement
/// gathers in a few of them).
int macro_level_for(const RgbMesh& mesh, int parts, int min_level = 0, int per_part = 32);

}  // namespace rgbmesh::parallel
