#pragma once
// Conjugate gradients preconditioned by algebraic multigrid (hypre's BoomerAMG, through PETSc):
// SolverKind::amg. Built from amg_petsc.cpp where PETSc is found, else from
// amg_unavailable.cpp (which refuses), so that no other file depends on PETSc.

#include <Eigen/Core>

#include "rgbmesh/fem/solver.hpp"

namespace rgbmesh::fem::detail {

struct AmgSolution {
  Eigen::VectorXd x;
  int iterations = 0;
};

bool amg_available();

// Solves a x = b for a symmetric positive definite `a` (both triangles stored) to the relative
// residual ‖b - a x‖ / ‖b‖ <= tolerance, from `guess` when given (same size as b).
// std::runtime_error when it does not converge; InputError where PETSc is not built in.
AmgSolution solve_amg(const SparseMatrix& a, const Eigen::VectorXd& b, const Eigen::VectorXd* guess,
                      double tolerance);

}  // namespace rgbmesh::fem::detail
