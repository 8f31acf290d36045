// Example 01: continuous level of detail with a moving front.
//
// A plane sweeps across an icosahedron. At every time step the mesh must be at level `fine`
// within a band around the plane and at level 0 elsewhere. One call of selective_refinement
// per step coarsens behind the front (queue Qc of removable vertices) and refines ahead of it
// (queue Qr of edges), one vertex at a time, and the mesh stays conforming throughout
// (paper, section V). Every step is written as a VTP file and listed in a .pvd collection,
// which ParaView plays as an animation.

#include <CLI/CLI.hpp>
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
#include "rgbmesh/shapes.hpp"
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

}  // namespace

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  CLI::App app{"Example 01: a band of fine levels follows a plane across an icosahedron (RGB queues alone)."};
  std::string out = "out/01_moving_front";
  app.add_option("OUT", out, "Output folder (one .vtp per step and front.pvd)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  const fs::path out_dir = out;
  fs::create_directories(out_dir);

  const rgbmesh::TriangleMeshData ico = rgbmesh::icosahedron();
  RgbMesh mesh = RgbMesh::from_triangles(ico.points, ico.triangles);
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
