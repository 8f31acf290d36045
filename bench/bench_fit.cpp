// Fitting a Loop surface to scanned points (goal: a 100,000-point fit under 30 s; a 30,000-point
// cloud, base included, in seconds to tens of seconds).
//
// BM_FitBunny: the targets are the Stanford bunny's limit surface sampled at level 3 (117,696
// points), the base is the bunny decimated to 2,000 triangles (about 1,000 vertices).
// BM_CloudToFit/L: what `rgbmesh fit --target cloud.xyz` does with its defaults, on the bunny's
// limit surface sampled at level L as a cloud without normals (L = 2: 29,378 points; 3: 117,696):
// normals, Poisson reconstruction and decimation to 1,000 faces, then the fit.
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

void BM_CloudToFit(benchmark::State& state) {
  const TriangleMeshData bunny = read_mesh(std::string(RGBMESH_DATA_DIR) + "/bunny.obj");
  PolygonSoup cloud;
  cloud.points = fit::limit_stencils(bunny, static_cast<int>(state.range(0))).evaluate(bunny.points);
  fit::Base base;
  fit::FitResult r;
  for (auto _ : state) {
    base = fit::make_base(cloud, {}, fit::BaseOptions{});
    r = fit::fit(base.mesh, cloud.points, fit::FitOptions{});
  }
  state.counters["points"] = static_cast<double>(cloud.points.size());
  state.counters["base_faces"] = static_cast<double>(base.mesh.triangles.size());
  state.counters["genus"] = base.topology.genus;
  state.counters["reconstruction_s"] = base.reconstruction_seconds;
  state.counters["decimation_s"] = base.decimation_seconds;
  state.counters["iterations"] = static_cast<double>(r.iterations.size() - 1);
  state.counters["rms_percent"] = 100 * r.rms / r.diagonal;
  state.counters["fit_s"] = r.seconds;
}
BENCHMARK(BM_CloudToFit)->Arg(2)->Arg(3)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
