#include "default_problem.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/statistics.hpp"
#include "rgbmesh/vtk_io.hpp"
#include "stages.hpp"

namespace rgbmesh::cli {

namespace {

// A star with six spikes (after the paper's Fig. 17): an octahedron whose six corners are
// pulled out into spikes, 24 triangles, vertices of valence 3 and 8.
RgbMesh embedded_star() {
  std::vector<Vec3> points = {{2.5, 0, 0},  {-2.5, 0, 0}, {0, 2.5, 0},
                              {0, -2.5, 0}, {0, 0, 2.5},  {0, 0, -2.5}};
  const std::array<std::int32_t, 3> octahedron[8] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                                     {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  // Each octahedron face gets a centre vertex on the unit sphere: 3 triangles per face.
  std::vector<std::array<std::int32_t, 3>> triangles;
  for (const auto& f : octahedron) {
    Vec3 c = (points[f[0]] + points[f[1]] + points[f[2]]) * (1.0 / 3.0);
    c *= 1.0 / norm(c);
    const auto ci = static_cast<std::int32_t>(points.size());
    points.push_back(c);
    triangles.push_back({f[0], f[1], ci});
    triangles.push_back({f[1], f[2], ci});
    triangles.push_back({f[2], f[0], ci});
  }
  return RgbMesh::from_triangles(points, triangles);
}

}  // namespace

int run_default_job(const std::string& out_dir) {
  namespace fs = std::filesystem;
  fs::create_directories(out_dir);
  RgbMesh mesh = embedded_star();
  std::cout << "rgbmesh default job: an embedded 6-spike star (" << mesh.num_triangles()
            << " triangles), refined selectively.\n";
  write_mesh(fs::path(out_dir) / "star_base.vtp", snapshot_for_file(mesh, fs::path(out_dir) / "star_base.vtp"));
  // Level 2 everywhere, level 6 around the tip of one spike (where the Loop surface passes:
  // the limit position of the spike's base vertex), level 4 in a ball around the centre.
  const Vec3 tip = mesh.limit_position(VertexHandle(0));
  const std::string tip_ball = std::to_string(tip.x) + "," + std::to_string(tip.y) + "," + std::to_string(tip.z) + ",0.4,6";
  std::vector<Stage> stages = {parse_uniform("2"), parse_ball(tip_ball), parse_ball("0,0,0,1.0,4")};
  const StageTotals totals = run_stages(mesh, stages);
  const std::string error = mesh.validate(true);
  if (!error.empty()) {
    std::cerr << "rgbmesh: internal error: " << error << "\n";
    return 1;
  }
  const fs::path out = fs::path(out_dir) / "star_refined.vtp";
  write_mesh(out, snapshot_for_file(mesh, out));
  const MeshStatistics s = compute_statistics(mesh);
  std::cout << "  stages: --uniform 2, --ball " << tip_ball << ", --ball 0,0,0,1.0,4\n"
            << "  result: " << s.vertices << " vertices, " << s.triangles << " triangles, levels 0.."
            << s.max_level << ", " << totals.splits << " splits in " << totals.seconds << " s\n"
            << "  wrote " << (fs::path(out_dir) / "star_base.vtp").string() << " and " << out.string()
            << " (open in ParaView, color by cell data 'level' or 'color')\n";
  return 0;
}

}  // namespace rgbmesh::cli
