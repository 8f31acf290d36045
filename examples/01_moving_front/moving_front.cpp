// Example 01: continuous level of detail with a moving front.
//
// A plane sweeps across an icosahedron. At every time step the mesh must be at level `fine`
// within a band around the plane and at level 0 elsewhere. One call of selective_refinement
// per step coarsens behind the front (queue Qc of removable vertices) and refines ahead of it
// (queue Qr of edges), one vertex at a time, and the mesh stays conforming throughout
// (paper, section V). Every step is written as a VTP file and listed in a .pvd collection,
// which ParaView plays as an animation.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace {

using rgbmesh::RgbMesh;
using rgbmesh::Vec3;

// The criterion of this example. The level a triangle should have depends on its distance to
// the plane x = front: `fine` inside the band, then one level less per band width, down to 0.
class BandAroundPlane final : public rgbmesh::LodCriterion {
 public:
  BandAroundPlane(double front, double half_width, int fine)
      : front_(front), half_width_(half_width), fine_(fine) {}

  // The level wanted at a point.
  int wanted_level(const Vec3& p) const {
    const double d = std::abs(p.x - front_) / half_width_;
    return d <= 1.0 ? fine_ : std::max(0, fine_ - static_cast<int>(std::floor(d)));
  }

  // A triangle rises one level when some corner wants more than it has.
  double triangle_priority(const RgbMesh& m, rgbmesh::TriangleHandle t) const override {
    int wanted = 0;
    for (rgbmesh::VertexHandle v : m.triangle_vertices(t)) wanted = std::max(wanted, wanted_level(m.control_point(v)));
    return wanted > m.level(t) ? 1.0 + wanted - m.level(t) : 0.0;
  }

  // A vertex goes when it is finer than every point of its star wants.
  double vertex_priority(const RgbMesh& m, rgbmesh::VertexHandle v) const override {
    int wanted = wanted_level(m.control_point(v));
    for (rgbmesh::VertexHandle w : m.star(v).neighbors) wanted = std::max(wanted, wanted_level(m.control_point(w)));
    return m.level(v) > wanted ? 1.0 + m.level(v) - wanted : 0.0;
  }

 private:
  double front_, half_width_;
  int fine_;
};

// A unit icosahedron: 12 vertices of valence 5, 20 triangles.
RgbMesh icosahedron() {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0, s = 1.0 / std::sqrt(1.0 + g * g);
  std::vector<Vec3> p = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                         {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (Vec3& q : p) q *= s;
  const std::vector<std::array<std::int32_t, 3>> t = {
      {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  return RgbMesh::from_triangles(p, t);
}

}  // namespace

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  const fs::path out_dir = argc > 1 ? argv[1] : "out/01_moving_front";
  fs::create_directories(out_dir);

  RgbMesh mesh = icosahedron();
  const int steps = 24, fine = 6;
  const double half_width = 0.08;
  std::vector<std::pair<double, std::string>> series;

  std::cout << " step  front  triangles  max level  inserted  removed\n";
  for (int step = 0; step <= steps; ++step) {
    const double front = -1.0 + 2.0 * step / steps;
    const rgbmesh::RefinementResult r =
        rgbmesh::selective_refinement(mesh, BandAroundPlane(front, half_width, fine));
    // Every step must leave a valid, stable RGB triangulation; say so loudly if not.
    if (const std::string error = mesh.validate(/*require_stable=*/true); !error.empty()) {
      std::cerr << "invalid mesh at step " << step << ": " << error << "\n";
      return 1;
    }
    const std::string file = "front_" + std::to_string(step) + ".vtp";
    rgbmesh::write_mesh(out_dir / file, mesh.snapshot());
    series.emplace_back(step, file);
    std::printf("%5d  %5.2f  %9zu  %9d  %8llu  %7llu\n", step, front, mesh.num_triangles(), mesh.max_level(),
                static_cast<unsigned long long>(r.splits), static_cast<unsigned long long>(r.removals));
  }
  rgbmesh::write_pvd(out_dir / "front.pvd", series);
  std::cout << "wrote " << (out_dir / "front.pvd").string() << " (" << series.size() << " steps)\n";
  return 0;
}
