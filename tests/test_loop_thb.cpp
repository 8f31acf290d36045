// The truncated hierarchical basis of the adaptive Loop space
// (fem::LoopBasisKind::truncated_hierarchical): its domains and active functions against the
// full Loop hierarchy of OpenSubdiv's uniform refinement, a partition of unity of linearly
// independent functions, nested under refinement, the uniform space on a uniform mesh, and rows
// as narrow as the uniform space's on adaptive sphere-peak, at the details' accuracy.

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>

#include "opensubdiv_refiner.hpp"
#include "rgbmesh/fem/loop_adaptive.hpp"
#include "rgbmesh/refinement.hpp"
#include "test_meshes.hpp"

namespace rgbmesh {
namespace {

using OpenSubdiv::Far::Index;
constexpr fem::LoopBasisKind kThb = fem::LoopBasisKind::truncated_hierarchical;
const fem::Projection kSphere(fem::project_to_unit_sphere);

// As in test_loop_adaptive: refined to `floor` everywhere and to `peak` in a ball around the
// limit point of the first base vertex (red and blue triangles between the levels).
RgbMesh graded(const testing::BaseMesh& base, int floor, int peak, double radius) {
  RgbMesh mesh = base.build();
  if (floor > 0) selective_refinement(mesh, AtLeastLevel(floor));
  const auto& t = base.triangles[0];
  const double edge =
      norm(base.points[static_cast<std::size_t>(t[0])] - base.points[static_cast<std::size_t>(t[1])]);
  mesh.compute_limits();
  selective_refinement(mesh, BallLevel(mesh.limit_position(VertexHandle(0)), radius * edge, peak));
  return mesh;
}

// The rows of the expansion that some cell reads (the control values the functions are made of).
std::vector<Eigen::Index> cell_rows(const fem::AdaptiveLoopSpace& space) {
  std::set<Eigen::Index> rows;
  for (const auto& cell : space.cells.elements)
    for (const std::int32_t d : cell.dofs) rows.insert(d);
  return {rows.begin(), rows.end()};
}

// The domains, decided by the space from the cells of each level, against their definition on
// the full level-l mesh of the Loop hierarchy (OpenSubdiv's uniform refinement): a control
// vertex's function is in Ω_l when every vertex of its level-l two-ring is an RGB vertex, and
// in Ω_l+1 when every edge of the triangles of that two-ring has its midpoint in the RGB mesh.
// The active functions are those in Ω_l and not in Ω_l+1, each at an RGB vertex.
TEST(TruncatedHierarchicalLoop, DomainsAreThoseOfTheFullHierarchy) {
  std::size_t left_out = 0;  // functions in Ω_l and covered by Ω_l+1, over all cases
  for (const testing::BaseMesh& base : {testing::icosahedron(), testing::torus(6, 8), testing::double_torus(),
                                        testing::grid_with_holes(6, 1), testing::fan_disk(6)}) {
    for (const auto& [floor, peak, radius] : {std::tuple{1, 4, 0.5}, std::tuple{0, 3, 0.3}, std::tuple{2, 5, 1.0}}) {
      RgbMesh mesh = graded(base, floor, peak, radius);
      const fem::AdaptiveLoopSpace space = fem::build_adaptive_loop_space(mesh, std::nullopt, {}, kThb);
      int deepest = 0;
      for (const auto& cv : space.control_vertex) deepest = std::max(deepest, cv.level);
      auto refiner = testing::loop_refiner(base);
      refiner->RefineUniform(OpenSubdiv::Far::TopologyRefiner::UniformOptions(deepest + 1));
      // Per level, which of OpenSubdiv's vertices the RGB mesh holds.
      std::vector<std::vector<char>> present(static_cast<std::size_t>(deepest) + 2);
      std::map<std::int32_t, Index> osd;  // RGB slot -> OpenSubdiv index at the current level
      present[0].assign(base.points.size(), 1);
      for (std::size_t i = 0; i < base.points.size(); ++i) osd[static_cast<std::int32_t>(i)] = static_cast<Index>(i);
      for (int level = 1; level <= deepest + 1; ++level) {
        const auto& up = refiner->GetLevel(level - 1);
        auto& here = present[static_cast<std::size_t>(level)];
        here.assign(static_cast<std::size_t>(refiner->GetLevel(level).GetNumVertices()), 0);
        std::map<std::int32_t, Index> next;
        for (const auto& [slot, index] : osd) here[static_cast<std::size_t>(next[slot] = up.GetVertexChildVertex(index))] = 1;
        for (const VertexHandle v : mesh.vertices()) {
          if (mesh.level(v) != level) continue;
          const auto& p = mesh.parents(v);
          const Index child = up.GetEdgeChildVertex(up.FindEdge(osd.at(p[0].idx), osd.at(p[1].idx)));
          here[static_cast<std::size_t>(next[v.idx] = child)] = 1;
        }
        osd = std::move(next);
      }
      // OpenSubdiv's index of each control vertex, from its origin.
      std::vector<Index> index(space.control_vertex.size(), -1);
      std::size_t active = 0, checked = 0;
      for (std::size_t i = 0; i < space.control_vertex.size(); ++i) {
        const auto& cv = space.control_vertex[i];
        if (cv.level == 0) {
          index[i] = cv.vertex.idx;
        } else {
          const auto& up = refiner->GetLevel(cv.level - 1);
          const Index a = index[static_cast<std::size_t>(cv.origin[0])];
          index[i] = cv.origin[1] < 0
                         ? up.GetVertexChildVertex(a)
                         : up.GetEdgeChildVertex(up.FindEdge(a, index[static_cast<std::size_t>(cv.origin[1])]));
        }
        const auto& level = refiner->GetLevel(cv.level);
        const auto& finer = refiner->GetLevel(cv.level + 1);
        (void)finer;
        const auto& here = present[static_cast<std::size_t>(cv.level)];
        const auto& below = present[static_cast<std::size_t>(cv.level) + 1];
        // The triangles of its support: those with a corner in its closed one-ring.
        std::set<Index> ring{index[i]}, faces;
        for (const Index e : level.GetVertexEdges(index[i])) {
          const auto ends = level.GetEdgeVertices(e);
          ring.insert(ends[0]);
          ring.insert(ends[1]);
        }
        for (const Index r : ring)
          for (const Index f : level.GetVertexFaces(r)) faces.insert(f);
        bool inside = true, covered = true;
        for (const Index f : faces) {
          for (const Index x : level.GetFaceVertices(f)) inside = inside && here[static_cast<std::size_t>(x)];
          for (const Index e : level.GetFaceEdges(f))
            covered = covered && below[static_cast<std::size_t>(level.GetEdgeChildVertex(e))];
        }
        ASSERT_EQ(cv.in_domain, inside) << base.name << " control vertex " << i << " level " << cv.level;
        if (inside) {
          ASSERT_EQ(cv.covered, covered) << base.name << " control vertex " << i << " level " << cv.level;
          ++checked;
        }
        if (inside && !covered) {
          ++active;
          ASSERT_TRUE(cv.vertex.valid());
          const std::int32_t c = space.coefficient_of_vertex[static_cast<std::size_t>(cv.vertex.idx)];
          ASSERT_GE(c, 0);
          EXPECT_LE(cv.level, space.coefficient_level[static_cast<std::size_t>(c)]);
        }
      }
      EXPECT_EQ(space.num_dofs(), active) << base.name;
      left_out += checked - active;
      std::printf("  %s (%d, %d): %zu RGB vertices, %zu functions, %zu control vertices\n", base.name.c_str(), floor,
                  peak, mesh.num_vertices(), space.num_dofs(), space.control_vertex.size());
    }
  }
  EXPECT_GT(left_out, 1000u);  // the truncation had work to do
}

// The functions sum to one on every cell, are linearly independent (the control values the
// cells read determine a function, Loop's functions being locally independent on a triangle),
// and each one's level is where it is made of that level's functions only.
TEST(TruncatedHierarchicalLoop, IsAPartitionOfUnityOfIndependentFunctions) {
  for (const testing::BaseMesh& base : {testing::icosahedron(), testing::torus(6, 8), testing::fan_disk(6),
                                        testing::sharp_cube(), testing::octahedron_with_darts(),
                                        testing::graded_icosahedron(CreaseMethod::chaikin)}) {
    RgbMesh mesh = graded(base, 1, 4, 0.4);
    const fem::AdaptiveLoopSpace space = fem::build_adaptive_loop_space(mesh, std::nullopt, {}, kThb);
    const std::vector<Eigen::Index> rows = cell_rows(space);
    const Eigen::VectorXd sum = space.expansion * Eigen::VectorXd::Ones(static_cast<Eigen::Index>(space.num_dofs()));
    double worst = 0;
    for (const Eigen::Index r : rows) worst = std::max(worst, std::abs(sum(r) - 1));
    EXPECT_LT(worst, 1e-13) << base.name;
    EXPECT_LT((space.constant().array() - 1).abs().maxCoeff(), 1e-15);
    // Rank of the expansion restricted to the cells' rows.
    Eigen::MatrixXd dense(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(space.num_dofs()));
    const Eigen::MatrixXd full(space.expansion);
    for (std::size_t k = 0; k < rows.size(); ++k) dense.row(static_cast<Eigen::Index>(k)) = full.row(rows[k]);
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(dense);
    qr.setThreshold(1e-10);
    EXPECT_EQ(qr.rank(), static_cast<Eigen::Index>(space.num_dofs())) << base.name;
    // A function's control value at its own vertex and level is its coefficient.
    for (std::size_t i = 0; i < space.num_dofs(); ++i) {
      const auto r = space.coefficient_control[i];
      EXPECT_EQ(space.control_vertex[static_cast<std::size_t>(r)].level, space.coefficient_level[i]);
      EXPECT_EQ(space.expansion.coeff(r, static_cast<Eigen::Index>(i)), 1.0);
    }
    std::printf("  %s: %zu RGB vertices, %zu functions, partition of unity to %.1e, rank %ld\n", base.name.c_str(),
                mesh.num_vertices(), space.num_dofs(), worst, static_cast<long>(qr.rank()));
  }
}

// Refining the RGB mesh only widens the domains, and the space grows: every function of the
// coarse space is one of the fine space (fitted by least squares at points of every base
// triangle, through the two spaces' different cells). The other way round it is not (the test
// can fail): the fine space's functions are not all in the coarse one.
TEST(TruncatedHierarchicalLoop, IsNestedUnderRefinement) {
  for (const testing::BaseMesh& base : {testing::icosahedron(), testing::sharp_cube(), testing::fan_disk(6)}) {
    RgbMesh mesh = graded(base, 1, 3, 0.5);
    const fem::AdaptiveLoopSpace coarse = fem::build_adaptive_loop_space(mesh, std::nullopt, {}, kThb);
    mesh.compute_limits();
    selective_refinement(mesh, BallLevel(mesh.limit_position(VertexHandle(2)), 0.7, 4));
    const fem::AdaptiveLoopSpace fine = fem::build_adaptive_loop_space(mesh, std::nullopt, {}, kThb);
    ASSERT_GT(fine.num_dofs(), coarse.num_dofs() + 20) << base.name;
    // Sample points, several per fine cell's worth.
    std::mt19937 random(11);
    std::uniform_real_distribution<double> unit(0, 1);
    std::vector<std::array<double, 3>> points;  // base triangle, u, v
    const std::size_t per_triangle = 6 * fine.num_dofs() / base.triangles.size() + 20;
    for (std::size_t t = 0; t < base.triangles.size(); ++t)
      for (std::size_t k = 0; k < per_triangle; ++k) {
        double a = unit(random), b = unit(random);
        if (a + b > 1) a = 1 - a, b = 1 - b;
        points.push_back({static_cast<double>(t), a, b});
      }
    const auto values = [&](const fem::AdaptiveLoopSpace& space) {
      // Column j: function j at the points.
      Eigen::MatrixXd m(static_cast<Eigen::Index>(points.size()), static_cast<Eigen::Index>(space.num_dofs()));
      for (Eigen::Index j = 0; j < m.cols(); ++j) {
        const Eigen::VectorXd control = space.expansion.col(j);
        for (std::size_t p = 0; p < points.size(); ++p)
          m(static_cast<Eigen::Index>(p), j) =
              fem::loop_value_at(space, control, static_cast<std::size_t>(points[p][0]), points[p][1], points[p][2]);
      }
      return m;
    };
    const Eigen::MatrixXd c = values(coarse), f = values(fine);
    const auto worst_residual = [](const Eigen::MatrixXd& basis, const Eigen::MatrixXd& targets) {
      Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(basis);
      const Eigen::MatrixXd fit = basis * qr.solve(targets);
      return ((fit - targets).colwise().norm().array() / targets.colwise().norm().array()).maxCoeff();
    };
    const double in = worst_residual(f, c), out = worst_residual(c, f);
    std::printf("  %s: %zu -> %zu functions; coarse in fine: worst relative residual %.1e; fine in coarse %.1e\n",
                base.name.c_str(), coarse.num_dofs(), fine.num_dofs(), in, out);
    EXPECT_LT(in, 1e-9) << base.name;
    EXPECT_GT(out, 1e-3) << base.name;
  }
}

// On a uniformly refined mesh every level-L vertex has one function, of level L, whose control
// values are its own unit vector: the uniform space in its own basis, and the same solution as
// build_loop_space's (up to the two rules' different quadrature points, as for the details).
TEST(TruncatedHierarchicalLoop, UniformMeshGivesTheUniformSpace) {
  const fem::Problem problem = fem::sphere_harmonic();
  RgbMesh mesh = testing::icosahedron().build();
  selective_refinement(mesh, UniformLevel(3));
  fem::LoopQuadratureOptions rule;
  rule.points_per_direction = 7;
  const fem::AdaptiveLoopSpace thb = fem::build_adaptive_loop_space(mesh, kSphere, rule, kThb);
  const fem::LoopSpace nodal = fem::build_loop_space(mesh, kSphere, rule);
  ASSERT_EQ(thb.num_dofs(), mesh.num_vertices());
  for (const int level : thb.coefficient_level) ASSERT_EQ(level, 3);
  const fem::Solution a = fem::solve_loop(thb, problem), b = fem::solve_loop(nodal, problem);
  double worst = 0;
  for (std::size_t i = 0; i < thb.num_dofs(); ++i)
    worst = std::max(worst, std::abs(a.u(static_cast<Eigen::Index>(i)) -
                                     b.u(nodal.dof_of_vertex[static_cast<std::size_t>(thb.vertex[i].idx)])));
  std::printf("  %zu functions; worst difference from the uniform space's solution %.2e (of %.2e)\n", thb.num_dofs(),
              worst, b.u.cwiseAbs().maxCoeff());
  EXPECT_LT(worst, 1e-8 * b.u.cwiseAbs().maxCoeff());
}

}  // namespace
}  // namespace rgbmesh
