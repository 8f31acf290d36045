// Refinement and coarsening throughput of the RGB mesh, and OpenSubdiv's uniform Loop
// refinement of the same base mesh in the same process (the reference for ratios).
//
//   build/bin/bench_refinement        (or scripts/run-bench.sh, which adds memory figures)

#include <benchmark/benchmark.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/soup.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace {

using namespace rgbmesh;

// A torus with 2 * rings * sides triangles (10,000 by default): every vertex regular.
struct Base {
  std::vector<Vec3> points;
  std::vector<std::array<std::int32_t, 3>> triangles;
  SharpFeatures sharp{};
};

const Base& torus_10k() {
  static const Base base = [] {
    Base b;
    const int rings = 100, sides = 50;
    const double pi = 3.14159265358979323846;
    for (int i = 0; i < rings; ++i)
      for (int j = 0; j < sides; ++j) {
        const double u = 2 * pi * i / rings, v = 2 * pi * j / sides;
        b.points.push_back({(3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v)});
      }
    auto id = [&](int i, int j) { return ((i + rings) % rings) * sides + (j + sides) % sides; };
    for (int i = 0; i < rings; ++i)
      for (int j = 0; j < sides; ++j) {
        b.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        b.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    return b;
  }();
  return base;
}

// A scan: the Stanford bunny (data/bunny.obj, 3,678 triangles) refined uniformly to level 2
// and taken as a new base of 58,784 triangles, with the scan's irregular valences (about the
// 52,000-triangle scan of issue 24's speed target).
const Base& scan_58k() {
  static const Base base = [] {
    const TriangleMeshData bunny = read_mesh(std::filesystem::path(RGBMESH_DATA_DIR) / "bunny.obj");
    RgbMesh scan = RgbMesh::from_triangles(bunny.points, bunny.triangles);
    selective_refinement(scan, UniformLevel(2));
    const MeshSnapshot s = scan.snapshot();
    return Base{s.points, s.triangles};
  }();
  return base;
}

// The torus with sharp features (issue 42): every fifth ring of edges around the tube an
// infinitely sharp crease, every fifth ring between them a semi-sharp one (sharpness 2.5), and
// every tenth meridian's edges infinitely sharp, crossing the rings at corners: a fifth of the
// vertices on creases, darts where semi-sharp rings meet the meridians.
const Base& torus_10k_sharp() {
  static const Base base = [] {
    Base b = torus_10k();
    const int rings = 100, sides = 50;
    auto id = [&](int i, int j) { return ((i + rings) % rings) * sides + (j + sides) % sides; };
    for (int i = 0; i < rings; ++i)
      for (int j = 0; j < sides; ++j) {
        if (i % 5 == 0) b.sharp.edges.push_back({id(i, j), id(i, j + 1), kInfiniteSharpness});
        if (i % 5 == 2) b.sharp.edges.push_back({id(i, j), id(i, j + 1), 2.5f});
        if (j % 10 == 0) b.sharp.edges.push_back({id(i, j), id(i + 1, j), kInfiniteSharpness});
      }
    return b;
  }();
  return base;
}

RgbMesh base_mesh(const Base& b = torus_10k()) { return RgbMesh::from_triangles(b.points, b.triangles, b.sharp); }

// RGB subdivision to uniform level `level` (topology and Loop control points); returns the
// vertices inserted.
std::uint64_t rgb_uniform(int level, const Base& b = torus_10k()) {
  RgbMesh m = base_mesh(b);
  const std::uint64_t splits = selective_refinement(m, UniformLevel(level)).splits;
  benchmark::DoNotOptimize(m.num_triangles());
  return splits;
}

struct Point {
  double p[3];
  void Clear() { p[0] = p[1] = p[2] = 0; }
  void AddWithWeight(const Point& o, double w) {
    for (int i = 0; i < 3; ++i) p[i] += w * o.p[i];
  }
};

// OpenSubdiv to uniform level `level`: topology refinement plus Loop interpolation of the
// positions, level by level (what RGB subdivision computes too); returns the vertices added.
std::uint64_t opensubdiv_uniform(int level, const Base& b = torus_10k()) {
  using namespace OpenSubdiv;
  std::vector<int> counts(b.triangles.size(), 3), indices;
  for (const auto& t : b.triangles) indices.insert(indices.end(), t.begin(), t.end());
  Sdc::Options options;
  options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(b.points.size());
  desc.numFaces = static_cast<int>(b.triangles.size());
  desc.numVertsPerFace = counts.data();
  desc.vertIndicesPerFace = indices.data();
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(desc, Factory::Options(Sdc::SCHEME_LOOP, options)));
  refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(level));
  std::vector<Point> src, dst;
  for (const auto& p : b.points) src.push_back({{p.x, p.y, p.z}});
  Far::PrimvarRefinerReal<double> primvar(*refiner);
  for (int k = 1; k <= level; ++k) {
    dst.resize(static_cast<std::size_t>(refiner->GetLevel(k).GetNumVertices()));
    primvar.Interpolate(k, src, dst);
    src.swap(dst);
  }
  benchmark::DoNotOptimize(src.data());
  return src.size() - b.points.size();
}

void BM_UniformRgb(benchmark::State& state) {
  std::uint64_t splits = 0;
  for (auto _ : state) splits += rgb_uniform(static_cast<int>(state.range(0)));
  state.counters["insertions/s"] = benchmark::Counter(static_cast<double>(splits), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_UniformRgb)->Arg(3)->Arg(4)->Arg(5)->Unit(benchmark::kMillisecond);

void BM_UniformOpenSubdiv(benchmark::State& state) {
  std::uint64_t vertices = 0;
  for (auto _ : state) vertices += opensubdiv_uniform(static_cast<int>(state.range(0)));
  state.counters["insertions/s"] = benchmark::Counter(static_cast<double>(vertices), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_UniformOpenSubdiv)->Arg(3)->Arg(4)->Arg(5)->Unit(benchmark::kMillisecond);

// Both, alternately in each iteration, so that the machine's state affects them alike:
// `ratio` = RGB time / OpenSubdiv time (the goal is at most 1).
void ratio_to_opensubdiv(benchmark::State& state, const Base& base) {
  const int level = static_cast<int>(state.range(0));
  double rgb = 0, osd = 0;
  for (auto _ : state) {
    auto t0 = std::chrono::steady_clock::now();
    rgb_uniform(level, base);
    auto t1 = std::chrono::steady_clock::now();
    opensubdiv_uniform(level, base);
    auto t2 = std::chrono::steady_clock::now();
    rgb += std::chrono::duration<double>(t1 - t0).count();
    osd += std::chrono::duration<double>(t2 - t1).count();
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["rgb_ms"] = 1e3 * rgb / n;
  state.counters["opensubdiv_ms"] = 1e3 * osd / n;
  state.counters["ratio"] = rgb / osd;
}
void BM_RatioToOpenSubdiv(benchmark::State& state) { ratio_to_opensubdiv(state, torus_10k()); }
BENCHMARK(BM_RatioToOpenSubdiv)->Arg(3)->Arg(4)->Arg(5)->Unit(benchmark::kMillisecond);

// The scan of 58,784 triangles to level 3 (3.76 M triangles).
void BM_RatioToOpenSubdivScan(benchmark::State& state) { ratio_to_opensubdiv(state, scan_58k()); }
BENCHMARK(BM_RatioToOpenSubdivScan)->Arg(3)->Unit(benchmark::kMillisecond);

// Any mesh file (RGBMESH_BENCH_MESH, e.g. CGAL's data/meshes/armadillo.off), to level 3: the
// speed targets that name a model of their own.
void BM_RatioToOpenSubdivFile(benchmark::State& state) {
  const char* file = std::getenv("RGBMESH_BENCH_MESH");
  if (file == nullptr) {
    state.SkipWithError("set RGBMESH_BENCH_MESH to a mesh file");
    return;
  }
  static const Base base = [file] {
    const TriangleMeshData mesh = read_mesh(file);
    return Base{mesh.points, mesh.triangles};
  }();
  ratio_to_opensubdiv(state, base);
  state.counters["base_triangles"] = static_cast<double>(base.triangles.size());
}
BENCHMARK(BM_RatioToOpenSubdivFile)->Arg(3)->Unit(benchmark::kMillisecond);

// Sharp features against none, alternately in each iteration on the same torus: `ratio` = time
// per insertion with sharp features / without (the goal: at most 1.2), and the bytes per vertex
// of both meshes' arrays (RgbMesh::memory_bytes; the goal: at most 8 more with sharp features).
// Uniform levels (split_all_edges) and selective refinement (a ball to level 7 and a budget of
// 200,000 triangles: the RGB queues, one split at a time).
template <class Refine>
void sharp_over_smooth(benchmark::State& state, Refine refine) {
  double smooth = 0, sharp = 0, smooth_bytes = 0, sharp_bytes = 0;
  std::uint64_t smooth_splits = 0, sharp_splits = 0;
  for (auto _ : state) {
    for (const Base* b : {&torus_10k(), &torus_10k_sharp()}) {
      RgbMesh m = base_mesh(*b);
      const auto t0 = std::chrono::steady_clock::now();
      const std::uint64_t splits = refine(m);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double bytes = static_cast<double>(m.memory_bytes()) / static_cast<double>(m.num_vertices());
      if (b == &torus_10k()) {
        smooth += seconds, smooth_splits += splits, smooth_bytes = bytes;
      } else {
        sharp += seconds, sharp_splits += splits, sharp_bytes = bytes;
      }
    }
  }
  state.counters["smooth_ns_per_insertion"] = 1e9 * smooth / static_cast<double>(smooth_splits);
  state.counters["sharp_ns_per_insertion"] = 1e9 * sharp / static_cast<double>(sharp_splits);
  state.counters["ratio"] = (sharp / static_cast<double>(sharp_splits)) / (smooth / static_cast<double>(smooth_splits));
  state.counters["smooth_bytes_per_vertex"] = smooth_bytes;
  state.counters["sharp_bytes_per_vertex"] = sharp_bytes;
}
void BM_SharpOverSmoothUniform(benchmark::State& state) {
  const int level = static_cast<int>(state.range(0));
  sharp_over_smooth(state, [level](RgbMesh& m) { return selective_refinement(m, UniformLevel(level)).splits; });
}
BENCHMARK(BM_SharpOverSmoothUniform)->Arg(3)->Arg(4)->Unit(benchmark::kMillisecond);
void BM_SharpOverSmoothBall(benchmark::State& state) {
  sharp_over_smooth(state, [](RgbMesh& m) { return selective_refinement(m, BallLevel({4, 0, 0}, 0.5, 7)).splits; });
}
BENCHMARK(BM_SharpOverSmoothBall)->Unit(benchmark::kMillisecond);
void BM_SharpOverSmoothBudget(benchmark::State& state) {
  sharp_over_smooth(state, [](RgbMesh& m) { return selective_refinement(m, TriangleBudget(200000)).splits; });
}
BENCHMARK(BM_SharpOverSmoothBudget)->Unit(benchmark::kMillisecond);

// Removing every inserted vertex of a uniform level-L mesh (setup excluded from the time).
void BM_CoarsenAll(benchmark::State& state) {
  const int level = static_cast<int>(state.range(0));
  RgbMesh refined = base_mesh();
  selective_refinement(refined, UniformLevel(level));
  std::uint64_t removals = 0;
  for (auto _ : state) {
    state.PauseTiming();
    RgbMesh m = refined;
    state.ResumeTiming();
    removals += selective_refinement(m, CoarsenAll()).removals;
  }
  state.counters["removals/s"] =
      benchmark::Counter(static_cast<double>(removals), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_CoarsenAll)->Arg(3)->Arg(4)->Unit(benchmark::kMillisecond);

// The limit positions of every vertex of a uniform level-L mesh (what the first VTK XML write
// of a mesh computes), against refining to that level in the same iteration: `ratio` =
// compute_limits time / refinement time.
void BM_ComputeLimits(benchmark::State& state) {
  const int level = static_cast<int>(state.range(0));
  double limits = 0, refine = 0;
  std::size_t vertices = 0;
  for (auto _ : state) {
    auto t0 = std::chrono::steady_clock::now();
    RgbMesh m = base_mesh();
    selective_refinement(m, UniformLevel(level));
    auto t1 = std::chrono::steady_clock::now();
    m.compute_limits();
    auto t2 = std::chrono::steady_clock::now();
    refine += std::chrono::duration<double>(t1 - t0).count();
    limits += std::chrono::duration<double>(t2 - t1).count();
    vertices = m.num_vertices();
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["limits_ms"] = 1e3 * limits / n;
  state.counters["ns_per_vertex"] = 1e9 * limits / n / static_cast<double>(vertices);
  state.counters["ratio"] = limits / refine;
}
BENCHMARK(BM_ComputeLimits)->Arg(3)->Arg(4)->Unit(benchmark::kMillisecond);

// Selective refinement: a ball to level 7 on one side of the torus.
void BM_BallRefinement(benchmark::State& state) {
  std::uint64_t splits = 0;
  for (auto _ : state) {
    RgbMesh m = base_mesh();
    splits += selective_refinement(m, BallLevel({4, 0, 0}, 0.5, 7)).splits;
  }
  state.counters["insertions/s"] =
      benchmark::Counter(static_cast<double>(splits), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_BallRefinement)->Unit(benchmark::kMillisecond);

// Longest edges first up to a budget of 200,000 triangles.
void BM_BudgetRefinement(benchmark::State& state) {
  std::uint64_t splits = 0;
  for (auto _ : state) {
    RgbMesh m = base_mesh();
    splits += selective_refinement(m, TriangleBudget(200000)).splits;
  }
  state.counters["insertions/s"] =
      benchmark::Counter(static_cast<double>(splits), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_BudgetRefinement)->Unit(benchmark::kMillisecond);

}  // namespace

// Reading a mesh: prepare_triangle_mesh's checks and orientation, then RgbMesh::from_triangles
// (the same checks again, and the half-edge pairing), on a planar grid of 2 * n * n/2
// triangles, a third of them flipped. Both should grow as n log n: the fitted complexity and the
// time per triangle at 10^5 and 10^6 triangles show it.
PolygonSoup flipped_grid(int w) {
  const int h = w / 2;
  PolygonSoup s;
  for (int j = 0; j <= h; ++j)
    for (int i = 0; i <= w; ++i) s.points.push_back({double(i), double(j), 0.0});
  auto id = [&](int i, int j) { return std::int64_t(j) * (w + 1) + i; };
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      s.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  for (std::size_t t = 1; t < s.faces.size(); t += 3) std::swap(s.faces[t][1], s.faces[t][2]);
  return s;
}

void BM_PrepareTriangleMesh(benchmark::State& state) {
  const PolygonSoup soup = flipped_grid(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(prepare_triangle_mesh(soup).triangles.size());
  state.SetComplexityN(static_cast<benchmark::IterationCount>(soup.faces.size()));
  state.counters["ns_per_triangle"] = benchmark::Counter(
      static_cast<double>(soup.faces.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_PrepareTriangleMesh)->Arg(316)->Arg(1000)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oNLogN);

void BM_FromTriangles(benchmark::State& state) {
  const TriangleMeshData data = prepare_triangle_mesh(flipped_grid(static_cast<int>(state.range(0))));
  for (auto _ : state) benchmark::DoNotOptimize(RgbMesh::from_triangles(data.points, data.triangles).num_triangles());
  state.SetComplexityN(static_cast<benchmark::IterationCount>(data.triangles.size()));
  state.counters["ns_per_triangle"] = benchmark::Counter(
      static_cast<double>(data.triangles.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_FromTriangles)->Arg(316)->Arg(1000)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oNLogN);

BENCHMARK_MAIN();
