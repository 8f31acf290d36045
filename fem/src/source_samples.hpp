#pragma once
// A problem's source at the lifted quadrature points of the triangles one computation visits
// (the load vector, the compatibility check, an estimator). A pointwise source (Problem::source)
// is called where the computation needs it, on every core; a vectorised one
// (Problem::source_values) is called once, beforehand, with all of those points, and the
// computation reads the table. Both give the same numbers: the points are the same.

#include <cstddef>
#include <string>
#include <vector>

#include "rgbmesh/errors.hpp"
#include "rgbmesh/fem/problem.hpp"
#include "rgbmesh/fem/surface_mesh.hpp"
#include "rgbmesh/fem/work_share.hpp"

namespace rgbmesh::fem::detail {

// Where a computation samples f on triangle t: on the flat triangle through its corners, or on
// the (P2: curved) element, element_point(mesh, t, λ).x; lifted in both cases.
enum class SamplePoints { flat, element };

class SourceSamples {
 public:
  static constexpr std::size_t kPoints = 7;  // triangle_quadrature()

  SourceSamples(const SurfaceMesh& mesh, const Problem& problem, SamplePoints where, const WorkShare& share);

  bool any() const { return pointwise_ != nullptr || !table_.empty(); }
  // f at quadrature point q of triangle t, whose lifted position is `lifted`.
  double at(std::size_t t, std::size_t q, const Vec3& lifted) const {
    if (pointwise_ != nullptr) return (*pointwise_)(lifted);
    return table_.empty() ? 0.0 : table_[kPoints * t + q];
  }

 private:
  const ScalarField* pointwise_ = nullptr;
  std::vector<double> table_;  // kPoints per triangle (NaN where the share does not compute)
};

// A vectorised field at the points, in one call.
std::vector<double> point_values(const PointValues& field, const std::vector<Vec3>& points);

}  // namespace rgbmesh::fem::detail
