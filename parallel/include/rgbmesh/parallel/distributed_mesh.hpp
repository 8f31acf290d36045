#pragma once
/// \file
/// The adaptive loop with the mesh itself distributed: each process holds its part of the mesh
/// and two layers of neighbours around it as the whole mesh has them, and the rest of the
/// surface as coarse as the RGB rules allow, down to the base mesh, below the run's floor (a
/// local view, local_view.hpp), so that its memory and its work follow its share of the mesh,
/// not the whole (on two processes a view holds about 0.55 of the mesh where one that kept the
/// floor held 0.88).
///
/// A cycle, on every process (AdaptOptions::distributed_mesh and its hooks):
///  1. Parts: the units (shared_units: the uniform floor's cells, divided where heavy) are
///     agreed from every process's own triangles, and partitioned by METIS. A run that
///     coarsens (its units the floor's cells) keeps the last parts while the largest holds at
///     most 10% more triangles than the mean: then nothing migrates.
///  2. Migration: each process sends the processes whose new part or ghost layers hold some of
///     its own triangles those triangles' vertices (with their ancestors, by names:
///     canonical.hpp), which insert them with split_edge between their parents; then each
///     coarsens away from its new part (coarsen_away) and chooses the diagonals by names.
///  3. Finite elements: its own triangles assembled, the unknowns numbered across processes by
///     their names (each owned by the lowest part among its triangles), solved by CG with
///     BoomerAMG; each process receives the values at its own triangles' corners and at its
///     first ghost layer (for the estimators' jumps and recovered gradients).
///  4. Marking against thresholds found together (adapt::mark_shared), refinement of its own
///     triangles, and the splits that reach other processes' parts handed over until none
///     does (a fixpoint, as reconcile_splits).
///  5. Coarsening (AdaptOptions::coarsen_below, the moving peak), before the refinement, in
///     rounds: each process removes the removable candidates among its own triangles'
///     corners (a vertex on an interface is one only if every process around it says so),
///     then the ghost layers are made exact again as in step 2, until no process removes
///     anything. A removal never makes another candidate unremovable, so the rounds end with
///     the mesh one process reaches in any order. Runs that coarsen take the floor's cells
///     as units, undivided (a coarsened triangle must stay inside one unit): their balance
///     is as fine as the floor (--min-level).
/// The meshes, unknowns and estimates are those of one process (tests/test_cli_mpi.cpp).

#include "rgbmesh/adapt/adaptive.hpp"

namespace rgbmesh::parallel {

/// Whether a run with these options can hold its mesh distributed: run_cycles or run_dynamic,
/// adaptive or uniform, with or without coarsening, not resumable (the views' states are
/// pieces). Otherwise distribute() runs it with the mesh whole on every process.
bool mesh_can_be_distributed(const adapt::AdaptOptions& options);

/// Sets the options for adapt::run_cycles on all processes of the MPI run (call initialize
/// first) with the mesh distributed: every process then passes the same mesh, problem and
/// options to run_cycles; the mesh it gets back is its view (its last part and ghost layers).
/// Throws std::invalid_argument where mesh_can_be_distributed does not hold. On one process
/// (or without MPI) the options are left as they are.
void distribute_mesh(adapt::AdaptOptions& options);

}  // namespace rgbmesh::parallel
