#pragma once
/// \file
/// The adaptive loop on every process of an MPI run, set up in one call.

#include "rgbmesh/adapt/adaptive.hpp"

namespace rgbmesh::parallel {

/// Makes adapt::run_cycles and adapt::run_dynamic with these options run on all processes of
/// the MPI run (call initialize first; every process then calls run_cycles with the same mesh,
/// problem and options). Each cycle the triangles above the floor options.min_level are divided
/// among the processes (units and METIS: triangle_parts, SolvedMesh::triangle_part); each
/// process assembles and estimates its own triangles, the systems are solved by CG with
/// BoomerAMG on all processes (shared_amg), every process receives the others' indicators and
/// adapts the same mesh; the reports count the bytes sent (CycleReport::bytes_sent). The
/// results are those of one process: the same meshes, estimates and errors within the solver's
/// tolerance. On one process (or without MPI) the options are left as they are. Every process
/// holds the whole mesh, so each cycle's state can be saved whole (AdaptOptions::resumable);
/// distribute_mesh (distributed_mesh.hpp) divides the mesh itself too, coarsening included.
void distribute(adapt::AdaptOptions& options);

}  // namespace rgbmesh::parallel
