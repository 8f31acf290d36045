#pragma once
/// \file
/// Which columns of a sparse matrix depend linearly on the others, and how: used to leave out
/// linearly dependent functions of a space given by its expansion (the truncated hierarchical
/// Loop basis next to high-valence vertices), and usable for any such space.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "rgbmesh/fem/solver.hpp"

namespace rgbmesh::fem {

/// A dependent column written in the kept ones: column `dependent` = Σ weight · column `kept`.
struct ColumnDependency {
  std::int32_t kept = 0, dependent = 0;
  double weight = 0;
};

struct DependentColumnsOptions {
  /// A column is dependent when the pivoted QR's pivot is below this times the largest one.
  double relative_threshold = 1e-10;
  /// Groups of columns sharing rows are ranked by a dense pivoted QR up to this many columns
  /// (exact rank revealing, cubic in the group's size), by Eigen's sparse QR beyond (COLAMD
  /// order, a pivot threshold; time and memory as the sparse factor's fill).
  std::size_t dense_group_limit = 400;
};

struct DependentColumns {
  std::vector<std::int32_t> columns;      ///< dependent columns, increasing
  std::vector<ColumnDependency> in_kept;  ///< each of them written in kept columns
  std::size_t largest_group = 0;          ///< columns in the largest group ranked by a QR
  std::size_t sparse_groups = 0;          ///< groups ranked by the sparse QR
};

/// The columns of `e` that depend on the others on the rows where `used` is non-zero (`used`
/// has e.rows() entries; an empty `used` means every row). A column alone on some row takes
/// part in no dependency, nor does one left alone once such columns are set aside: those are
/// peeled first (linear in the entries); the rest fall apart into groups sharing no row, each
/// ranked by a pivoted QR (see DependentColumnsOptions). Keeping the columns not returned gives
/// a set of full column rank spanning the same space.
DependentColumns dependent_columns(const SparseMatrix& e, const std::vector<char>& used,
                                   const DependentColumnsOptions& options = {});

}  // namespace rgbmesh::fem
