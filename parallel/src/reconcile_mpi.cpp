// rgbmesh::parallel::reconcile_splits with MPI (local_view.hpp).

#include <mpi.h>

#include <map>
#include <vector>

#include "rgbmesh/canonical.hpp"
#include "rgbmesh/parallel/local_view.hpp"
#include "rgbmesh/parallel/mpi.hpp"

namespace rgbmesh::parallel {

Reconciled reconcile_splits(RgbMesh& view, const std::unordered_set<std::int32_t>& start,
                            const std::unordered_set<VertexKey>& fine) {
  Reconciled out;
  const int p = processes();
  if (p <= 1) return out;
  static_assert(sizeof(unsigned long long) == sizeof(VertexKey), "keys travel as unsigned long long");
  for (;;) {
    ++out.rounds;
    // Every process's inserted vertices (key and parents' keys) to all. (Each to all is enough
    // for a few processes; at scale only the neighbours whose regions meet need them.)
    std::vector<unsigned long long> mine;
    for (const auto& [key, parents] : vertex_keys(view, start).parents) {
      mine.push_back(key);
      mine.push_back(parents[0]);
      mine.push_back(parents[1]);
    }
    std::vector<int> counts(static_cast<std::size_t>(p)), offsets(static_cast<std::size_t>(p), 0);
    const int count = static_cast<int>(mine.size());
    MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
    for (int q = 1; q < p; ++q)
      offsets[static_cast<std::size_t>(q)] = offsets[static_cast<std::size_t>(q - 1)] + counts[static_cast<std::size_t>(q - 1)];
    std::vector<unsigned long long> all(static_cast<std::size_t>(offsets.back() + counts.back()));
    MPI_Allgatherv(mine.data(), count, MPI_UNSIGNED_LONG_LONG, all.data(), counts.data(), offsets.data(),
                   MPI_UNSIGNED_LONG_LONG, MPI_COMM_WORLD);
    std::map<VertexKey, std::array<VertexKey, 2>> splits;
    for (std::size_t i = 0; i + 2 < all.size(); i += 3) splits[all[i]] = {all[i + 1], all[i + 2]};
    const std::size_t made = make_splits(view, start, fine, splits);
    out.made += made;
    unsigned long long here = made, everywhere = 0;
    MPI_Allreduce(&here, &everywhere, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    if (everywhere == 0) break;
  }
  canonical_diagonals(view);  // the diagonals by names, as the whole mesh's (canonical.hpp)
  return out;
}

}  // namespace rgbmesh::parallel
