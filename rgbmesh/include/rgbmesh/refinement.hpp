#pragma once
/// \file
/// Selective refinement (section V): a queue Qr of green edges to split and a queue Qc of
/// vertices to remove, driven by a level-of-detail criterion, after ROAM (Duchaineau et al.).
///
/// A criterion says which elements are under-refined (edges to split, or triangles whose level
/// must rise) and which vertices are over-refined, each with a priority (larger first). Popped
/// entries whose edge or vertex no longer exists, or no longer qualifies, are skipped.
/// Splits go through RgbMesh::split_edge (forced splits of coarser neighbours, BB-swaps), so
/// the mesh stays conforming and stable; removals through RgbMesh::remove_vertex.

#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

class LodCriterion {
 public:
  virtual ~LodCriterion() = default;
  /// \> 0 when green edge e must be split; the value is its priority.
  virtual double edge_priority(const RgbMesh& mesh, EdgeHandle e) const;
  /// \> 0 when triangle t must rise one level; its lowest green edges (or, for a blue
  /// triangle, those of its red sibling) are then queued with this priority.
  virtual double triangle_priority(const RgbMesh& mesh, TriangleHandle t) const;
  /// \> 0 when removable vertex v is over-refined; the value is its priority.
  virtual double vertex_priority(const RgbMesh& mesh, VertexHandle v) const;
  /// Stop refining once true (budgets).
  virtual bool satisfied(const RgbMesh& mesh) const;
  /// Whether elements created by the run are tested too (false for marks computed once on
  /// the initial mesh, such as error indicators of a solution).
  virtual bool tests_new_elements() const { return true; }
  /// Whether priorities of existing elements change as the mesh refines around them (edges
  /// that become refinable, stencil points that become exact): the run then also tests the
  /// far edges of new triangles, and re-tests the whole mesh until a pass splits nothing.
  virtual bool priorities_change_nearby() const { return false; }
  /// The number of triangles the run will end with when the criterion knows it (budgets), 0
  /// otherwise: the mesh's arrays are then sized for it once instead of doubling as they grow
  /// (a doubled array holds up to twice what it needs, and both copies while it moves).
  virtual std::size_t final_triangles() const { return 0; }
};

struct RefinementOptions {
  /// Splits that would create a vertex above this level are not performed.
  int max_level = kMaxLevel;
  /// A ceiling on the mesh's arrays (RgbMesh::memory_bytes) and the queues, in bytes; 0: none.
  /// Refinement stops before it would pass it (counting the copy an array makes when it
  /// grows), leaving a valid, stable mesh, and says so in RefinementResult.
  std::size_t max_mesh_bytes = 0;
  /// Called now and then with (operations done, queue size) for progress reports.
  std::function<void(std::uint64_t, std::size_t)> progress;
  /// Carries out the stage's removals instead of the queue (a distributed mesh: each process
  /// removes the candidates of its own part, then the processes exchange and go on, to the
  /// same end). Called with the mesh and the criterion after every element is tested and
  /// before any split; returns the removals. Whatever the order of the removals, a stage ends
  /// with the same mesh when the criterion's vertex priorities stay fixed as vertices go
  /// (FieldCriterion): a removal never makes another candidate unremovable (section IV-D:
  /// the new neighbours are no finer than the removed vertex), so every order reaches the
  /// one mesh in which no candidate is left.
  std::function<std::uint64_t(RgbMesh&, const LodCriterion&)> coarsen;
};

struct RefinementResult {
  std::uint64_t splits = 0;    ///< vertices inserted (forced splits included)
  std::uint64_t removals = 0;  ///< vertices removed
  std::uint64_t skipped = 0;   ///< stale queue entries
  bool stopped_at_memory_limit = false;  ///< RefinementOptions::max_mesh_bytes reached
};

/// The counts of the mesh at uniform level `level` (every part refined or coarsened to it),
/// from the invariants of Loop refinement: the base has T0 = 2 (V0 - χ) - B0 triangles (B0
/// boundary edges), level L has T0 4^L triangles and B0 2^L boundary edges, E = (3T + B) / 2
/// and V = χ + E - T. Exact for any mesh of the same base. Doubles: large levels overflow
/// every integer type.
struct MeshCounts {
  double vertices = 0, edges = 0, triangles = 0;
  double bytes() const;  ///< RgbMesh::storage_bytes for these counts
};
MeshCounts uniform_level_counts(const RgbMesh& mesh, int level);

/// Runs one stage: fills both queues from the whole mesh, removes over-refined vertices, then
/// splits under-refined edges, until both queues are empty or the criterion is satisfied.
/// UniformLevel and CoarsenAll, which depend on levels only, run as level-by-level sweeps
/// without queues (same result, less work); a uniform mesh is refined a whole level at a time
/// (RgbMesh::split_all_edges, on every core), so progress is reported between levels there.
RefinementResult selective_refinement(RgbMesh& mesh, const LodCriterion& criterion,
                                      const RefinementOptions& options = {});

// ---- built-in criteria --------------------------------------------------------------------

/// Every part of the mesh at exactly `level`: splits green edges below it, removes vertices
/// above it.
class UniformLevel final : public LodCriterion {
 public:
  explicit UniformLevel(int level) : level_(level) {}
  int level() const { return level_; }
  double edge_priority(const RgbMesh& m, EdgeHandle e) const override;
  double vertex_priority(const RgbMesh& m, VertexHandle v) const override;

 private:
  int level_;
};

/// At least `level` on every triangle (refines only): a floor under adaptive refinement.
class AtLeastLevel final : public LodCriterion {
 public:
  explicit AtLeastLevel(int level) : level_(level) {}
  double triangle_priority(const RgbMesh& m, TriangleHandle t) const override;

 private:
  int level_;
};

/// At least `level` on every triangle that meets the ball (refines only).
class BallLevel final : public LodCriterion {
 public:
  BallLevel(Vec3 center, double radius, int level) : center_(center), radius_(radius), level_(level) {}
  double triangle_priority(const RgbMesh& m, TriangleHandle t) const override;

 private:
  Vec3 center_;
  double radius_;
  int level_;
};

/// No edge longer than `length` (refines only; the longest first).
class MaxEdgeLength final : public LodCriterion {
 public:
  explicit MaxEdgeLength(double length) : length_(length) {}
  double triangle_priority(const RgbMesh& m, TriangleHandle t) const override;

 private:
  double length_;
};

/// Splits where the surface is not yet resolved to `tolerance`: a green edge of level l splits
/// when the control point its split would create lies farther than the tolerance from the
/// edge's midpoint at level l (Eq. 1); a boundary edge, whose new point is its midpoint
/// (Eq. 2), splits when one of its endpoints would move farther than that at level l+1
/// (Eq. 5). Stencil points that are not available without inserting vertices are replaced by
/// the shown control points (an approximation near coarser regions only).
class GeometricTolerance final : public LodCriterion {
 public:
  explicit GeometricTolerance(double tolerance) : tolerance_(tolerance) {}
  double edge_priority(const RgbMesh& m, EdgeHandle e) const override;
  bool priorities_change_nearby() const override { return true; }
  /// The deviation that edge_priority compares with the tolerance (e must be refinable).
  static double deviation(const RgbMesh& m, EdgeHandle e);

 private:
  double tolerance_;
};

/// Splits the longest green edges until the mesh has at least `triangles` triangles.
class TriangleBudget final : public LodCriterion {
 public:
  explicit TriangleBudget(std::size_t triangles) : triangles_(triangles) {}
  double edge_priority(const RgbMesh& m, EdgeHandle e) const override;
  bool satisfied(const RgbMesh& m) const override { return m.num_triangles() >= triangles_; }
  std::size_t final_triangles() const override { return triangles_; }

 private:
  std::size_t triangles_;
};

/// Removes every vertex that is not in the base mesh.
class CoarsenAll final : public LodCriterion {
 public:
  double vertex_priority(const RgbMesh& m, VertexHandle v) const override;
};

/// An external field, sampled once on the current mesh (e.g. a finite-element error
/// indicator): triangles whose value exceeds refine_above rise one level, removable vertices
/// whose value is below coarsen_below are removed. Values are indexed by handle slot; an
/// empty vector disables that half. New elements created by the run are not tested.
class FieldCriterion final : public LodCriterion {
 public:
  FieldCriterion(std::vector<double> triangle_values, double refine_above, std::vector<double> vertex_values,
                 double coarsen_below);
  double triangle_priority(const RgbMesh& m, TriangleHandle t) const override;
  double vertex_priority(const RgbMesh& m, VertexHandle v) const override;
  bool tests_new_elements() const override { return false; }

 private:
  std::vector<double> triangle_values_;
  double refine_above_;
  std::vector<double> vertex_values_;
  double coarsen_below_;
};

// ---- random operation sequences (a testing aid) -------------------------------------------

struct RandomWalkOptions {
  int max_level = 6;               ///< splits stay below this level
  std::size_t max_triangles = 0;   ///< 0: 64 x the base mesh; above it, only removals
  double split_probability = 0.5;  ///< chance that a step tries a split first
  /// Called after each step (tests validate the mesh here).
  std::function<void(std::uint64_t step)> after_step;
};

/// Performs `steps` random operations: a split_edge of a random green edge or a
/// remove_vertex of a random removable vertex, reproducibly from `seed`.
RefinementResult random_walk(RgbMesh& mesh, std::uint64_t steps, std::uint64_t seed,
                             const RandomWalkOptions& options = {});

}  // namespace rgbmesh
