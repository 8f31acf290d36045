// Restoring a saved RGB state (rgb_state.hpp) against refining to the same mesh, in one
// process: each iteration refines the base mesh and restores the saved state of the result,
// one after the other, so that a noisy machine affects both alike. `ratio` = restore time /
// refinement time; the goal is at most about 2.
//
// The restore gets every expectation a saved .vtp file gives read_rgb_mesh (triangles,
// levels, colours, control points, limit positions), so it includes all of its checks; the
// refinement computes no limit positions.
//
//   build/bin/bench_rgb_state

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <functional>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/rgb_state.hpp"

namespace {

using namespace rgbmesh;

// A torus of 2 * 100 * 50 = 10,000 triangles (5,000 vertices, all regular); uniform level 4
// has 1,280,000 vertices.
RgbMesh torus_10k() {
  const int rings = 100, sides = 50;
  const double pi = 3.14159265358979323846;
  std::vector<Vec3> points;
  std::vector<std::array<std::int32_t, 3>> triangles;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      const double u = 2 * pi * i / rings, v = 2 * pi * j / sides;
      points.push_back({(3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v)});
    }
  auto id = [&](int i, int j) { return ((i + rings) % rings) * sides + (j + sides) % sides; };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return RgbMesh::from_triangles(points, triangles);
}

// What a saved file holds: the state and, as read_rgb_mesh passes them, the expectations.
struct Saved {
  RgbState state;
  RestoreExpectations expected;
  std::size_t vertices = 0;
};

Saved save(RgbMesh& m) {
  m.compute_limits();
  const MeshSnapshot s = m.snapshot(RgbMesh::Points::control, true);
  Saved saved;
  saved.state = save_state(m, s);
  RestoreExpectations& x = saved.expected;
  x.triangles = s.triangles;
  x.vertex_level = s.vertex_level;
  x.triangle_level = s.triangle_level;
  for (const Color c : s.triangle_color) x.triangle_color.push_back(static_cast<std::uint8_t>(c));
  for (VertexHandle v : s.vertex_handle) {
    x.control_points.push_back(m.control_point(v));
    x.limits.push_back(m.limit_position(v));
  }
  saved.vertices = m.num_vertices();
  return saved;
}

// Alternates refine(base) and the restore of its saved result; reports both times and the ratio.
void restore_against_refinement(benchmark::State& state, const std::function<void(RgbMesh&)>& refine) {
  RgbMesh refined = torus_10k();
  refine(refined);
  const Saved saved = save(refined);
  double refine_s = 0, restore_s = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    {
      RgbMesh m = torus_10k();
      refine(m);
      benchmark::DoNotOptimize(m.num_vertices());
    }
    const auto t1 = std::chrono::steady_clock::now();
    {
      const RestoredMesh r = restore_state(saved.state, saved.expected);
      if (r.mesh.num_vertices() != saved.vertices) state.SkipWithError("the restored mesh differs");
    }
    const auto t2 = std::chrono::steady_clock::now();
    refine_s += std::chrono::duration<double>(t1 - t0).count();
    restore_s += std::chrono::duration<double>(t2 - t1).count();
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["vertices"] = static_cast<double>(saved.vertices);
  state.counters["refine_ms"] = 1e3 * refine_s / n;
  state.counters["restore_ms"] = 1e3 * restore_s / n;
  state.counters["ratio"] = restore_s / refine_s;
}

// Uniform refinement of the torus to level 4 (1.28 million vertices), saved and restored.
void BM_RestoreUniform(benchmark::State& state) {
  const int level = static_cast<int>(state.range(0));
  restore_against_refinement(state, [level](RgbMesh& m) { selective_refinement(m, UniformLevel(level)); });
}
BENCHMARK(BM_RestoreUniform)->Arg(4)->Unit(benchmark::kMillisecond)->Iterations(3);

// An adaptive mesh: a ball to level 7 on one side of the torus (forced splits, every
// colour, trapezoid diagonals to choose).
void BM_RestoreBall(benchmark::State& state) {
  restore_against_refinement(state, [](RgbMesh& m) { selective_refinement(m, BallLevel({4, 0, 0}, 0.5, 7)); });
}
BENCHMARK(BM_RestoreBall)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
