// fem::dependent_columns against matrices whose rank is known by construction: random entries
// on a cyclic band with fewer rows than columns (generic rank = rows), and full-rank bands with
// columns replaced by combinations of others. Both ranking paths (dense pivoted QR per group,
// Eigen's sparse QR for groups above the limit) must find as many dependent columns as the
// construction made, write each in kept columns exactly, and ignore the rows not used.

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "rgbmesh/fem/dependent_columns.hpp"

namespace rgbmesh {
namespace {

using fem::SparseMatrix;

// m × n, column j with random entries on rows j, j+1, ..., j+width-1 (mod m): each row is on
// `width` columns, so nothing is peeled and the columns form one group.
SparseMatrix cyclic_band(Eigen::Index m, Eigen::Index n, int width, std::mt19937& random) {
  std::uniform_real_distribution<double> value(0.5, 1.5);
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index j = 0; j < n; ++j)
    for (int k = 0; k < width; ++k) entries.emplace_back((j * m / n + k) % m, j, value(random));
  SparseMatrix a(m, n);
  a.setFromTriplets(entries.begin(), entries.end());
  return a;
}

// Every dependent column equals its weights' combination of kept columns, to rounding: within
// 1e-9 of the column's norm plus the combination's terms' (weights along a long band can grow
// large, and so does the rounding of their sum).
void expect_written_in_kept(const SparseMatrix& a, const fem::DependentColumns& found,
                            const std::vector<char>& used) {
  const std::set<std::int32_t> dependent(found.columns.begin(), found.columns.end());
  std::vector<Eigen::VectorXd> combination(static_cast<std::size_t>(a.cols()));
  std::vector<double> terms(static_cast<std::size_t>(a.cols()), 0.0);
  for (const auto& d : found.in_kept) {
    ASSERT_FALSE(dependent.count(d.kept)) << "column " << d.kept << " is both kept and dependent";
    ASSERT_TRUE(dependent.count(d.dependent));
    auto& c = combination[static_cast<std::size_t>(d.dependent)];
    if (c.size() == 0) c = Eigen::VectorXd::Zero(a.rows());
    c += d.weight * Eigen::VectorXd(a.col(d.kept));
    terms[static_cast<std::size_t>(d.dependent)] += std::abs(d.weight) * a.col(d.kept).norm();
  }
  for (const std::int32_t j : found.columns) {
    Eigen::VectorXd column = a.col(j);
    Eigen::VectorXd c = combination[static_cast<std::size_t>(j)];
    if (c.size() == 0) c = Eigen::VectorXd::Zero(a.rows());
    for (Eigen::Index r = 0; r < a.rows(); ++r)
      if (!used.empty() && !used[static_cast<std::size_t>(r)]) column(r) = c(r) = 0;
    EXPECT_LE((column - c).norm(), 1e-9 * (column.norm() + terms[static_cast<std::size_t>(j)]))
        << "column " << j;
  }
}

TEST(DependentColumns, FewerRowsThanColumnsLeaveExactlyTheSurplusOutOnBothPaths) {
  std::mt19937 random(7);
  for (const Eigen::Index n : {40, 300, 1500}) {
    const Eigen::Index m = n - 6;
    const SparseMatrix a = cyclic_band(m, n, 3, random);
    for (const std::size_t limit : {std::size_t{100000}, std::size_t{0}}) {
      if (limit > 0 && n > 400) continue;  // the dense path on 1500 columns: seconds, not needed
      fem::DependentColumnsOptions options;
      options.dense_group_limit = limit;
      const fem::DependentColumns found = fem::dependent_columns(a, {}, options);
      EXPECT_EQ(found.columns.size(), static_cast<std::size_t>(n - m)) << n << " columns, limit " << limit;
      EXPECT_EQ(found.largest_group, static_cast<std::size_t>(n));
      EXPECT_EQ(found.sparse_groups, limit == 0 ? 1u : 0u);
      expect_written_in_kept(a, found, {});
    }
  }
}

TEST(DependentColumns, ColumnsReplacedByCombinationsAreFoundInALargeGroup) {
  std::mt19937 random(11);
  const Eigen::Index n = 5000, m = 2 * n;
  SparseMatrix a = cyclic_band(m, n, 4, random);  // rows 2j .. 2j+3: full column rank
  // Seven columns become combinations of two or three others (far apart, so the group stays
  // connected through the band).
  std::vector<Eigen::Index> replaced = {17, 901, 1777, 2500, 3333, 4100, 4999};
  for (const Eigen::Index j : replaced) {
    Eigen::VectorXd combination =
        0.7 * Eigen::VectorXd(a.col((j + 1) % n)) - 1.3 * Eigen::VectorXd(a.col((j + 2) % n));
    if (j % 2) combination += 0.25 * Eigen::VectorXd(a.col((j + 1000) % n));
    for (SparseMatrix::InnerIterator it(a, j); it; ++it) it.valueRef() = 0;
    for (Eigen::Index r = 0; r < m; ++r)
      if (combination(r) != 0) a.coeffRef(r, j) = combination(r);
  }
  a.prune(0.0);
  a.makeCompressed();
  const fem::DependentColumns found = fem::dependent_columns(a, {});
  EXPECT_EQ(found.columns.size(), replaced.size());
  EXPECT_GE(found.sparse_groups, 1u);
  EXPECT_GT(found.largest_group, fem::DependentColumnsOptions{}.dense_group_limit);
  expect_written_in_kept(a, found, {});
  // The kept columns have full rank: their normal matrix's pivoted factor finds no zero pivot
  // (checked on the dense path's own algorithm, independently of the sparse QR).
  std::vector<Eigen::Index> kept;
  const std::set<std::int32_t> out(found.columns.begin(), found.columns.end());
  for (Eigen::Index j = 0; j < 600; ++j)  // a window of the band, with columns 17 and 501
    if (!out.count(static_cast<std::int32_t>(j))) kept.push_back(j);
  Eigen::MatrixXd window = Eigen::MatrixXd::Zero(m, static_cast<Eigen::Index>(kept.size()));
  for (std::size_t k = 0; k < kept.size(); ++k) window.col(static_cast<Eigen::Index>(k)) = a.col(kept[k]);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(window);
  qr.setThreshold(1e-10);
  EXPECT_EQ(qr.rank(), window.cols());
}

TEST(DependentColumns, RowsNotUsedAreIgnoredAndZeroColumnsLeftOut) {
  std::mt19937 random(3);
  const Eigen::Index n = 60, m = n - 2;
  SparseMatrix band = cyclic_band(m, n, 3, random);
  // Two extra rows, one entry each on columns 5 and 9: with them, the columns have full rank
  // (5 and 9 are peeled, then the rest ...); unused, the surplus is 2 again.
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index j = 0; j < n; ++j)
    for (SparseMatrix::InnerIterator it(band, j); it; ++it) entries.emplace_back(it.row(), j, it.value());
  entries.emplace_back(m, 5, 1.0);
  entries.emplace_back(m + 1, 9, 1.0);
  SparseMatrix a(m + 2, n + 1);  // and column n, zero on every row
  a.setFromTriplets(entries.begin(), entries.end());
  std::vector<char> every(static_cast<std::size_t>(m + 2), 1), band_rows = every;
  band_rows[static_cast<std::size_t>(m)] = band_rows[static_cast<std::size_t>(m + 1)] = 0;
  const fem::DependentColumns with_extra = fem::dependent_columns(a, every);
  const fem::DependentColumns without = fem::dependent_columns(a, band_rows);
  // With the extra rows: rank m + 2 of n columns with entries, plus the zero column.
  EXPECT_EQ(with_extra.columns.size(), static_cast<std::size_t>(n - (m + 2)) + 1);
  EXPECT_EQ(without.columns.size(), static_cast<std::size_t>(n - m) + 1);
  EXPECT_TRUE(
      std::binary_search(without.columns.begin(), without.columns.end(), static_cast<std::int32_t>(n)));
  expect_written_in_kept(a, with_extra, every);
  expect_written_in_kept(a, without, band_rows);
}

}  // namespace
}  // namespace rgbmesh
