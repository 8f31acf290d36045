// Writing a large mesh: wall time and peak memory of each output format, measured in one
// process so that the ratios to the PLY write hold on a noisy, shared machine.
//
// The mesh: the Stanford bunny (data/bunny.obj, a scan of 3,678 triangles) refined uniformly to
// level 2 and taken as a new base of 58,784 triangles (about the 52,000-triangle scan of
// issue 11), then refined uniformly to LEVEL (default 3: 1.88 million vertices, 3.76 million
// triangles).
//
// Each write is what the command-line tool does (write_rgb_mesh: VTK XML files streamed from the
// mesh, the other formats through snapshot_for_file and write_mesh), into a temporary folder;
// the rows "... snapshot" write VTK XML files the library's other way, from a snapshot
// (snapshot_for_file + write_mesh). The first VTK XML write of a mesh also computes its limit
// positions, which PLY does not need: it is measured once first ("vtp cold"); the repeated
// rows are warm. Reported per output: the median seconds over the repeats and the ratio to the
// PLY write's median, the file size, and memory in bytes per vertex: the process's peak
// resident memory during the write (VmHWM, reset before each write through
// /proc/self/clear_refs) and the write's own share of it (that peak minus the resident memory
// before the write).
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
#include "rgbmesh/timing.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace {

namespace fs = std::filesystem;
using namespace rgbmesh;

using Clock = std::chrono::steady_clock;

using rgbmesh::seconds_since;

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

using Writer = std::function<void(const fs::path&, RgbMesh&)>;

struct Output {
  Output(std::string label_, std::string extension_, Writer write_)
      : label(std::move(label_)), extension(std::move(extension_)), write(std::move(write_)) {}
  std::string label;
  std::string extension;
  Writer write;
  std::vector<double> seconds;
  double peak_per_vertex = 0, own_per_vertex = 0;
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

  const auto tool = [](Compression c) {
    return [c](const fs::path& p, RgbMesh& m) {
      WriteOptions options;
      options.compression = c;
      write_rgb_mesh(p, m, options);
    };
  };
  const Writer from_snapshot = [](const fs::path& p, RgbMesh& m) { write_mesh(p, snapshot_for_file(m, p)); };
  std::vector<Output> outputs;
  outputs.emplace_back("ply", ".ply", tool(Compression::lz4));
  outputs.emplace_back("vtp", ".vtp", tool(Compression::lz4));  // the default compression
  outputs.emplace_back("vtp zlib", ".vtp", tool(Compression::zlib));
  outputs.emplace_back("vtp none", ".vtp", tool(Compression::none));
  outputs.emplace_back("vtu", ".vtu", tool(Compression::lz4));
  outputs.emplace_back("vtp snapshot", ".vtp", from_snapshot);
  outputs.emplace_back("vtu snapshot", ".vtu", from_snapshot);
  outputs.emplace_back("obj", ".obj", tool(Compression::lz4));
  outputs.emplace_back("off", ".off", tool(Compression::lz4));
  outputs.emplace_back("stl", ".stl", tool(Compression::lz4));

  const fs::path dir = fs::temp_directory_path() / ("rgbmesh-bench-write-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const bool peaks = reset_peak();
  const auto measure = [&](Output& o, const fs::path& file) {
    const double before = status_bytes("VmRSS");
    reset_peak();
    const auto start = Clock::now();
    o.write(file, mesh);
    o.seconds.push_back(seconds_since(start));
    const double peak = status_bytes("VmHWM");
    o.peak_per_vertex = std::max(o.peak_per_vertex, peak / vertices);
    o.own_per_vertex = std::max(o.own_per_vertex, (peak - before) / vertices);
    o.bytes = fs::file_size(file);
    fs::remove(file);
  };
  // Cold: the PLY write, then the first VTK XML write, which computes the limit positions.
  Output cold_ply("ply cold", ".ply", tool(Compression::lz4)), cold_vtp("vtp cold", ".vtp", tool(Compression::lz4));
  measure(cold_ply, dir / "cold.ply");
  measure(cold_vtp, dir / "cold.vtp");
  for (int r = 0; r < repeats; ++r)
    for (std::size_t i = 0; i < outputs.size(); ++i)
      measure(outputs[i], dir / ("mesh" + std::to_string(i) + outputs[i].extension));
  fs::remove_all(dir);

  std::printf("\n%-13s %8s %7s %8s %7s %7s\n", "output", "seconds", "vs ply", "MB", "peak", "write");
  const auto row = [&](const Output& o, double ply) {
    const double s = median(o.seconds);
    std::printf("%-13s %8.2f %7.2f %8.1f", o.label.c_str(), s, s / ply, static_cast<double>(o.bytes) / 1e6);
    if (peaks)
      std::printf(" %7.0f %7.0f\n", o.peak_per_vertex, o.own_per_vertex);
    else
      std::printf(" %7s %7s\n", "?", "?");
  };
  row(cold_ply, median(cold_ply.seconds));
  row(cold_vtp, median(cold_ply.seconds));
  for (const Output& o : outputs) row(o, median(outputs.front().seconds));
  std::printf(
      "seconds: the write as the tool makes it (cold: once, the VTK XML write computing the limit positions;\n"
      "the others the median of %d warm runs) and its ratio to PLY's (cold to cold). Bytes per vertex: peak,\n"
      "the process's resident peak during the write; write, its rise over the resident size before.\n",
      repeats);
  return 0;
}
