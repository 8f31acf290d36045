#pragma once
/// \file
/// Loop-basis elements on an adaptive RGB mesh: the hierarchical basis of the selectively
/// refined Loop space.
///
/// The unknowns are one coefficient per vertex of the RGB mesh. A base vertex's coefficient is
/// its control value at level 0; a vertex inserted at level l (the midpoint of a level l-1
/// edge) carries a detail, added at level l to the control value that Loop's edge rule gives
/// it from the level l-1 values. So the control values of every level follow from the
/// coefficients as the surface's control points follow from the base mesh, and the discrete
/// functions are those of Loop subdivision with details: C² except at extraordinary vertices.
/// On a uniformly refined mesh this is the space of build_loop_space (another basis of it);
/// refining adds a function with a zero coefficient (the function is unchanged), coarsening
/// drops a detail, so refine-then-coarsen gives the same function back exactly.
///
/// Integration: a function inserted at level l is a level-l Loop basis function, smooth on the
/// level-l triangles of its two-ring. The integration cells are the triangles of the Loop
/// hierarchy (base triangles, split 1-to-4) refined where a finer function is not smooth: a
/// cell of level l is split when one of its children's patches holds a vertex the RGB mesh
/// inserted at level l + 1 (no finer function can reach a cell otherwise: a level l + 2
/// vertex is the midpoint of an edge with a level l + 1 end in that patch). On each cell every
/// function is a combination of the cell's level-l patch functions, whose control values are
/// the `expansion` of the coefficients. RGB's red and blue triangles decide nothing here.
///
/// Sharp features (RgbMesh::sharp_features) enter through the base patches (tagged_features):
/// each cell's patch carries what its corners' rules need at its level, so creases, corners,
/// darts and semi-sharp features (either creasing method) subdivide the functions as they
/// subdivide the surface. The cells on the two sides of an infinitely sharp base edge, of
/// whatever levels, are paired where their sides overlap (cells.seams), for the estimator.
///
/// On a mesh with a boundary the space follows Loop's boundary rules, as the surface does
/// (LoopBoundary::loop_rules): its domain is the limit surface, bounded by the B-spline of the
/// boundary vertices, and Dirichlet data are imposed weakly (Nitsche) on the cells' sides
/// there (cells.boundary).

#include <Eigen/SparseCore>
#include <optional>
#include <vector>

#include "rgbmesh/fem/loop_basis_kind.hpp"
#include "rgbmesh/fem/loop_elements.hpp"

namespace rgbmesh::fem {

struct AdaptiveLoopSpace {
  LoopBasisKind basis = LoopBasisKind::details;
  /// The integration cells, as the elements of a LoopSpace whose DOFs are control values at
  /// the cells' levels (the "control vertices": each level's vertices that some cell's patch
  /// uses). Errors, estimates and pictures take `cells` and control_values(u): for instance
  /// loop_error_norms(space.cells, space.control_values(u), exact).
  LoopSpace cells;
  std::vector<int> cell_level;  ///< per cell
  /// The hierarchy of triangles down to the cells: nodes 0 .. T0 - 1 are the base triangles
  /// (RgbMesh::base_triangles, parameters from their corners as listed), a split node's
  /// children are first_child + 0..3 (numbered as loop_child_patch does), a leaf names its cell.
  struct Node {
    std::int32_t first_child = -1, cell = -1;
  };
  std::vector<Node> tree;
  /// Per cell, the RGB vertices among its corners, or, where none is one (a cell outside the
  /// refined region that a finer function reaches), among the corners of its nearest ancestor
  /// that has some (invalid handles fill the rest): where marking a cell acts on the RGB mesh.
  std::vector<std::array<VertexHandle, 3>> anchors;
  /// Per control vertex (DOF of `cells`): its level, and the RGB vertex it is, if any.
  struct ControlVertex {
    int level = 0;
    VertexHandle vertex;  ///< invalid for a point of the Loop hierarchy the RGB mesh does not hold
    /// The control vertices of level - 1 it is computed from: {v, -1} for the same point one
    /// level up (Loop's vertex rule), {a, b} for the midpoint of edge ab (the edge rule);
    /// {-1, -1} at level 0.
    std::array<std::int32_t, 2> origin{-1, -1};
    /// Its level's function has its support in Ω_level: every triangle of that level whose
    /// patch holds it has its corners in the RGB mesh (LoopBasisKind::truncated_hierarchical).
    bool in_domain = true;
    /// ... and in Ω_{level + 1}: every such triangle has its edges' midpoints in the RGB mesh.
    bool covered = true;
  };
  std::vector<ControlVertex> control_vertex;
  /// control values = expansion * coefficients (rows: control vertices; columns: coefficients).
  SparseMatrix expansion;
  std::vector<VertexHandle> vertex;  ///< coefficient -> RGB vertex (base vertices first)
  /// Coefficients 0 .. num_base - 1 are the base vertices' values (details; 0 for the
  /// truncated hierarchical basis, whose functions are all alike).
  std::size_t num_base = 0;
  /// Vertex slot -> coefficient (-1 if none); with the truncated hierarchical basis, the
  /// vertex's finest function.
  std::vector<std::int32_t> coefficient_of_vertex;

  /// The same space's truncated basis, which the solvers use (with the truncated hierarchical
  /// basis: the expansion itself, the coefficients' conversions both the identity): there an inserted vertex's
  /// control value at its level is its coefficient (rather than the value its rule predicts
  /// plus a detail), so coarser functions are cut off where finer ones take over (as truncated
  /// hierarchical B-splines are). The matrix has as many entries (the ghost control vertices
  /// of partly refined levels carry coarse coefficients down), but it is far better
  /// conditioned for multigrid. control values = truncated_expansion * truncated coefficients.
  SparseMatrix truncated_expansion;
  /// Per inserted vertex's coefficient, the rule that predicts its value from the control
  /// values one level up (rows: coefficients, empty for base vertices; columns: control vertices).
  SparseMatrix prediction;
  /// With the truncated hierarchical basis: the control values of the untruncated sums of the
  /// functions level by level (a coefficient at its own control vertex, the rules elsewhere),
  /// from which `prediction` gives each function's detail (hierarchical_coefficients).
  SparseMatrix accumulated;
  /// With the truncated hierarchical basis: active functions left out because they depend on
  /// the others (which span the same space); see dependent_columns in loop_adaptive.cpp.
  std::size_t dependent_left_out = 0;
  /// With the truncated hierarchical basis: the coefficients of the function 1 (all ones, unless
  /// dependent functions were left out); constant() returns them.
  Eigen::VectorXd constant_coefficients;
  std::vector<std::int32_t> coefficient_control;  ///< coefficient -> its control vertex at its level
  /// Per coefficient, the level of its function (for the truncated hierarchical basis; for the
  /// details, the vertex's level).
  std::vector<int> coefficient_level;

  std::size_t num_dofs() const { return vertex.size(); }
  Eigen::VectorXd control_values(const Eigen::VectorXd& u) const { return expansion * u; }
  /// Hierarchical coefficients (details) from truncated ones (values), and back: the same
  /// function. With the truncated hierarchical basis, its coefficients and the details of the
  /// hierarchical (untruncated) basis of the same functions.
  Eigen::VectorXd hierarchical_coefficients(const Eigen::VectorXd& truncated) const;
  Eigen::VectorXd truncated_coefficients(const Eigen::VectorXd& hierarchical) const;
  /// The coefficients of the function 1 (the base vertices' functions sum to one).
  Eigen::VectorXd constant() const;
};

/// The value at point (u, v) of base triangle `base_triangle` of the function whose control
/// values (AdaptiveLoopSpace::control_values) are given: Loop's limit, exactly.
double loop_value_at(const AdaptiveLoopSpace& space, const Eigen::VectorXd& control,
                     std::size_t base_triangle, double u, double v);

/// An estimate's indicators per cell moved onto the RGB mesh, for marking: each cell's η²
/// is shared equally by the triangles of its level or coarser around its anchors (all of
/// their triangles if none is that coarse), so that Σ η_T² is the estimate's, and a marked
/// triangle rising one level puts finer functions where the cell is. Per triangle slot (0
/// where no cell reaches).
std::vector<double> loop_indicators_on_triangles(const AdaptiveLoopSpace& space, const RgbMesh& mesh,
                                                 const std::vector<double>& per_cell);

/// The function at the limit positions of the vertices, in the DOF order of a P1 mesh of the
/// same RGB mesh (build_surface_mesh, order 1): each vertex is a corner of some cell, where
/// Loop's limit mask gives its value.
Eigen::VectorXd loop_values_on(const AdaptiveLoopSpace& space, const Eigen::VectorXd& coefficients,
                               const SurfaceMesh& p1);

/// The hierarchical Loop space of an RGB mesh in any state of selective refinement. Throws InputError where
/// a base triangle's patch folds onto itself (the base mesh is too coarse: refine it once and use that as
/// the base).
AdaptiveLoopSpace build_adaptive_loop_space(const RgbMesh& mesh,
                                            std::optional<Projection> projection = std::nullopt,
                                            const LoopQuadratureOptions& quadrature = {},
                                            LoopBasisKind basis = LoopBasisKind::details);

/// -Δu + c u = f on the surface, as solve_loop: the cells' matrices assembled on their control
/// values (K), then the coefficients' system expansionᵀ K expansion (the details' in their
/// truncated basis, the result converted back; the truncated hierarchical basis in itself). On a closed surface with
/// c = 0, the zero-mean solution; on a surface with a boundary, u = g there by Nitsche's
/// method, except on the Neumann sides (as solve_loop on a LoopSpace). The result's `u` holds
/// the coefficients.
Solution solve_loop(const AdaptiveLoopSpace& space, const Problem& problem, const SolveOptions& options = {},
                    const LoopNitscheOptions& nitsche = {});

/// The same, also returning the energy of each coefficient's function, a(φ_i, φ_i) (the
/// diagonal of the coefficients' matrix): |u_i| sqrt(a(φ_i, φ_i)) is what dropping a detail
/// costs in the energy norm, to first order, which is how adaptive runs choose the vertices
/// to remove. (With the truncated hierarchical basis, the truncated functions' energies.)
Solution solve_loop(const AdaptiveLoopSpace& space, const Problem& problem, const SolveOptions& options,
                    Eigen::VectorXd& energies, const LoopNitscheOptions& nitsche = {});

/// What removing each RGB vertex would cost the solution u (coefficients of `space`), to first
/// order in the energy norm, from the energies solve_loop returned: per vertex slot, a base
/// vertex's infinite. Details: the vertex's |detail| sqrt(a(φ, φ)). Truncated hierarchical: the
/// largest of the details of its functions (hierarchical_coefficients) times their energies'
/// roots; a vertex with no function of its own (its two-ring incomplete at its level), whose
/// removal takes its neighbours' functions of its level and finer away from the domain, the
/// largest of theirs.
std::vector<double> loop_removal_costs(const AdaptiveLoopSpace& space, const RgbMesh& mesh, const Eigen::VectorXd& u,
                                       const Eigen::VectorXd& energies);

}  // namespace rgbmesh::fem
