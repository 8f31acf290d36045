#pragma once
/// \file
/// Assembly and solution of -Δu + c u = f with linear (P1) or isoparametric quadratic (P2)
/// elements on a SurfaceMesh.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "rgbmesh/fem/problem.hpp"
#include "rgbmesh/fem/surface_mesh.hpp"
#include "rgbmesh/fem/work_share.hpp"

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
/// The PETSc options (name, value) every amg solve takes, here and in rgbmesh::parallel's
/// distributed solve: under the prefix rgbmesh_amg_ (so that PETSC_OPTIONS can still change
/// them), HMIS coarsening with extended+i interpolation, the usual choice for 2-D problems
/// (fewer levels and less memory than the default Falgout coarsening at the same iteration
/// counts).
const std::vector<std::array<const char*, 2>>& amg_options();

/// What a linear solver returns: the solution and its iterations (0 for direct solvers).
struct LinearSolution {
  Eigen::VectorXd x;
  int iterations = 0;
  double relative_residual = -1;  ///< ‖b - a x‖ / ‖b‖ where the solver measured it (shared solvers)
};
/// A solver for the assembled system of the free unknowns, a x = b (a symmetric positive
/// definite, both triangles stored, compressed), to the relative residual ‖b - a x‖ / ‖b‖ <=
/// tolerance, from guess when not null. Throws std::runtime_error when it fails.
using LinearSolver = std::function<LinearSolution(const SparseMatrix& a, const Eigen::VectorXd& b,
                                                  const Eigen::VectorXd* guess, double tolerance)>;

/// The solver of a system shared among processes (SolveOptions::share): each process passes
/// the contributions of its own triangles, a and b (the system is their sum over the
/// processes; rows that other processes own included), and row_part[i], the process owning
/// row i (the same on every process); row_of_dof[d] is the row of the mesh's DOF d (-1 for a
/// fixed one), for a solver that names rows by the DOFs' points (a distributed mesh, whose
/// processes number their DOFs differently). Returns the whole solution on every process (a
/// distributed mesh: at the DOFs of the process's own triangles and their neighbours) and the
/// relative residual of the summed system. Throws std::runtime_error when it fails. The solver
/// may release a's memory once it has read it (fem::solve does not use it afterwards): the
/// solve is a run's peak of memory.
using SharedLinearSolver = std::function<LinearSolution(
    SparseMatrix& a, const Eigen::VectorXd& b, const std::vector<std::int32_t>& row_part,
    const std::vector<Eigen::Index>& row_of_dof, const Eigen::VectorXd* guess, double tolerance)>;

struct SolveOptions {
  SolverKind solver = SolverKind::automatic;
  double cg_tolerance = 1e-10;
  const Eigen::VectorXd* initial_guess = nullptr;  ///< for CG and AMG (e.g. the previous cycle's solution)
  /// When set, solves every system in place of the kind above (which is then only what the
  /// solution reports): how rgbmesh::parallel solves on all processes of an MPI run.
  LinearSolver linear_solver;
  /// A run on several processes: with share.part and shared_solver set, each process assembles
  /// its own triangles only and shared_solver solves the sum (rgbmesh::parallel::shared_amg).
  WorkShare share;
  SharedLinearSolver shared_solver;
};

struct Solution {
  Eigen::VectorXd u;  ///< one value per DOF
  SolverKind solver = SolverKind::automatic;  ///< the one used
  int iterations = 0;                         ///< CG and AMG only
  double assembly_seconds = 0, solve_seconds = 0;
  bool zero_mean = false;  ///< solved in the zero-mean space (closed or pure Neumann, c = 0)
};

/// Solves a x = b for a symmetric positive definite a (both triangles stored) with options'
/// solver, as solve() solves its free unknowns (automatic: by size), from options'
/// initial_guess when it has b's size; returns x as `u` with the solver used, its iterations
/// and time. Throws std::runtime_error (naming `problem_name`) when the system is singular or
/// the solver fails. Other discretizations (Loop elements) share the solvers through it.
Solution solve_linear_system(SparseMatrix& a, const Eigen::VectorXd& b, const SolveOptions& options,
                             const std::string& problem_name);

/// Assembles and solves. Errors (std::runtime_error, with the reason): a singular system
/// (no Dirichlet part and c = 0 is handled by the zero-mean condition; anything else singular
/// is reported), a source without zero mean where one is required (InputError), c < 0,
/// non-finite data, a solver that fails.
Solution solve(const SurfaceMesh& mesh, const Problem& problem, const SolveOptions& options = {});

}  // namespace rgbmesh::fem
