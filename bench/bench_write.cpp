// Writing a large mesh: wall time and peak memory of each output format, measured in one
// process so that the ratios to the PLY write hold on a noisy, shared machine.
//
// The mesh: the Stanford bunny (data/bunny.obj, a scan of 3,678 triangles) refined uniformly to
// level 2 and taken as a new base of 58,784 triangles (about the 52,000-triangle scan of
// issue 11), then refined uniformly to LEVEL (default 3: 1.88 million vertices, 3.76 million
// triangles).
//
// Each write is what the command-line tool does: snapshot_for_file, then write_mesh, into a
// temporary folder. Reported per output: the median seconds over the repeats (snapshot and
// write, and the snapshot alone), the ratio to the PLY write's median, the file size, and
// memory in bytes per vertex: the process's peak resident memory during the write (VmHWM,
// reset before each write through /proc/self/clear_refs), the write's own share of it (that
// peak minus the resident memory before the write: the snapshot, VTK's arrays and buffers),
// and the snapshot's share alone.
//
//   build/bin/bench_write [LEVEL [REPEATS]]       (scripts/run-bench.sh runs it)

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <unistd.h>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace {

namespace fs = std::filesystem;
using namespace rgbmesh;

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A field of /proc/self/status in bytes ("VmRSS", "VmHWM"); 0 if unknown.
double status_bytes(const std::string& field) {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind(field + ":", 0) == 0) return 1024.0 * std::atof(line.c_str() + field.size() + 1);
  return 0;
}

// Makes VmHWM start again from the current resident size (Linux 4.0 and later).
bool reset_peak() {
  std::ofstream out("/proc/self/clear_refs");
  out << "5";
  out.flush();
  return static_cast<bool>(out);
}

using Writer = std::function<void(const fs::path&, const MeshSnapshot&)>;

struct Output {
  Output(std::string label_, std::string extension_, Writer write_)
      : label(std::move(label_)), extension(std::move(extension_)), write(std::move(write_)) {}
  std::string label;
  std::string extension;
  Writer write;
  std::vector<double> seconds, snapshot_seconds;
  double peak_per_vertex = 0, own_per_vertex = 0, snapshot_per_vertex = 0;
  std::uintmax_t bytes = 0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 1 << 20);  // as the command-line tool does
#endif
  const int level = argc > 1 ? std::atoi(argv[1]) : 3;
  const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 3;
  if (level < 0 || level > 6) {
    std::fprintf(stderr, "usage: bench_write [LEVEL (0..6) [REPEATS]]\n");
    return 2;
  }

  const auto t0 = Clock::now();
  RgbMesh mesh = [] {
    const TriangleMeshData bunny = read_mesh(fs::path(RGBMESH_DATA_DIR) / "bunny.obj");
    RgbMesh scan = RgbMesh::from_triangles(bunny.points, bunny.triangles);
    selective_refinement(scan, UniformLevel(2));
    const MeshSnapshot s = scan.snapshot();
    return RgbMesh::from_triangles(s.points, s.triangles);
  }();
  const std::size_t base_triangles = mesh.num_triangles();
  selective_refinement(mesh, UniformLevel(level));
  const double refine_seconds = seconds_since(t0);
  const double vertices = static_cast<double>(mesh.num_vertices());
  std::printf("base: the bunny at level 2, %zu triangles; refined to level %d: %zu vertices, %zu triangles (%.1f s)\n",
              base_triangles, level, mesh.num_vertices(), mesh.num_triangles(), refine_seconds);
  std::printf("resident memory: peak so far %.0f bytes per vertex, now %.0f\n", status_bytes("VmHWM") / vertices,
              status_bytes("VmRSS") / vertices);

  const auto with = [](Compression c) {
    return [c](const fs::path& p, const MeshSnapshot& s) {
      WriteOptions options;
      options.compression = c;
      write_mesh(p, s, options);
    };
  };
  const Writer plain = [](const fs::path& p, const MeshSnapshot& s) { write_mesh(p, s); };
  std::vector<Output> outputs;
  outputs.emplace_back("ply", ".ply", plain);
  outputs.emplace_back("vtp", ".vtp", plain);  // the default compression
  outputs.emplace_back("vtp lz4", ".vtp", with(Compression::lz4));
  outputs.emplace_back("vtp zlib", ".vtp", with(Compression::zlib));
  outputs.emplace_back("vtp none", ".vtp", with(Compression::none));
  outputs.emplace_back("vtu", ".vtu", plain);
  outputs.emplace_back("obj", ".obj", plain);
  outputs.emplace_back("off", ".off", plain);
  outputs.emplace_back("stl", ".stl", plain);

  const fs::path dir = fs::temp_directory_path() / ("rgbmesh-bench-write-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const bool peaks = reset_peak();
  for (int r = 0; r < repeats; ++r) {
    for (std::size_t i = 0; i < outputs.size(); ++i) {
      Output& o = outputs[i];
      const fs::path file = dir / ("mesh" + std::to_string(i) + o.extension);
      const double before = status_bytes("VmRSS");
      reset_peak();
      const auto start = Clock::now();
      {
        const MeshSnapshot snapshot = snapshot_for_file(mesh, file);
        o.snapshot_seconds.push_back(seconds_since(start));
        o.snapshot_per_vertex = std::max(o.snapshot_per_vertex, (status_bytes("VmRSS") - before) / vertices);
        o.write(file, snapshot);
      }
      o.seconds.push_back(seconds_since(start));
      const double peak = status_bytes("VmHWM");
      o.peak_per_vertex = std::max(o.peak_per_vertex, peak / vertices);
      o.own_per_vertex = std::max(o.own_per_vertex, (peak - before) / vertices);
      o.bytes = fs::file_size(file);
      fs::remove(file);
    }
  }
  fs::remove_all(dir);

  const double ply = median(outputs.front().seconds);
  std::printf("\n%-9s %8s %7s %9s %8s %7s %7s %9s\n", "output", "seconds", "vs ply", "snapshot", "MB", "peak", "write",
              "snapshot");
  for (const Output& o : outputs) {
    const double s = median(o.seconds);
    std::printf("%-9s %8.2f %7.2f %9.2f %8.1f", o.label.c_str(), s, s / ply, median(o.snapshot_seconds),
                static_cast<double>(o.bytes) / 1e6);
    if (peaks)
      std::printf(" %7.0f %7.0f %9.0f\n", o.peak_per_vertex, o.own_per_vertex, o.snapshot_per_vertex);
    else
      std::printf(" %7s %7s %9.0f\n", "?", "?", o.snapshot_per_vertex);
  }
  std::printf(
      "seconds: snapshot_for_file and write_mesh, the median of %d runs, and its ratio to PLY's; snapshot: the\n"
      "seconds of snapshot_for_file alone. Bytes per vertex: peak, the process's resident peak during the write;\n"
      "write, its rise over the resident size before; snapshot, the resident size the snapshot adds.\n",
      repeats);
  return 0;
}
