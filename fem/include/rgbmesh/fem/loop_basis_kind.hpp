#pragma once
/// \file
/// The bases of the adaptive Loop space (loop_adaptive.hpp), apart so that options can name
/// them without the space's headers.

namespace rgbmesh::fem {

/// Which functions span the adaptive Loop space of an RGB mesh.
enum class LoopBasisKind {
  /// One function per RGB vertex: a base vertex's level-0 function, an inserted vertex's
  /// function at the level it was inserted (its detail). A coarse function keeps its whole
  /// support under every finer level, so rows grow with the depth of refinement (about 190
  /// entries on adaptive sphere-peak).
  details,
  /// The truncated hierarchical basis of the domains the RGB mesh refined (THB; Giannelli,
  /// Jüttler and Speleers 2012, for box splines Kanduč et al. 2017). Level l's domain Ω_l is
  /// the union of the level-l triangles of the Loop hierarchy whose three corners are RGB
  /// vertices (Ω_0 the whole surface; nested, since a midpoint is inserted only on an edge of
  /// present corners). A level-l function (a level-l control vertex's) is active when its
  /// support (its level-l two-ring) lies in Ω_l but not in Ω_{l+1} (Kraft's selection), and is
  /// truncated level by level: its components at level k > l on the functions whose support
  /// lies in Ω_k are dropped, those being the finer levels' business. The functions are as
  /// narrow as their level, and they sum to one. Several functions may sit at one RGB vertex
  /// (one per level where it is active), and a vertex whose two-ring the RGB mesh did not
  /// complete at its level has none of its own.
  truncated_hierarchical,
};

}  // namespace rgbmesh::fem
