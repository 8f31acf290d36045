// The assembly of Loop-basis elements' interior terms, shared by loop_elements.cpp (closed
// surfaces) and loop_plate.cpp (which adds its boundary terms to the same pattern).
#pragma once

#include <Eigen/Core>
#include <string>

#include "rgbmesh/fem/loop_elements.hpp"

namespace rgbmesh::fem::detail {

/// An assembled system, with ∫φ_i (the mean condition) and ∫f, ∫|f|. The matrix holds an
/// entry for every pair of DOFs that share a patch, zero or not.
struct LoopSystem {
  SparseMatrix a;
  Eigen::VectorXd b, area;
  double integral = 0, magnitude = 0, seconds = 0;
};

/// ∫ ∇u·∇v + c u v (second order) or ∫ Δ_Γu Δ_Γv + c u v (fourth order) over the elements,
/// and the load ∫ f v (from `batch` when given, else from `source`).
LoopSystem assemble_loop_system(const LoopSpace& space, bool fourth_order, double c,
                                const ScalarField& source, const PointValues& batch, const std::string& name);

/// The solver SolverKind::automatic means for a Loop system of n unknowns.
SolveOptions loop_solver(const SolveOptions& options, Eigen::Index n);

}  // namespace rgbmesh::fem::detail
