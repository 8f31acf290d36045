#pragma once
/// \file
/// Assembly and solution of -Δu + c u = f with P1 elements on a SurfaceMesh.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>

#include "rgbmesh/fem/problem.hpp"
#include "rgbmesh/fem/surface_mesh.hpp"

namespace rgbmesh::fem {

using SparseMatrix = Eigen::SparseMatrix<double>;

/// Stiffness (Laplace-Beltrami: ∫ ∇φi·∇φj), consistent mass (∫ φi φj) and load vector
/// (∫ f φi with the degree-5 rule, plus ∫ h φi on Neumann edges) of a problem.
struct System {
  SparseMatrix stiffness, mass;
  Eigen::VectorXd load;
};
System assemble(const SurfaceMesh& mesh, const Problem& problem);
/// Only the load vector.
Eigen::VectorXd load_vector(const SurfaceMesh& mesh, const Problem& problem);

enum class SolverKind {
  automatic,        ///< by size: sparse LDLT; from 20,000 DOFs amg, else CHOLMOD (LDLT, then CG without it)
  ldlt,             ///< Eigen::SimplicialLDLT
  cg_ichol,         ///< Eigen::ConjugateGradient with IncompleteCholesky (relative residual 1e-10)
  cholmod,          ///< Eigen::CholmodSupernodalLLT (if built with SuiteSparse)
  amg,              ///< CG with hypre's BoomerAMG through PETSc (if built with PETSc), same tolerance as cg
};
const char* to_string(SolverKind k);
/// "auto", "ldlt", "cg", "cholmod", "amg"; InputError otherwise.
SolverKind parse_solver(const std::string& name);
bool cholmod_available();
bool amg_available();

struct SolveOptions {
  SolverKind solver = SolverKind::automatic;
  double cg_tolerance = 1e-10;
  const Eigen::VectorXd* initial_guess = nullptr;  ///< for CG and AMG (e.g. the previous cycle's solution)
};

struct Solution {
  Eigen::VectorXd u;  ///< one value per DOF
  SolverKind solver = SolverKind::automatic;  ///< the one used
  int iterations = 0;                         ///< CG and AMG only
  double assembly_seconds = 0, solve_seconds = 0;
  bool zero_mean = false;  ///< solved in the zero-mean space (closed or pure Neumann, c = 0)
};

/// Assembles and solves. Errors (std::runtime_error, with the reason): a singular system
/// (no Dirichlet part and c = 0 is handled by the zero-mean condition; anything else singular
/// is reported), a source without zero mean where one is required (InputError), c < 0,
/// non-finite data, a solver that fails.
Solution solve(const SurfaceMesh& mesh, const Problem& problem, const SolveOptions& options = {});

}  // namespace rgbmesh::fem
