// The partition of a run on several processes (rgbmesh::parallel), against what it serves: each
// iteration builds the finite-element mesh of a uniform icosahedron level (the limit positions:
// the "mesh" share of an adaptive cycle) and then partitions its triangles for 4 processes above
// the floor (units and METIS: the "partition" share), one after the other so that a noisy
// machine affects both alike. `ratio` = partition time / FE-mesh time; `cached`: the floor's
// uniform mesh kept between calls, as a run keeps it from cycle to cycle (FloorCache).
//
//   build/bin/bench_partition

#include <benchmark/benchmark.h>

#include <chrono>
#include <memory>

#include "rgbmesh/fem/surface_mesh.hpp"
#include "rgbmesh/parallel/partition.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"

namespace {

using namespace rgbmesh;

void Partition(benchmark::State& state) {
  const int level = static_cast<int>(state.range(0));
  const TriangleMeshData ico = icosahedron();
  RgbMesh mesh = RgbMesh::from_triangles(ico.points, ico.triangles);
  selective_refinement(mesh, UniformLevel(level));
  double fe_seconds = 0, partition_seconds = 0;
  // As in a run: the floor's uniform mesh kept from call to call (state.range(1) = 1).
  const std::shared_ptr<parallel::FloorCache> cache = state.range(1) ? parallel::make_floor_cache() : nullptr;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const fem::SurfaceMesh fe = fem::build_surface_mesh(mesh);
    const auto t1 = std::chrono::steady_clock::now();
    const std::vector<std::int32_t> parts = parallel::triangle_parts(mesh, fe, 0, 4, cache.get());
    const auto t2 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(parts.data());
    fe_seconds += std::chrono::duration<double>(t1 - t0).count();
    partition_seconds += std::chrono::duration<double>(t2 - t1).count();
  }
  state.counters["triangles"] = static_cast<double>(mesh.num_triangles());
  state.counters["partition_s"] = partition_seconds / static_cast<double>(state.iterations());
  state.counters["fe_mesh_s"] = fe_seconds / static_cast<double>(state.iterations());
  state.counters["ratio"] = partition_seconds / fe_seconds;
}
BENCHMARK(Partition)
    ->ArgsProduct({{5, 6, 7}, {0, 1}})
    ->ArgNames({"level", "cached"})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(1.0);

}  // namespace

BENCHMARK_MAIN();
