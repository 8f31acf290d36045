// The clamped Kirchhoff plate with Loop-basis elements (fem::solve_clamped_plate) against the
// classic series value of the clamped square's centre deflection.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "rgbmesh/errors.hpp"
#include "rgbmesh/fem/loop_plate.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"

namespace rgbmesh {
namespace {

struct PlateRun {
  double centre = 0;
  std::size_t dofs = 0;
};

// A map of the plane applied to the lattice's points (identity by default).
using PlaneMap = std::function<Vec3(const Vec3&)>;

// The centre deflection of the clamped square [0, side]² on cells² squares; the centre is a
// vertex of the lattice (cells even), where the limit of the lattice is the vertex itself (its
// neighbours lie symmetrically about it).
PlateRun clamped_square(int cells, double side = 1,
                        const fem::PlateProblem& problem = fem::clamped_square_plate(),
                        const fem::PlateOptions& options = {}, const PlaneMap& map = {}, bool flip = false) {
  TriangleMeshData lattice = square_lattice(cells, side);
  const Vec3 centre{side / 2, side / 2, 0};
  Vec3 mapped_centre = centre;
  if (map) {
    for (Vec3& x : lattice.points) x = map(x);
    mapped_centre = map(centre);
  }
  if (flip)
    for (auto& t : lattice.triangles) std::swap(t[1], t[2]);
  RgbMesh mesh = RgbMesh::from_triangles(lattice.points, lattice.triangles);
  const fem::LoopSpace space = fem::build_loop_space(mesh, std::nullopt, {}, fem::LoopBoundary::ghost_ring);
  const fem::Solution s = fem::solve_clamped_plate(space, problem, options);
  const Eigen::VectorXd at_vertices = fem::loop_vertex_values(space, s.u);
  PlateRun run;
  run.dofs = space.num_dofs();
  run.centre = std::nan("");
  for (std::size_t d = 0; d < space.num_dofs(); ++d)
    if (norm(space.control[d] - mapped_centre) < 1e-9 * side)
      run.centre = at_vertices(static_cast<Eigen::Index>(d));
  return run;
}

// Uniform lattices: the relative error of the centre deflection falls below 1e-4 with 16
// cells a side (359 unknowns), and at 32 cells it is at the reference's last digit.
TEST(LoopPlate, ClampedSquareReachesTheSeriesValue) {
  double previous = 0;
  for (const int cells : {4, 8, 16, 32}) {
    const PlateRun run = clamped_square(cells);
    const double relative = run.centre / fem::kClampedSquareCentreDeflection - 1;
    std::printf("  %2d cells: %5zu unknowns, centre %.9f, relative error %+.2e", cells, run.dofs, run.centre,
                relative);
    if (previous != 0) std::printf(", rate %.2f", std::log2(std::abs(previous / relative)));
    std::printf("\n");
    if (cells == 8) {
      EXPECT_LT(std::abs(relative), 2e-3);
    } else if (cells >= 16) {
      EXPECT_LT(std::abs(relative), cells == 16 ? 1e-4 : 5e-6);
    }
    previous = relative;
  }
}

// Nitsche's terms are consistent: the penalty γ only has to be large enough, and what it
// changes is of the order of the discretization error, which refinement removes (γ large
// approaches the exact constraint, which locks the box-spline space: slower from above).
// Too small a γ loses coercivity, which the factorization detects: refused with advice.
TEST(LoopPlate, NitschePenaltyOnlyNeedsToBeLargeEnough) {
  const std::vector<double> penalties = {80.0, 160.0, 640.0, 5000.0};
  std::vector<double> spread;
  for (const int cells : {8, 16, 32}) {
    std::printf("  %2d cells:", cells);
    double low = 1, high = -1;
    for (const double penalty : penalties) {
      fem::PlateOptions o;
      o.penalty = penalty;
      const double relative = clamped_square(cells, 1, fem::clamped_square_plate(), o).centre /
                                  fem::kClampedSquareCentreDeflection -
                              1;
      std::printf(" γ %4.0f: %+.1e", penalty, relative);
      low = std::min(low, relative), high = std::max(high, relative);
      if (cells == 32) {
        EXPECT_LT(std::abs(relative), penalty <= 640 ? 1e-5 : 5e-5) << penalty;
      }
    }
    std::printf("\n");
    spread.push_back(high - low);
  }
  EXPECT_LT(spread[1], spread[0] / 10);
  EXPECT_LT(spread[2], spread[1] / 10);
  fem::PlateOptions weak;
  weak.penalty = 20;
  try {
    clamped_square(8, 1, fem::clamped_square_plate(), weak);
    FAIL() << "a penalty too small to be coercive was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("raise the penalty"), std::string::npos) << e.what();
  }
}

// w scales as q L⁴ / D; the plane may be anywhere in space, either side up; the lattice may be
// graded (a map whose second and third derivatives enter the boundary terms) as long as its
// boundary stays the square: x -> x + a sin(2πx / L) keeps the lattice odd about both sides.
TEST(LoopPlate, ScalesRotatesAndGradesAsThePlateDoes) {
  fem::PlateProblem heavy = fem::clamped_square_plate();
  heavy.rigidity = 3;
  heavy.load = [](const Vec3&) { return 5.0; };
  const double side = 2;
  const double expected = fem::kClampedSquareCentreDeflection * 5 * std::pow(side, 4) / 3;
  EXPECT_NEAR(clamped_square(16, side, heavy).centre / expected, 1, 1e-4);
  const PlaneMap tilted = [](const Vec3& p) {
    // A rotation (axis (1, 2, 2) / 3, 50 degrees) and a shift.
    const Vec3 a{1.0 / 3, 2.0 / 3, 2.0 / 3};
    const double c = std::cos(0.87), s = std::sin(0.87);
    return c * p + s * cross(a, p) + ((1 - c) * dot(a, p)) * a + Vec3{3, -1, 7};
  };
  for (const bool flip : {false, true}) {
    const PlateRun run = clamped_square(16, 1, fem::clamped_square_plate(), {}, tilted, flip);
    EXPECT_NEAR(run.centre / fem::kClampedSquareCentreDeflection, 1, 1e-4) << flip;
  }
  const PlaneMap graded = [](const Vec3& p) {
    const double a = 0.04, k = 2 * std::acos(-1.0);
    return Vec3{p.x + a * std::sin(k * p.x), p.y + a * std::sin(k * p.y), 0};
  };
  for (const int cells : {16, 32}) {
    const PlateRun run = clamped_square(cells, 1, fem::clamped_square_plate(), {}, graded);
    const double relative = run.centre / fem::kClampedSquareCentreDeflection - 1;
    std::printf("  graded, %d cells: relative error %+.2e\n", cells, relative);
    EXPECT_LT(std::abs(relative), cells == 16 ? 2e-4 : 2e-5);
  }
}

TEST(LoopPlate, RefusesWhatIsNoPlate) {
  // A curved mesh: a shell, not a plate; the vertex off the plane is named.
  TriangleMeshData bumped = square_lattice(8, 1);
  for (Vec3& x : bumped.points) x.z = 0.1 * x.x * x.x;
  RgbMesh curved = RgbMesh::from_triangles(bumped.points, bumped.triangles);
  const fem::LoopSpace curved_space =
      fem::build_loop_space(curved, std::nullopt, {}, fem::LoopBoundary::ghost_ring);
  try {
    fem::solve_clamped_plate(curved_space, fem::clamped_square_plate());
    FAIL() << "a curved mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("flat mesh, but vertex"), std::string::npos) << e.what();
  }
  // A closed surface has nothing to clamp.
  const TriangleMeshData ico = icosahedron();
  RgbMesh closed = RgbMesh::from_triangles(ico.points, ico.triangles);
  selective_refinement(closed, UniformLevel(1));
  const fem::LoopSpace closed_space =
      fem::build_loop_space(closed, std::nullopt, {}, fem::LoopBoundary::ghost_ring);
  EXPECT_TRUE(closed_space.boundary.empty());
  EXPECT_THROW(fem::solve_clamped_plate(closed_space, fem::clamped_square_plate()), InputError);
  // A lattice without ghosts: its boundary vertices are the square's own, no triangle has three
  // interior corners on one cell a side.
  const TriangleMeshData bare = square_lattice(1, 1, 0);
  RgbMesh bare_mesh = RgbMesh::from_triangles(bare.points, bare.triangles);
  EXPECT_THROW(fem::build_loop_space(bare_mesh, std::nullopt, {}, fem::LoopBoundary::ghost_ring), InputError);
  // The closed-surface solvers refuse a space with a boundary rather than impose natural
  // conditions nobody asked for.
  const TriangleMeshData flat = square_lattice(4, 1);
  RgbMesh flat_mesh = RgbMesh::from_triangles(flat.points, flat.triangles);
  const fem::LoopSpace flat_space =
      fem::build_loop_space(flat_mesh, std::nullopt, {}, fem::LoopBoundary::ghost_ring);
  fem::Problem poisson;
  poisson.name = "p";
  poisson.c = 1;
  poisson.source = [](const Vec3&) { return 1.0; };
  EXPECT_THROW(fem::solve_loop(flat_space, poisson), InputError);
  // And by default a mesh with boundary is refused, as before.
  EXPECT_THROW(fem::build_loop_space(flat_mesh), InputError);
}

}  // namespace
}  // namespace rgbmesh
