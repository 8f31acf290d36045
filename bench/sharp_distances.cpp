// How far the Loop limit surface of a CAD part lies from the part, both ways, without and with
// sharp features found at an angle (issue 42's measure): one markdown row per mesh file.
//
//   rgbmesh_sharp_distances [--angle DEG] [--level K] MESH...
//
// Each mesh is read as the tool reads it (polygons fan-split; --repair's repairs where the
// mesh needs them, said in the row), refined uniformly to level K (default: the level nearest
// 200,000 triangles, at most 4) and its vertices placed at their limit positions. part -> limit:
// points spread over the part's triangles (as many as the refined mesh has vertices) to the
// refined limit mesh; limit -> part: the refined mesh's vertices to the part's triangles. Both
// as RMS and maximum in percent of the part's bounding-box diagonal (CGAL's exact distances to
// triangles, fit/distances.hpp). Not part of the test command: a survey of many parts.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "rgbmesh/fit/distances.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/repair/repair.hpp"
#include "rgbmesh/vtk_io.hpp"

using namespace rgbmesh;

namespace {

struct Distances {
  double to_limit_rms = 0, to_limit_max = 0, to_part_rms = 0, to_part_max = 0;
  std::size_t sharp_edges = 0, corners = 0;
};

double rms(const std::vector<double>& d) {
  double s = 0;
  for (double x : d) s += x * x;
  return d.empty() ? 0 : std::sqrt(s / static_cast<double>(d.size()));
}

Distances measure(const TriangleMeshData& part, const fit::TargetSurface& part_surface, int level) {
  RgbMesh mesh = RgbMesh::from_triangles(part.points, part.triangles, part.sharp);
  Distances out;
  out.sharp_edges = mesh.sharp_features().edges.size();
  for (const SharpVertex& v : mesh.sharp_features().vertices) out.corners += v.sharpness > 0;
  selective_refinement(mesh, UniformLevel(level));
  mesh.compute_limits();
  const MeshSnapshot limit = mesh.snapshot(RgbMesh::Points::limit);
  TriangleMeshData limit_mesh;
  limit_mesh.points = limit.points;
  limit_mesh.triangles = limit.triangles;
  const fit::TargetSurface limit_surface = fit::TargetSurface::from_mesh(limit_mesh);
  const double diagonal = bounding_box_diagonal(part.points);
  const std::vector<double> to_part = part_surface.distances(limit.points);
  const std::vector<double> to_limit =
      limit_surface.distances(fit::surface_samples(part, std::max(limit.points.size(), part.points.size())));
  out.to_part_rms = 100 * rms(to_part) / diagonal;
  out.to_part_max = 100 * *std::max_element(to_part.begin(), to_part.end()) / diagonal;
  out.to_limit_rms = 100 * rms(to_limit) / diagonal;
  out.to_limit_max = 100 * *std::max_element(to_limit.begin(), to_limit.end()) / diagonal;
  return out;
}

bool within(const Distances& d) {
  // The bar: 0.5% RMS and 3% maximum of the diagonal, both ways.
  return d.to_limit_rms <= 0.5 && d.to_part_rms <= 0.5 && d.to_limit_max <= 3 && d.to_part_max <= 3;
}

}  // namespace

int main(int argc, char** argv) {
  double angle = 30;
  int level = -1;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--angle" && i + 1 < argc) {
      angle = std::atof(argv[++i]);
    } else if (a == "--level" && i + 1 < argc) {
      level = std::atoi(argv[++i]);
    } else {
      files.push_back(a);
    }
  }
  if (files.empty()) {
    std::fprintf(stderr, "usage: rgbmesh_sharp_distances [--angle DEG] [--level K] MESH...\n");
    return 2;
  }
  std::printf("| part | triangles | level | smooth: part->limit rms / max | limit->part rms / max | within | "
              "--sharp-angle %g: crease edges | part->limit rms / max | limit->part rms / max | within |\n",
              angle);
  std::printf("| --- | ---: | ---: | ---: | ---: | --- | ---: | ---: | ---: | --- |\n");
  int smooth_ok = 0, sharp_ok = 0, measured = 0;
  for (const std::string& file : files) {
    const std::string name = file.substr(file.find_last_of('/') + 1);
    TriangleMeshData part, detected;
    std::string how;
    try {
      SoupOptions options;
      options.triangulate = true;
      try {
        part = read_mesh(file, options);
      } catch (const MeshDefectError&) {
        options = repair::soup_options(true, true);
        part = read_mesh(file, options);
        how = " (repaired)";
      }
      options.sharp_angle = angle;
      detected = read_mesh(file, options);
    } catch (const std::exception& e) {
      std::printf("| %s | | | not read: %s | | | | | | |\n", name.c_str(), e.what());
      continue;
    }
    int k = level;
    if (k < 0) {  // the level nearest 200,000 triangles, 1 to 4
      k = 1;
      while (k < 4 && part.triangles.size() * (std::size_t{1} << (2 * (k + 1))) <= 300000) ++k;
    }
    try {
      const fit::TargetSurface surface = fit::TargetSurface::from_mesh(part);
      const Distances smooth = measure(part, surface, k);
      const Distances sharp = measure(detected, surface, k);
      ++measured;
      smooth_ok += within(smooth);
      sharp_ok += within(sharp);
      std::printf("| %s%s | %zu | %d | %.3f%% / %.2f%% | %.3f%% / %.2f%% | %s | %zu | %.3f%% / %.2f%% | %.3f%% / %.2f%% | %s |\n",
                  name.c_str(), how.c_str(), part.triangles.size(), k, smooth.to_limit_rms, smooth.to_limit_max,
                  smooth.to_part_rms, smooth.to_part_max, within(smooth) ? "yes" : "no", sharp.sharp_edges,
                  sharp.to_limit_rms, sharp.to_limit_max, sharp.to_part_rms, sharp.to_part_max,
                  within(sharp) ? "yes" : "no");
    } catch (const std::exception& e) {
      std::printf("| %s | %zu | %d | failed: %s | | | | | | |\n", name.c_str(), part.triangles.size(), k, e.what());
    }
    std::fflush(stdout);
  }
  std::printf("\nwithin 0.5%% rms and 3%% max both ways: %d of %d smooth, %d of %d with --sharp-angle %g\n", smooth_ok,
              measured, sharp_ok, measured, angle);
  return 0;
}
