// A distributed refinement over MPI, run by CTest under mpirun on four processes: each process
// holds the local view of its part of an adaptive mesh (one ghost layer), refines it with the
// marks it sees, and parallel::reconcile_splits hands splits between the processes until none
// changes. Inside its part every view must then hold the whole mesh refined (which each
// process here also computes, to compare with): its vertices at bit for bit its points and,
// the trapezoids' diagonals chosen by names (canonical.hpp), exactly its triangles, whether the
// process saw only its own triangles' marks or its ghost triangles' too. Exit 0 when all hold.

#include <mpi.h>

#include <cstdio>
#include <string>

#include "local_views_common.hpp"
#include "rgbmesh/parallel/mpi.hpp"

int main(int argc, char** argv) {
  namespace par = rgbmesh::parallel;
  par::initialize(&argc, &argv);
  const int r = par::rank(), p = par::processes();
  int failures = 0;
  if (p != par::testing::Setup::kParts) {
    std::fprintf(stderr, "run on %d processes (got %d)\n", par::testing::Setup::kParts, p);
    return 1;
  }
  // Marking its own and its ghost triangles, or only its own (which needs the others' splits):
  // the whole mesh refined, exactly.
  par::Reconciled rec;
  for (const bool ghost_marks : {true, false}) {
    par::testing::View view = par::testing::refined_view(r, 1, ghost_marks);
    rec = par::reconcile_splits(view.mesh, view.start, view.fine);
    const std::string problem = view.mesh.validate();
    const par::testing::Compared c = par::testing::compare_inside(view);
    const bool exact = c.missing == 0 && c.extra == 0;
    if (!problem.empty() || c.missing_vertices != 0 || c.moved != 0.0 || c.inside == 0 || !exact) {
      ++failures;
      std::fprintf(stderr, "process %d, %s marks: %s; %zu triangles inside, %zu vertices and %zu triangles missing, %zu extra, "
                   "points within %.1e\n", r, ghost_marks ? "own and ghost" : "own", problem.empty() ? "valid" : problem.c_str(),
                   c.inside, c.missing_vertices, c.missing, c.extra, c.moved);
    }
  }
  unsigned long long made = rec.made, all_made = 0;
  MPI_Allreduce(&made, &all_made, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  int all = 0;
  MPI_Allreduce(&failures, &all, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  if (r == 0)
    std::printf("%s: %llu splits handed over in %d rounds\n",
                all == 0 ? "distributed refinement: all checks hold" : "distributed refinement: checks failed", all_made,
                rec.rounds);
  return all == 0 ? 0 : 1;
}
