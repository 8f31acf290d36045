// The cost of --repair against reading alone, in the same process: `ratio` = (reading with
// repair) / reading, the goal of issue 43 being at most 2. Reading is read_polygon_soup and
// prepare_triangle_mesh's checks; reading with repair is what `rgbmesh info --repair FILE` does
// before its statistics. A file that needs repair is refused at its first defect, so its reading
// is measured on a twin without the defects (the torus's) or, for a file of your own, up to the
// refusal (then the ratio is larger than the cost of repair).
//
//   build/bin/bench_repair                                   a torus of 371,520 triangles, as STL
//   RGBMESH_BENCH_MESH=part.stl build/bin/bench_repair       any mesh file
//
// The torus is written as a binary STL (every triangle with its own corners, in single
// precision: what CAD tools and slicers export), once as it is and once with defects that
// repair must mend in a few places (repeated, reversed and back-to-back triangles, a vertex
// where two parts touch).

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "rgbmesh/repair/repair.hpp"
#include "rgbmesh/soup.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace {

using namespace rgbmesh;
using Triangle = std::array<Vec3, 3>;

// A torus of 2 * 430 * 432 = 371,520 triangles.
std::vector<Triangle> torus() {
  const int rings = 430, sides = 432;
  const double pi = 3.14159265358979323846;
  const auto at = [&](int i, int j) {
    const double u = 2 * pi * i / rings, v = 2 * pi * j / sides;
    return Vec3{(3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v)};
  };
  std::vector<Triangle> out;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      out.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      out.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return out;
}

// Every 10,000th triangle repeated, every 10,000th (offset by 5,000) reversed, one triangle
// given a back-to-back twin, and a small tetrahedron touching the torus at one of its vertices.
std::vector<Triangle> with_defects(std::vector<Triangle> t) {
  const std::size_t n = t.size();
  for (std::size_t i = 0; i < n; i += 10000) t.push_back(t[i]);
  for (std::size_t i = 5000; i < n; i += 10000) std::swap(t[i][1], t[i][2]);
  t.push_back({t[77][0], t[77][2], t[77][1]});
  const Vec3 apex = t[123][0], d{0, 0, 0.01};
  const Vec3 a = apex + Vec3{0.01, 0, 0.01}, b = apex + Vec3{0, 0.01, 0.01}, c = apex + d * 2.0;
  for (const Triangle& f :
       {Triangle{apex, a, b}, Triangle{apex, b, c}, Triangle{apex, c, a}, Triangle{a, c, b}})
    t.push_back(f);
  return t;
}

void write_stl(const std::filesystem::path& path, const std::vector<Triangle>& triangles) {
  std::ofstream out(path, std::ios::binary);
  char header[80] = "rgbmesh bench_repair";
  out.write(header, sizeof header);
  const auto count = static_cast<std::uint32_t>(triangles.size());
  out.write(reinterpret_cast<const char*>(&count), 4);
  for (const Triangle& t : triangles) {
    float record[12] = {};
    for (int k = 0; k < 3; ++k) {
      record[3 + 3 * k] = static_cast<float>(t[k].x);
      record[4 + 3 * k] = static_cast<float>(t[k].y);
      record[5 + 3 * k] = static_cast<float>(t[k].z);
    }
    out.write(reinterpret_cast<const char*>(record), sizeof record);
    const std::uint16_t attributes = 0;
    out.write(reinterpret_cast<const char*>(&attributes), 2);
  }
}

// The two torus files, in a folder of their own that goes when the benchmark ends.
struct TorusFiles {
  std::filesystem::path folder, clean, broken;
  TorusFiles() {
    folder = std::filesystem::temp_directory_path() / ("rgbmesh_bench_repair_" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder);
    clean = folder / "torus.stl";
    broken = folder / "torus_defects.stl";
    write_stl(clean, torus());
    write_stl(broken, with_defects(torus()));
  }
  ~TorusFiles() {
    std::error_code ignored;
    std::filesystem::remove_all(folder, ignored);
  }
};

const std::filesystem::path& torus_file(bool defects) {
  static const TorusFiles files;
  return defects ? files.broken : files.clean;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void ratio_to_reading(benchmark::State& state, const std::filesystem::path& file,
                      const std::filesystem::path& reference) {
  double reading = 0, repairing = 0;
  std::size_t triangles = 0;
  std::string note;
  // One untimed round first: the allocator's first large blocks are fresh pages from the kernel
  // (glibc maps them, then raises its threshold and reuses its heap), which would weigh on
  // whichever benchmark runs first.
  try {
    benchmark::DoNotOptimize(prepare_triangle_mesh(read_polygon_soup(reference)));
  } catch (const InputError&) {
  }
  benchmark::DoNotOptimize(read_mesh(file, repair::soup_options(false, true)));
  for (auto _ : state) {
    auto t0 = std::chrono::steady_clock::now();
    try {
      benchmark::DoNotOptimize(prepare_triangle_mesh(read_polygon_soup(reference)));
    } catch (const InputError&) {
      // a file that needs repair is refused: reading is what it took to find out
    }
    reading += seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    const TriangleMeshData repaired = read_mesh(file, repair::soup_options(false, true));
    repairing += seconds_since(t0);
    triangles = repaired.triangles.size();
    note = repaired.notes.empty() ? "" : repaired.notes.front();
  }
  state.counters["ratio"] = repairing / reading;
  state.counters["read_s"] = reading / static_cast<double>(state.iterations());
  state.counters["with_repair_s"] = repairing / static_cast<double>(state.iterations());
  state.counters["triangles"] = static_cast<double>(triangles);
  state.SetLabel(note.substr(0, 120));
}

void BM_RepairOverReadingTorus(benchmark::State& state) {
  ratio_to_reading(state, torus_file(false), torus_file(false));
}
BENCHMARK(BM_RepairOverReadingTorus)->Unit(benchmark::kMillisecond)->Iterations(5);

void BM_RepairOverReadingTorusWithDefects(benchmark::State& state) {
  ratio_to_reading(state, torus_file(true), torus_file(false));
}
BENCHMARK(BM_RepairOverReadingTorusWithDefects)->Unit(benchmark::kMillisecond)->Iterations(5);

void BM_RepairOverReadingFile(benchmark::State& state) {
  const char* file = std::getenv("RGBMESH_BENCH_MESH");
  if (file == nullptr) {
    state.SkipWithError("set RGBMESH_BENCH_MESH to a mesh file");
    return;
  }
  ratio_to_reading(state, file, file);
}
BENCHMARK(BM_RepairOverReadingFile)->Unit(benchmark::kMillisecond)->Iterations(5);

}  // namespace

BENCHMARK_MAIN();
