#pragma once
/// \file
/// A finite-element solution carried through the refinement and coarsening of its RGB mesh.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "rgbmesh/fem/surface_mesh.hpp"
#include "rgbmesh/mesh.hpp"

namespace rgbmesh::adapt {

/// Follows the mesh's insertions and removals (as an observer) from the solution given to
/// store(), and gives the carried values on a later FE mesh of the same RgbMesh (on()).
///
/// P1: a new vertex takes the mean of the ends of the edge it split (the linear interpolant
/// there); a removed vertex drops its value.
///
/// P2 (store() of an order-2 solution): the stored function is the quadratic of each old
/// element in its reference coordinates, and every later node takes its value at the node's
/// place in those coordinates (the prolongation of a nested, parametric hierarchy):
///  - each vertex inserted since store() is located in an old element: the midpoint, in that
///    element's barycentric coordinates, of the edge it split (its parents must share an old
///    element; they do until coarsening removes old vertices);
///  - a new vertex takes the old quadratic there; on a stored edge that is that edge's node
///    value (injection: build_surface_mesh puts the node where the splitting vertex goes — its
///    limit position; with a projection, the projected midpoint, next to the projected vertex);
///  - a new edge's node takes the old quadratic at the midpoint of its ends' places, whatever
///    made the edge (a split, a forced split, a swap); on the halves of a split edge these are
///    its quarter points, 3/8 u_a + 3/4 u_m - 1/8 u_b;
///  - removing a vertex gives the edge it merges its value back (injection again), so that
///    refining and coarsening back returns the stored P2 function exactly; an edge whose ends
///    share no old element (after old vertices were removed) takes the mean of its ends.
/// The values seed the next solve (an initial guess for iterative solvers).
class SolutionTransfer {
 public:
  explicit SolutionTransfer(RgbMesh& mesh);
  ~SolutionTransfer();
  SolutionTransfer(const SolutionTransfer&) = delete;
  SolutionTransfer& operator=(const SolutionTransfer&) = delete;

  /// The solution u on fe (a mesh of this RgbMesh, of order 1 or 2) becomes the carried one.
  void store(const fem::SurfaceMesh& fe, const Eigen::VectorXd& u);
  /// The carried values in the DOF order of fe (its vertices; for P2 its edge nodes too, an
  /// edge no rule above reached taking the mean of its ends); empty before the first store().
  Eigen::VectorXd on(const fem::SurfaceMesh& fe) const;
  /// The carried values at these vertices (live ones of the mesh); empty before the first
  /// store(). Loop elements seed their coefficients with them.
  Eigen::VectorXd at(const std::vector<VertexHandle>& vertices) const;

 private:
  void observe();
  void grow();
  void inserted(VertexHandle v, VertexHandle a, VertexHandle b);
  void removing(VertexHandle v);
  void renumbered(const RgbMesh::Renumbering& map);
  static std::uint64_t key(VertexHandle a, VertexHandle b);
  const double* edge_value(VertexHandle a, VertexHandle b) const;
  void set_edge_value(VertexHandle a, VertexHandle b, double value);

  // A value on the edge between two vertex slots, valid while both slots hold the vertices
  // they held when it was set (their births): an edge that a swap took away keeps its entry
  // when one of its ends is removed later, and a vertex inserted in that slot must not read it.
  struct EdgeValue {
    double value;
    std::uint32_t born_low, born_high;  ///< births of the smaller and the larger slot
  };

  // P2: where a vertex is in the stored (old) elements. An old vertex is a corner of each
  // element of its old star; a vertex inserted since store() has barycentric coordinates in
  // one old element (and, on its edge, in the neighbour across).
  struct Location {
    static constexpr std::int32_t kNone = -1, kOldVertex = -2;
    std::int32_t element = kNone;  ///< an old element, or kNone / kOldVertex
    std::array<double, 3> lambda{};
  };
  struct OldElement {
    std::array<VertexHandle, 3> corners;
    std::array<double, 6> values;          ///< corners, then the nodes of edges 0-1, 1-2, 2-0
    std::array<std::int32_t, 3> across{};  ///< the element across edge k (-1: boundary)
  };
  /// x's barycentric coordinates in old element e, if x lies in it.
  std::optional<std::array<double, 3>> coordinates_in(VertexHandle x, std::int32_t e) const;
  /// The stored quadratic at the midpoint of p and q, if they share an old element.
  std::optional<double> at_midpoint(VertexHandle p, VertexHandle q, Location* where = nullptr) const;

  RgbMesh& mesh_;
  int insertion_id_ = -1, removal_id_ = -1, renumbering_id_ = -1;
  std::vector<double> values_;                          ///< per vertex slot
  std::vector<std::uint32_t> born_;                     ///< per vertex slot: insertions into it
  std::unordered_map<std::uint64_t, EdgeValue> edges_;  ///< P2: stored and merged edges (ends' slots)
  std::vector<Location> locations_;                  ///< P2: per vertex slot
  std::vector<OldElement> old_;                      ///< P2: the stored elements
  std::vector<std::vector<std::int32_t>> old_star_;  ///< P2: old vertex slot -> its old elements
  bool has_values_ = false;
  bool quadratic_ = false;
};

}  // namespace rgbmesh::adapt
