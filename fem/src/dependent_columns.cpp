// Linearly dependent columns of a sparse matrix (rgbmesh/fem/dependent_columns.hpp).

#include "rgbmesh/fem/dependent_columns.hpp"

#include <Eigen/OrderingMethods>
#include <Eigen/QR>
#include <Eigen/SparseQR>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace rgbmesh::fem {

namespace {

// A group's dependent columns (positions) and their weights in the kept ones, dense.
void rank_dense(const Eigen::MatrixXd& a, double threshold, const std::vector<std::int32_t>& group,
                std::vector<std::int32_t>& out, std::vector<ColumnDependency>& in_kept) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  qr.setThreshold(threshold);
  const Eigen::Index rank = qr.rank();
  if (rank == a.cols()) return;
  const auto& order = qr.colsPermutation().indices();
  Eigen::MatrixXd basis(a.rows(), rank), dependent(a.rows(), a.cols() - rank);
  for (Eigen::Index k = 0; k < rank; ++k) basis.col(k) = a.col(order(k));
  for (Eigen::Index k = rank; k < a.cols(); ++k) dependent.col(k - rank) = a.col(order(k));
  const Eigen::MatrixXd weights = basis.colPivHouseholderQr().solve(dependent);
  for (Eigen::Index d = 0; d < weights.cols(); ++d) {
    out.push_back(group[static_cast<std::size_t>(order(rank + d))]);
    for (Eigen::Index k = 0; k < rank; ++k)
      if (weights(k, d) != 0)
        in_kept.push_back({group[static_cast<std::size_t>(order(k))],
                           group[static_cast<std::size_t>(order(rank + d))], weights(k, d)});
  }
}

// The same with Eigen's sparse QR (COLAMD order; a column whose pivot falls below the threshold
// times the largest column norm is dependent), for groups too large for a dense factor.
void rank_sparse(const SparseMatrix& a, double threshold, const std::vector<std::int32_t>& group,
                 std::vector<std::int32_t>& out, std::vector<ColumnDependency>& in_kept) {
  double largest = 0;
  for (Eigen::Index j = 0; j < a.cols(); ++j) largest = std::max(largest, a.col(j).norm());
  Eigen::SparseQR<SparseMatrix, Eigen::COLAMDOrdering<int>> qr;
  qr.setPivotThreshold(threshold * largest);
  qr.compute(a);
  if (qr.info() != Eigen::Success) throw std::runtime_error("dependent columns: the sparse QR failed");
  const Eigen::Index rank = qr.rank();
  if (rank == a.cols()) return;
  // A P = Q [R11 R12; 0 ~0], the kept columns first: a dependent column is the kept ones
  // times R11⁻¹ R12's column, to within what its pivot left (below the threshold).
  const auto& order = qr.colsPermutation().indices();
  const SparseMatrix r = qr.matrixR();
  const SparseMatrix r11 = r.topLeftCorner(rank, rank);
  constexpr Eigen::Index chunk = 64;  // a dense right-hand side of rank × chunk at most
  for (Eigen::Index d0 = rank; d0 < a.cols(); d0 += chunk) {
    const Eigen::Index d1 = std::min<Eigen::Index>(a.cols(), d0 + chunk);
    Eigen::MatrixXd weights = Eigen::MatrixXd(r.block(0, d0, rank, d1 - d0));
    r11.triangularView<Eigen::Upper>().solveInPlace(weights);
    for (Eigen::Index d = d0; d < d1; ++d) {
      const std::int32_t column = group[static_cast<std::size_t>(order(d))];
      out.push_back(column);
      for (Eigen::Index k = 0; k < rank; ++k)
        if (weights(k, d - d0) != 0)
          in_kept.push_back({group[static_cast<std::size_t>(order(k))], column, weights(k, d - d0)});
    }
  }
}

}  // namespace

DependentColumns dependent_columns(const SparseMatrix& e, const std::vector<char>& used,
                                   const DependentColumnsOptions& options) {
  const std::size_t m = static_cast<std::size_t>(e.rows()), n = static_cast<std::size_t>(e.cols());
  const auto counts = [&used](Eigen::Index row, double value) {
    return value != 0 && (used.empty() || used[static_cast<std::size_t>(row)]);
  };
  DependentColumns result;
  // Peel: a row with one live column makes that column independent of the others; set it
  // aside, which may leave other rows with one.
  std::vector<std::int32_t> count(m, 0);
  for (std::size_t j = 0; j < n; ++j)
    for (SparseMatrix::InnerIterator it(e, static_cast<Eigen::Index>(j)); it; ++it)
      if (counts(it.row(), it.value())) ++count[static_cast<std::size_t>(it.row())];
  std::vector<std::size_t> start(m + 1, 0);
  for (std::size_t r = 0; r < m; ++r) start[r + 1] = start[r] + static_cast<std::size_t>(count[r]);
  std::vector<std::int32_t> columns(start[m]);
  {
    std::vector<std::size_t> at(start.begin(), start.end() - 1);
    for (std::size_t j = 0; j < n; ++j)
      for (SparseMatrix::InnerIterator it(e, static_cast<Eigen::Index>(j)); it; ++it)
        if (counts(it.row(), it.value()))
          columns[at[static_cast<std::size_t>(it.row())]++] = static_cast<std::int32_t>(j);
  }
  std::vector<char> alive(n, 1);
  std::vector<std::size_t> queue;
  for (std::size_t r = 0; r < m; ++r)
    if (count[r] == 1) queue.push_back(r);
  while (!queue.empty()) {
    const std::size_t r = queue.back();
    queue.pop_back();
    if (count[r] != 1) continue;
    std::int32_t j = -1;
    for (std::size_t k = start[r]; k < start[r + 1] && j < 0; ++k)
      if (alive[static_cast<std::size_t>(columns[k])]) j = columns[k];
    alive[static_cast<std::size_t>(j)] = 0;
    for (SparseMatrix::InnerIterator it(e, j); it; ++it)
      if (counts(it.row(), it.value()) && --count[static_cast<std::size_t>(it.row())] == 1)
        queue.push_back(static_cast<std::size_t>(it.row()));
  }
  std::vector<std::int32_t> left;
  for (std::size_t j = 0; j < n; ++j)
    if (alive[j]) left.push_back(static_cast<std::int32_t>(j));
  // A column without entries on the used rows is zero there: dependent, with no weights.
  std::vector<std::int32_t> zero;
  // The columns left fall apart into groups that share no row: each is ranked alone.
  std::vector<std::int32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&parent](std::int32_t j) {
    while (parent[static_cast<std::size_t>(j)] != j)
      j = parent[static_cast<std::size_t>(j)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(j)])];
    return j;
  };
  std::vector<std::int32_t> first_on_row(m, -1);
  for (const std::int32_t j : left) {
    bool any = false;
    for (SparseMatrix::InnerIterator it(e, j); it; ++it) {
      if (!counts(it.row(), it.value())) continue;
      any = true;
      const auto row = static_cast<std::size_t>(it.row());
      if (first_on_row[row] < 0) {
        first_on_row[row] = j;
      } else {
        const std::int32_t a = root(j), b = root(first_on_row[row]);
        if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
      }
    }
    if (!any) zero.push_back(j);
  }
  std::vector<std::pair<std::int32_t, std::int32_t>> by_group;  // (group, column)
  for (const std::int32_t j : left) by_group.emplace_back(root(j), j);
  std::sort(by_group.begin(), by_group.end());
  std::vector<std::int32_t> row_of(m, -1), rows, group;
  for (std::size_t g = 0; g < by_group.size();) {
    group.clear();
    std::size_t h = g;
    for (; h < by_group.size() && by_group[h].first == by_group[g].first; ++h)
      group.push_back(by_group[h].second);
    g = h;
    if (group.size() == 1) continue;  // one column with entries is independent; a zero one is in `zero`
    result.largest_group = std::max(result.largest_group, group.size());
    rows.clear();
    std::vector<Eigen::Triplet<double>> entries;
    for (std::size_t k = 0; k < group.size(); ++k)
      for (SparseMatrix::InnerIterator it(e, group[k]); it; ++it) {
        if (!counts(it.row(), it.value())) continue;
        const auto row = static_cast<std::size_t>(it.row());
        if (row_of[row] < 0) {
          row_of[row] = static_cast<std::int32_t>(rows.size());
          rows.push_back(static_cast<std::int32_t>(row));
        }
        entries.emplace_back(row_of[row], static_cast<Eigen::Index>(k), it.value());
      }
    for (const std::int32_t r : rows) row_of[static_cast<std::size_t>(r)] = -1;
    const auto nr = static_cast<Eigen::Index>(rows.size()), nc = static_cast<Eigen::Index>(group.size());
    if (group.size() <= options.dense_group_limit) {
      Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(nr, nc);
      for (const auto& t : entries) dense(t.row(), t.col()) += t.value();
      rank_dense(dense, options.relative_threshold, group, result.columns, result.in_kept);
    } else {
      SparseMatrix sparse(nr, nc);
      sparse.setFromTriplets(entries.begin(), entries.end());
      rank_sparse(sparse, options.relative_threshold, group, result.columns, result.in_kept);
      ++result.sparse_groups;
    }
  }
  result.columns.insert(result.columns.end(), zero.begin(), zero.end());
  std::sort(result.columns.begin(), result.columns.end());
  return result;
}

}  // namespace rgbmesh::fem
