// Fitting a Loop surface to 100,000 points with a 1,000-vertex base (goal: under 30 s): the
// targets are the Stanford bunny's limit surface sampled at level 3 (117,696 points), the base
// is the bunny decimated to 2,000 triangles (about 1,000 vertices).
//
//   build/bin/bench_fit        (scripts/run-bench.sh runs it too)

#include <benchmark/benchmark.h>

#include "rgbmesh/fit/fit.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace {

using namespace rgbmesh;

void BM_FitBunny(benchmark::State& state) {
  const TriangleMeshData bunny = read_mesh(std::string(RGBMESH_DATA_DIR) + "/bunny.obj");
  const std::vector<Vec3> targets = fit::limit_stencils(bunny, 3).evaluate(bunny.points);
  const TriangleMeshData base = fit::decimate(bunny, 2000);
  fit::FitResult r;
  for (auto _ : state) r = fit::fit(base, targets, fit::FitOptions{});
  state.counters["targets"] = static_cast<double>(targets.size());
  state.counters["base_vertices"] = static_cast<double>(base.points.size());
  state.counters["iterations"] = static_cast<double>(r.iterations.size() - 1);
  state.counters["rms_percent"] = 100 * r.rms / r.diagonal;
  state.counters["fit_s"] = r.seconds;
}
BENCHMARK(BM_FitBunny)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
