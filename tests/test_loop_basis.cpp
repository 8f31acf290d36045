// Loop's limit functions on a triangle (fem::evaluate_loop_basis, loop_quadrature) against
// OpenSubdiv's, an independent implementation: Far::PatchTable built by adaptive isolation of
// the extraordinary vertices evaluates the limit exactly on its regular (LOOP) patches, with
// derivatives, in the base face's parameters; PrimvarRefinerReal::Limit gives the exact limit
// at every vertex, extraordinary ones included.

#include <gtest/gtest.h>
#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/primvarRefiner.h>

#include <cmath>
#include <memory>
#include <random>

#include "opensubdiv_refiner.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/fem/loop_basis.hpp"
#include "rgbmesh/refinement.hpp"
#include "test_meshes.hpp"

namespace rgbmesh {
namespace {

using namespace OpenSubdiv;

struct Scalar {
  double x = 0;
  void Clear() { x = 0; }
  void AddWithWeight(const Scalar& o, double w) { x += w * o.x; }
};

// The patch of each base triangle, from the mesh's rings.
fem::LoopPatch patch_of(const RgbMesh& mesh, const std::array<std::int32_t, 3>& t) {
  return fem::gather_loop_patch(t, [&mesh](std::int32_t v, std::vector<std::int32_t>& ring) {
    const VertexStar s = mesh.star(VertexHandle(v));
    ring.clear();
    for (const VertexHandle w : s.neighbors) ring.push_back(w.idx);
    return !s.boundary;
  });
}

double dot(const Eigen::VectorXd& w, const fem::LoopPatch& patch, const std::vector<double>& values) {
  double sum = 0;
  for (std::size_t i = 0; i < patch.vertices.size(); ++i)
    sum += w(static_cast<Eigen::Index>(i)) * values[static_cast<std::size_t>(patch.vertices[i])];
  return sum;
}

class LoopBasisVsOpenSubdiv : public ::testing::TestWithParam<testing::BaseMesh> {};

// Values, first and second derivatives at random points of every base triangle, wherever
// OpenSubdiv's patch there is a regular Loop patch (everywhere but the last isolation level's
// triangles at extraordinary vertices, which it only approximates).
TEST_P(LoopBasisVsOpenSubdiv, LimitAndDerivativesOnRegularPatches) {
  const testing::BaseMesh& base = GetParam();
  const RgbMesh mesh = base.build();
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<double> values(base.points.size());
  for (double& x : values) x = unit(random) - 0.5;

  const int isolation = 6;
  auto refiner = testing::loop_refiner(base);
  Far::PatchTableFactory::Options patch_options(isolation);
  patch_options.SetPatchPrecision<double>();
  refiner->RefineAdaptive(patch_options.GetRefineAdaptiveOptions());
  std::unique_ptr<const Far::PatchTable> table(Far::PatchTableFactory::Create(*refiner, patch_options));
  std::vector<Scalar> all(
      static_cast<std::size_t>(refiner->GetNumVerticesTotal() + table->GetNumLocalPoints()));
  for (std::size_t i = 0; i < values.size(); ++i) all[i].x = values[i];
  Far::PrimvarRefinerReal<double> primvar(*refiner);
  Scalar* src = all.data();
  for (int level = 1; level <= refiner->GetMaxLevel(); ++level) {
    Scalar* dst = src + refiner->GetLevel(level - 1).GetNumVertices();
    primvar.Interpolate(level, src, dst);
    src = dst;
  }
  // (The local points of the end caps, which are not compared; through the double-precision
  // stencils, as ComputeLocalPointValues reads only single-precision ones.)
  if (table->GetNumLocalPoints() > 0)
    table->GetLocalPointStencilTable<double>()->UpdateValues(all.data(), all.data() + refiner->GetNumVerticesTotal());
  const Far::PatchMap map(*table);

  int compared = 0;
  double worst[6] = {0, 0, 0, 0, 0, 0};
  for (std::size_t f = 0; f < base.triangles.size(); ++f) {
    const fem::LoopPatch patch = patch_of(mesh, base.triangles[f]);
    // OpenSubdiv's patches near a boundary vertex of one triangle are corner box splines, an
    // approximation of the smooth corner's rule (BoundaryCornersAgainstUniformRefinement
    // checks those faces against its refinement instead).
    if ((patch.open[0] && patch.valence[0] == 2) || (patch.open[1] && patch.valence[1] == 2) ||
        (patch.open[2] && patch.valence[2] == 2))
      continue;
    for (int sample = 0; sample < 40; ++sample) {
      // Half the points anywhere, half within 1/16 of a corner (where extraordinary corners
      // make the patch deepest).
      double u = unit(random), v = unit(random);
      if (u + v > 1) u = 1 - u, v = 1 - v;
      if (sample % 2) {
        u /= 16, v /= 16;
        if (sample % 3 == 1) std::swap(u, v), u = 1 - u - v;  // near corner 1 as well
      }
      const Far::PatchTable::PatchHandle* handle = map.FindPatch(static_cast<int>(f), u, v);
      ASSERT_NE(handle, nullptr);
      if (table->GetPatchDescriptor(*handle).GetType() != Far::PatchDescriptor::LOOP) continue;
      double w[6][12];
      table->EvaluateBasis(*handle, u, v, w[0], w[1], w[2], w[3], w[4], w[5]);
      const Far::ConstIndexArray cvs = table->GetPatchVertices(*handle);
      double reference[6] = {0, 0, 0, 0, 0, 0};
      for (int k = 0; k < 6; ++k)
        for (int i = 0; i < cvs.size(); ++i)
          reference[k] += w[k][i] * all[static_cast<std::size_t>(cvs[i])].x;
      // OpenSubdiv 3.5 returns the second derivatives of a sub-triangle turned half around
      // (the middle child of a split) with the wrong sign: the turn negates the first
      // derivatives (d/du = -2^depth d/du') but leaves the second ones positive (4^depth).
      // The central differences of its own first derivatives below confirm the sign used here.
      if (table->GetPatchParam(*handle).IsTriangleRotated())
        for (int k = 3; k < 6; ++k) reference[k] = -reference[k];
      if (sample % 5 == 0) {
        // d/du and d/dv of OpenSubdiv's first derivatives, by central differences.
        const double h = 1e-6;
        const auto first_derivatives = [&](double pu, double pv) {
          const Far::PatchTable::PatchHandle* at = map.FindPatch(static_cast<int>(f), pu, pv);
          double d[6][12], du = 0, dv = 0;
          table->EvaluateBasis(*at, pu, pv, d[0], d[1], d[2], d[3], d[4], d[5]);
          const Far::ConstIndexArray points = table->GetPatchVertices(*at);
          for (int i = 0; i < points.size(); ++i) {
            du += d[1][i] * all[static_cast<std::size_t>(points[i])].x;
            dv += d[2][i] * all[static_cast<std::size_t>(points[i])].x;
          }
          return std::array<double, 2>{du, dv};
        };
        if (u > h && v > h && u + v < 1 - h) {
          const auto up = first_derivatives(u + h, v), um = first_derivatives(u - h, v);
          const auto vp = first_derivatives(u, v + h), vm = first_derivatives(u, v - h);
          const double scale =
              1e-5 * (1 + std::abs(reference[3]) + std::abs(reference[4]) + std::abs(reference[5]));
          EXPECT_NEAR((up[0] - um[0]) / (2 * h), reference[3], scale)
              << base.name << " duu at " << u << ", " << v;
          EXPECT_NEAR((vp[0] - vm[0]) / (2 * h), reference[4], scale)
              << base.name << " duv at " << u << ", " << v;
          EXPECT_NEAR((vp[1] - vm[1]) / (2 * h), reference[5], scale)
              << base.name << " dvv at " << u << ", " << v;
        }
      }
      const fem::LoopBasisAt at = fem::evaluate_loop_basis(patch, u, v);
      const Eigen::VectorXd* ours[6] = {&at.value, &at.du, &at.dv, &at.duu, &at.duv, &at.dvv};
      for (int k = 0; k < 6; ++k) {
        const double error = std::abs(dot(*ours[k], patch, values) - reference[k]);
        worst[k] = std::max(worst[k], error);
        ASSERT_LT(error, 1e-9) << base.name << " face " << f << " (u, v) = (" << u << ", " << v
                               << "), quantity " << k << " (value, du, dv, duu, duv, dvv); corners' valences "
                               << patch.valence[0] << patch.valence[1] << patch.valence[2] << ", open "
                               << patch.open[0] << patch.open[1] << patch.open[2];
      }
      ++compared;
    }
  }
  EXPECT_GT(compared, static_cast<int>(base.triangles.size()) * 18) << base.name;
  std::printf(
      "  %s: %d points; largest differences value %.1e, du %.1e, dv %.1e, duu %.1e, duv %.1e, dvv %.1e\n",
      base.name.c_str(), compared, worst[0], worst[1], worst[2], worst[3], worst[4], worst[5]);
}

// The limit at the corners, extraordinary ones included, is OpenSubdiv's limit of the vertex.
TEST_P(LoopBasisVsOpenSubdiv, CornerLimitsAreTheLimitPositions) {
  const testing::BaseMesh& base = GetParam();
  const RgbMesh mesh = base.build();
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::vector<double> values(base.points.size());
  for (double& x : values) x = unit(random);
  auto refiner = testing::loop_refiner(base);
  Far::TopologyRefiner::UniformOptions uniform(1);
  uniform.fullTopologyInLastLevel = true;
  refiner->RefineUniform(uniform);
  std::vector<Scalar> level0(values.size()),
      level1(static_cast<std::size_t>(refiner->GetLevel(1).GetNumVertices())), limit(level1.size());
  for (std::size_t i = 0; i < values.size(); ++i) level0[i].x = values[i];
  Far::PrimvarRefinerReal<double> primvar(*refiner);
  primvar.Interpolate(1, level0, level1);
  primvar.Limit(level1, limit);
  for (std::size_t f = 0; f < base.triangles.size(); ++f) {
    const fem::LoopPatch patch = patch_of(mesh, base.triangles[f]);
    for (int corner = 0; corner < 3; ++corner) {
      const int child =
          refiner->GetLevel(0).GetVertexChildVertex(base.triangles[f][static_cast<std::size_t>(corner)]);
      const double reference = limit[static_cast<std::size_t>(child)].x;
      EXPECT_NEAR(dot(fem::loop_corner_limit(patch, corner), patch, values), reference, 1e-12) << base.name;
      const double u = corner == 1 ? 1 : 0, v = corner == 2 ? 1 : 0;
      EXPECT_NEAR(dot(fem::evaluate_loop_basis(patch, u, v).value, patch, values), reference, 1e-12)
          << base.name;
    }
  }
}

// A base mesh refined uniformly, as a base mesh of its own (its control points at that level).
// The tetrahedron's levels have vertices of valence 3: a patch next to one holds that vertex's
// third neighbour in two of its places (level 1: the middle triangles' patches have 12 places
// and 11 vertices), which the evaluation must count twice, as OpenSubdiv does.
// The third derivatives (used by fourth-order boundary terms) are the slopes of the second
// ones: central differences at random points of every base triangle. The limit is a
// polynomial on each sub-triangle, and the random points lie off the knot lines.
TEST_P(LoopBasisVsOpenSubdiv, ThirdDerivativesAreTheSlopesOfTheSecond) {
  const testing::BaseMesh& base = GetParam();
  const RgbMesh mesh = base.build();
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0.05, 0.9);
  const double h = 1e-6;
  double worst = 0;
  for (const auto& t : base.triangles) {
    fem::LoopPatch patch = patch_of(mesh, t);
    for (std::size_t i = 0; i < patch.vertices.size(); ++i) patch.vertices[i] = static_cast<std::int32_t>(i);
    for (int k = 0; k < 4; ++k) {
      const double u = unit(random), v = unit(random) * (1 - u);
      const fem::LoopBasisAt at = fem::evaluate_loop_basis(patch, u, v);
      const fem::LoopBasisAt up = fem::evaluate_loop_basis(patch, u + h, v);
      const fem::LoopBasisAt um = fem::evaluate_loop_basis(patch, u - h, v);
      const fem::LoopBasisAt vp = fem::evaluate_loop_basis(patch, u, v + h);
      const fem::LoopBasisAt vm = fem::evaluate_loop_basis(patch, u, v - h);
      const double scale = 1 + at.duu.cwiseAbs().maxCoeff() + at.dvv.cwiseAbs().maxCoeff();
      const auto check = [&](const Eigen::VectorXd& exact, const Eigen::VectorXd& plus,
                             const Eigen::VectorXd& minus) {
        const double e = (exact - (plus - minus) / (2 * h)).cwiseAbs().maxCoeff() / scale;
        worst = std::max(worst, e);
      };
      check(at.duuu, up.duu, um.duu);
      check(at.duuv, vp.duu, vm.duu);
      check(at.duuv, up.duv, um.duv);
      check(at.duvv, up.dvv, um.dvv);
      check(at.duvv, vp.duv, vm.duv);
      check(at.dvvv, vp.dvv, vm.dvv);
    }
  }
  std::printf("  largest difference from central differences %.1e (relative)\n", worst);
  EXPECT_LT(worst, 1e-6);
}

testing::BaseMesh refined(const testing::BaseMesh& base, int level) {
  RgbMesh m = base.build();
  selective_refinement(m, UniformLevel(level));
  m.compute_limits();
  testing::BaseMesh out;
  out.name = base.name + "_level" + std::to_string(level);
  std::vector<std::int32_t> index(static_cast<std::size_t>(m.vertex_slots()), -1);
  for (const VertexHandle v : m.vertices()) {
    index[static_cast<std::size_t>(v.idx)] = static_cast<std::int32_t>(out.points.size());
    out.points.push_back(m.control_point(v, level));
  }
  for (const TriangleHandle t : m.triangles()) {
    const auto c = m.triangle_vertices(t);
    out.triangles.push_back({index[static_cast<std::size_t>(c[0].idx)],
                             index[static_cast<std::size_t>(c[1].idx)],
                             index[static_cast<std::size_t>(c[2].idx)]});
  }
  return out;
}

std::vector<testing::BaseMesh> closed_meshes() {
  return {testing::octahedron(),
          testing::icosahedron(),
          testing::cube(),
          testing::bipyramid(7),
          testing::torus(6, 8),
          testing::double_torus(),
          refined(testing::tetrahedron(), 1),
          refined(testing::tetrahedron(), 2),
          refined(testing::bipyramid(3), 1)};
}

// Meshes with boundaries, under Loop's boundary rules (OpenSubdiv's VTX_BOUNDARY_EDGE_ONLY):
// boundary vertices of two to five triangles (grids with alternating diagonals, fans), the
// regular ones (three triangles) where OpenSubdiv's boundary patches are box splines with
// extrapolated points, and interior extraordinary vertices next to the boundary.
testing::BaseMesh named(testing::BaseMesh mesh, const std::string& name) {
  mesh.name = name;
  return mesh;
}

std::vector<testing::BaseMesh> open_meshes() {
  return {testing::fan_disk(5),
          testing::fan_disk(7),
          named(testing::grid_with_holes(4, 0), "grid4"),
          named(testing::grid_with_holes(6, 2), "grid6_holes2"),
          refined(testing::fan_disk(5), 1),
          refined(named(testing::grid_with_holes(3, 0), "grid3"), 1),
          refined(testing::cad_pillbox(6, 0.8), 1)};
}

std::string test_name(const ::testing::TestParamInfo<testing::BaseMesh>& param) {
  std::string name = param.param.name;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(Closed, LoopBasisVsOpenSubdiv, ::testing::ValuesIn(closed_meshes()), test_name);
INSTANTIATE_TEST_SUITE_P(Open, LoopBasisVsOpenSubdiv, ::testing::ValuesIn(open_meshes()), test_name);

// Near boundary vertices of one and two triangles, at points of ever finer levels: the
// values equal the limit of OpenSubdiv's uniform refinement at the vertex of that level (its
// refinement, not its patches, which approximate smooth corners of one triangle by corner box
// splines: 1e-6 off near the grid's corners). The vertices at (2^-k, 0), (0, 2^-k) and
// (2^-k, 2^-k) from corner 0 of each face are followed down the refiner's levels as children
// of edges.
TEST(LoopBasis, BoundaryCornersAgainstUniformRefinement) {
  for (const testing::BaseMesh& base : {testing::single_triangle(), testing::fan_disk(4)}) {
    const RgbMesh mesh = base.build();
    const int levels = 9;
    auto refiner = testing::loop_refiner(base);
    Far::TopologyRefiner::UniformOptions uniform(levels);
    uniform.fullTopologyInLastLevel = true;
    refiner->RefineUniform(uniform);
    std::mt19937 random(5);
    std::uniform_real_distribution<double> unit(-1, 1);
    std::vector<std::vector<Scalar>> level(levels + 1);
    level[0].resize(base.points.size());
    for (Scalar& x : level[0]) x.x = unit(random);
    Far::PrimvarRefinerReal<double> primvar(*refiner);
    for (int l = 1; l <= levels; ++l) {
      level[static_cast<std::size_t>(l)].resize(static_cast<std::size_t>(refiner->GetLevel(l).GetNumVertices()));
      primvar.Interpolate(l, level[static_cast<std::size_t>(l - 1)], level[static_cast<std::size_t>(l)]);
    }
    std::vector<Scalar> limit(level[levels].size());
    primvar.Limit(level[levels], limit);
    std::vector<double> values(base.points.size());
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = level[0][i].x;
    double worst = 0;
    for (std::size_t f = 0; f < base.triangles.size(); ++f) {
      const fem::LoopPatch patch = patch_of(mesh, base.triangles[f]);
      int corner = base.triangles[f][0], along_u = base.triangles[f][1], along_v = base.triangles[f][2];
      for (int l = 1; l <= levels; ++l) {
        const Far::TopologyLevel& parent = refiner->GetLevel(l - 1);
        const int diagonal = parent.GetEdgeChildVertex(parent.FindEdge(along_u, along_v));
        along_u = parent.GetEdgeChildVertex(parent.FindEdge(corner, along_u));
        along_v = parent.GetEdgeChildVertex(parent.FindEdge(corner, along_v));
        corner = parent.GetVertexChildVertex(corner);
        // Carried to the last level, where the limit is taken.
        const auto last = [&](int v) {
          for (int k = l; k < levels; ++k) v = refiner->GetLevel(k).GetVertexChildVertex(v);
          return limit[static_cast<std::size_t>(v)].x;
        };
        const double h = std::ldexp(1.0, -l);
        const std::array<std::array<double, 3>, 3> points = {
            {{h, 0, last(along_u)}, {0, h, last(along_v)}, {h, h, last(diagonal)}}};
        for (const auto& [u, v, reference] : points) {
          const double ours = dot(fem::evaluate_loop_basis(patch, u, v).value, patch, values);
          worst = std::max(worst, std::abs(ours - reference));
          ASSERT_NEAR(ours, reference, 1e-12) << base.name << " face " << f << " at (" << u << ", " << v << ")";
        }
      }
    }
    std::printf("  %s: largest difference %.1e over %d levels\n", base.name.c_str(), worst, levels);
  }
}

// A patch whose corners' rings overlap beyond the triangle (the tetrahedron: every vertex is
// in every ring) is refused with the triangle named. A boundary corner's fan is open.
TEST(LoopBasis, RefusesFoldedPatchesAndOpensBoundaryFans) {
  const testing::BaseMesh tetra = testing::tetrahedron();
  const RgbMesh mesh = tetra.build();
  try {
    patch_of(mesh, tetra.triangles[0]);
    FAIL() << "a folded patch was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("closes up"), std::string::npos) << e.what();
  }
  const testing::BaseMesh disk = testing::fan_disk(6);
  const RgbMesh open = disk.build();
  const fem::LoopPatch patch = patch_of(open, disk.triangles[0]);
  int boundary_corners = 0;
  for (int k = 0; k < 3; ++k) {
    if (!patch.open[static_cast<std::size_t>(k)]) {
      EXPECT_EQ(patch.valence[static_cast<std::size_t>(k)], 6);  // the centre
      continue;
    }
    ++boundary_corners;
    EXPECT_EQ(patch.valence[static_cast<std::size_t>(k)], 3);  // a rim vertex: two triangles
  }
  EXPECT_EQ(boundary_corners, 2);
  EXPECT_EQ(patch.vertices.size(), 7u);  // the whole disk
  EXPECT_EQ(patch.triangles.size(), 6u);
  EXPECT_FALSE(patch.regular());
}

// The quadrature rules: their weights sum to the parameter triangle's area, they integrate
// polynomials of their degree exactly on regular patches, and on a patch with an extraordinary
// corner the basis at their points is the pointwise evaluation's.
TEST(LoopBasis, QuadratureRules) {
  std::vector<double> x, w;
  fem::gauss_legendre(5, x, w);
  double moment = 0, sum = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sum += w[i], moment += w[i] * std::pow(x[i], 9);
  EXPECT_NEAR(sum, 1.0, 1e-15);
  EXPECT_NEAR(moment, 0.1, 1e-15);  // degree 9 = 2 n - 1

  const testing::BaseMesh ico = testing::icosahedron();
  const RgbMesh mesh = ico.build();
  const fem::LoopPatch patch = patch_of(mesh, ico.triangles[0]);  // three corners of valence 5
  fem::LoopQuadratureOptions options;
  options.extraordinary_depth = 3;
  const auto rule = fem::loop_quadrature(patch, options);
  double area = 0, u3v2 = 0;
  for (std::size_t p = 0; p < rule->size(); ++p) {
    area += rule->weight[p];
    u3v2 += rule->weight[p] * std::pow(rule->u[p], 3) * std::pow(rule->v[p], 2);
    if (p % 37 == 0) {
      const fem::LoopBasisAt at = fem::evaluate_loop_basis(patch, rule->u[p], rule->v[p]);
      EXPECT_LT((rule->value.col(static_cast<Eigen::Index>(p)) - at.value).norm(), 1e-13);
      EXPECT_LT((rule->du.col(static_cast<Eigen::Index>(p)) - at.du).norm(), 1e-11);
      EXPECT_LT((rule->dvv.col(static_cast<Eigen::Index>(p)) - at.dvv).norm(), 1e-9);
    }
  }
  EXPECT_NEAR(area, 0.5, 1e-14);
  EXPECT_NEAR(u3v2, 3.0 * 2.0 / (7.0 * 6.0 * 5.0 * 4.0 * 3.0), 1e-15);  // 3! 2! / 7!
  // Built once per connectivity: the same rule again.
  EXPECT_EQ(fem::loop_quadrature(patch, options).get(), rule.get());
}

// The default rule on regular triangles (12 symmetric points) is exact to degree 6 as the
// 4 x 4 collapsed Gauss rule is: every monomial u^i v^j with i + j <= 6, and on a regular
// patch (quartic box splines) the products of first derivatives and of values with second
// derivatives (degree 6) give a 7 x 7 rule's matrices.
TEST(LoopBasis, DefaultRuleIsExactToDegreeSix) {
  const testing::BaseMesh ico = testing::icosahedron();
  const RgbMesh mesh = ico.build();
  const fem::LoopPatch middle = fem::loop_child_patch(patch_of(mesh, ico.triangles[0]), 3)->patch;
  ASSERT_TRUE(middle.regular());
  const auto rule = fem::loop_quadrature(middle);
  ASSERT_EQ(rule->size(), 12u);
  for (int i = 0; i <= 6; ++i) {
    for (int j = 0; i + j <= 6; ++j) {
      double sum = 0;
      for (std::size_t p = 0; p < rule->size(); ++p)
        sum += rule->weight[p] * std::pow(rule->u[p], i) * std::pow(rule->v[p], j);
      const double exact = std::tgamma(i + 1) * std::tgamma(j + 1) / std::tgamma(i + j + 3);
      EXPECT_NEAR(sum, exact, 1e-15 * exact) << "u^" << i << " v^" << j;
    }
  }
  fem::LoopQuadratureOptions fine_options;
  fine_options.points_per_direction = 7;
  const auto fine = fem::loop_quadrature(middle, fine_options);
  const auto products = [](const fem::LoopQuadrature& r) {
    const Eigen::VectorXd w =
        Eigen::Map<const Eigen::VectorXd>(r.weight.data(), static_cast<Eigen::Index>(r.size()));
    const Eigen::MatrixXd gradients = r.du * w.asDiagonal() * r.du.transpose() +
                                      r.dv * w.asDiagonal() * r.dv.transpose(),
                          curvature = r.value * w.asDiagonal() * (r.duu + r.dvv).transpose();
    return std::pair{gradients, curvature};
  };
  const auto [g, c] = products(*rule);
  const auto [g_fine, c_fine] = products(*fine);
  EXPECT_LT((g - g_fine).norm(), 1e-14 * g_fine.norm());
  EXPECT_LT((c - c_fine).norm(), 1e-14 * c_fine.norm());
  // Not exact beyond: the products of values (degree 8) differ.
  const Eigen::VectorXd w = Eigen::Map<const Eigen::VectorXd>(rule->weight.data(), 12),
                        w_fine = Eigen::Map<const Eigen::VectorXd>(fine->weight.data(),
                                                                   static_cast<Eigen::Index>(fine->size()));
  const Eigen::MatrixXd mass = rule->value * w.asDiagonal() * rule->value.transpose(),
                        mass_fine = fine->value * w_fine.asDiagonal() * fine->value.transpose();
  EXPECT_GT((mass - mass_fine).norm(), 1e-10 * mass_fine.norm());
}

}  // namespace
}  // namespace rgbmesh
