// The assembly of Loop-basis elements' interior terms, shared by loop_elements.cpp (closed
// surfaces) and loop_plate.cpp (which adds its boundary terms to the same pattern).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

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

/// The solver SolverKind::automatic means for a Loop system: CHOLMOD, or BoomerAMG for
/// large ones (by unknowns and matrix entries).
SolveOptions loop_solver(const SolveOptions& options, const SparseMatrix& a);

/// A point of an element's side `edge` (from corner edge to corner edge + 1 of its parameter
/// triangle) at t in [0, 1]: its parameters (u, v) and their derivatives along the side.
struct SideParameters {
  double u = 0, v = 0, du = 0, dv = 0;
};
SideParameters side_parameters(int edge, double t);

/// The largest λ with B v = λ A v for v off A's kernel (A, B symmetric positive semidefinite):
/// how much of an element's energy (A) a boundary quantity (B) can take, the constant that
/// makes Nitsche's penalty coercive. B must vanish on A's kernel (functions without energy
/// have no boundary terms either), which holds for the forms here.
double largest_ratio(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

/// Nitsche's options: InputError unless the penalty factor is above `guarantee` (the factor
/// that makes the form coercive on any mesh), naming `option`.
void check_nitsche_options(const std::string& name, double factor, double guarantee,
                           const std::string& option, int edge_points);

/// InputError naming the problem where the space has seams (infinitely sharp edges): the
/// functions are only C⁰ there, and fourth-order problems need C¹ ones.
void require_smooth(const LoopSpace& space, const std::string& name);

/// Adds an element's matrix (rows and columns in the order of its DOFs) into the system.
void add_local(SparseMatrix& a, const std::vector<std::int32_t>& dofs, const Eigen::MatrixXd& local);

/// Solves the system of a closed surface: with c = 0 in the zero-mean space, where `constant`
/// holds the coefficients of the function 1 (all ones for control values; the base vertices'
/// for a hierarchical basis) and s.area the integrals of the basis functions.
Solution solve_closed_loop_system(LoopSystem& s, const Problem& problem, const SolveOptions& options,
                                  const Eigen::VectorXd& constant);

/// Adds Nitsche's terms for u = g on the space's boundary sides (Neumann sides take their flux)
/// to the system of -Δu + c u = f (see LoopNitscheOptions).
void add_loop_boundary_terms(const LoopSpace& space, const Problem& problem, const LoopNitscheOptions& options,
                             LoopSystem& s);

/// Solves a system with Nitsche's boundary terms. Below a mesh-dependent penalty their form is
/// not coercive, which the factorization detects: InputError naming the penalty and the option
/// that raises it.
Solution solve_nitsche_system(LoopSystem& s, const SolveOptions& options, const std::string& name,
                              double penalty, const std::string& option);

}  // namespace rgbmesh::fem::detail
