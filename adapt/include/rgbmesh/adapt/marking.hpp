#pragma once
/// \file
/// Marking: which triangles an adaptive cycle refines, from their error indicators (paper
/// section V: the marked triangles' edges go to the refine queue). The extension point for
/// marking strategies: derive from MarkingStrategy (as deal.II's GridRefinement functions and
/// MFEM's ThresholdRefiner choose elements), or take a built-in one by name (make_marking).

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "rgbmesh/mesh.hpp"

namespace rgbmesh::adapt {

/// What a marking strategy sees: one indicator per FE triangle of this process, the target of
/// the run (AdaptOptions::target_estimate, 0 when none) and, on a distributed mesh, which of
/// the triangles are this process's own and how to add numbers over the processes. On one
/// process every triangle is own and add_over_processes does nothing, so that a strategy
/// written with them is right on any number of processes.
struct Indicators {
  /// One process: every triangle is own.
  explicit Indicators(const std::vector<double>& values, double target = 0)
      : eta(values), target_estimate(target) {}
  /// A distributed mesh: `own` flags this process's triangles; `sum` adds over the processes.
  Indicators(const std::vector<double>& values, double target, const std::vector<char>& own_flags,
             std::function<void(double* values, std::size_t count)> add)
      : eta(values), target_estimate(target), own(&own_flags), sum(std::move(add)) {}

  const std::vector<double>& eta;
  double target_estimate = 0;
  /// A distributed mesh: per triangle, whether it is this process's own (nullptr: all are).
  const std::vector<char>* own = nullptr;
  /// A distributed mesh: adds values over the processes, in place.
  std::function<void(double* values, std::size_t count)> sum;

  bool distributed() const { return own != nullptr; }
  bool is_own(std::size_t triangle) const { return own == nullptr || (*own)[triangle] != 0; }
  void add_over_processes(double* values, std::size_t count) const {
    if (sum) sum(values, count);
  }
};

/// Chooses the triangles to refine. Marks go on own triangles only; every process of a
/// distributed run must mark those that one process holding the whole mesh would (the
/// built-in strategies search their thresholds with add_over_processes).
class MarkingStrategy {
 public:
  virtual ~MarkingStrategy() = default;
  /// One flag per triangle (1: refine).
  virtual std::vector<char> mark(const Indicators& indicators) const = 0;
  /// The scale of coarsening (AdaptOptions::coarsen_below multiplies it): by default the
  /// smallest marked indicator over all processes, 0 if nothing is marked.
  virtual double refinement_threshold(const Indicators& indicators, const std::vector<char>& marked) const;
  /// Whether the strategy marks against Indicators::target_estimate, which must then be set
  /// (run_dynamic sets it from the estimate reached at the start).
  virtual bool marks_by_target() const { return false; }
  /// For a strategy that marks by target: the one that adapts to the start of a moving
  /// problem while no target exists yet (run_dynamic). nullptr: this one.
  virtual std::shared_ptr<const MarkingStrategy> before_target() const { return nullptr; }
};

/// Dörfler's bulk chasing: the fewest triangles carrying the fraction θ of Σ η_T².
///
/// Like fixed-fraction marking, it also marks every indicator within a relative 1e-6 of the
/// last one it marks (ties that only rounding separates), so that marks do not depend on the
/// solver's last digits (e.g. on the number of processes). On a distributed mesh the last
/// marked indicator is found by bisection on its value, about 64 sums of one number.
class DorflerMarking final : public MarkingStrategy {
 public:
  explicit DorflerMarking(double theta = 0.5);
  std::vector<char> mark(const Indicators& indicators) const override;
  double theta() const { return theta_; }

 private:
  double theta_;
};

/// The fraction θ of the triangles with the largest η_T.
class FixedFractionMarking final : public MarkingStrategy {
 public:
  explicit FixedFractionMarking(double theta);
  std::vector<char> mark(const Indicators& indicators) const override;

 private:
  double theta_;
};

/// Every triangle with η_T > target / sqrt(number of triangles): equidistribution towards a
/// fixed total, which keeps the mesh at a steady size for moving features. Before a target
/// exists (the start of a moving problem), Dörfler marking with start_theta.
class EquidistributionMarking final : public MarkingStrategy {
 public:
  explicit EquidistributionMarking(double start_theta = 0.5) : start_theta_(start_theta) {}
  std::vector<char> mark(const Indicators& indicators) const override;
  /// The limit target / sqrt(N) itself.
  double refinement_threshold(const Indicators& indicators, const std::vector<char>& marked) const override;
  bool marks_by_target() const override { return true; }
  std::shared_ptr<const MarkingStrategy> before_target() const override;

 private:
  double start_theta_;
};

/// One row of the table of marking strategies by name, which the command line's --marking and
/// Python's marking= both read (adding a strategy: its class, and a row here). `make` takes θ.
struct NamedMarking {
  const char* name;
  const char* description;
  std::shared_ptr<const MarkingStrategy> (*make)(double theta);
};
/// "dorfler", "fraction", "equidistribution".
/// Marks more triangles so that the refinement keeps the truncated hierarchical Loop space
/// admissible of class `levels` (at most that many levels of functions non-zero on any cell;
/// Bracco, Giannelli and Vázquez 2018, as GeoPDEs' mark_admissible does): a marked triangle of
/// level l makes the triangles of level l - levels + 1 or coarser within that level's support
/// extension of it marked too, and so on from those. The support extension, the union of the
/// supports of the level-k functions non-zero on the triangle, reaches three level-k edges
/// from it; distances are walked along the mesh's edges, an edge of level j counting 2^(k - j)
/// level-k edges. `marked` is per entry of `triangles` (the finite-element mesh's); the marks
/// added stay within it. Returns how many were added. levels < 2: nothing.
std::size_t mark_admissible(const RgbMesh& mesh, const std::vector<TriangleHandle>& triangles,
                            std::vector<char>& marked, int levels);

const std::vector<NamedMarking>& marking_table();
/// The strategy of that name with θ; InputError naming the choices otherwise, or when θ is not
/// in (0, 1].
std::shared_ptr<const MarkingStrategy> make_marking(const std::string& name, double theta);

}  // namespace rgbmesh::adapt
