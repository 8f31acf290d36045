// The truncated hierarchical basis of the adaptive Loop space (LoopBasisKind::
// truncated_hierarchical): its cells, its dependent functions, its expansion.

#include <Eigen/QR>
#include <algorithm>
#include <stdexcept>

#include "loop_control_net.hpp"

namespace rgbmesh::fem {

namespace {

using detail::Cell;
using detail::ControlNet;

// The columns of `e` that depend on the others on the rows `used` (the control values the
// cells read), to be left out. Truncated functions near a vertex of high valence can be
// linearly dependent (Loop's functions are not locally independent there: on anchor.off a
// valence-34 vertex made three neighbours' truncated level-0 functions sum to three times a
// fourth's). A column that is alone on some row takes part in no dependency, and neither does
// one left alone once such columns are set aside; what remains after peeling them (functions
// at the levels' interfaces, a few percent) is ranked by a pivoted QR.
// Each dependent column is also written in the kept ones of its group (`in_kept`: kept column,
// dependent column, weight), so that a function of the whole set (the constant, the sum of all)
// can be written in the kept ones.
struct Dependency {
  std::int32_t kept = 0, dependent = 0;
  double weight = 0;
};
std::vector<std::int32_t> dependent_columns(const SparseMatrix& e, const std::vector<char>& used,
                                            std::vector<Dependency>& in_kept) {
  const std::size_t m = static_cast<std::size_t>(e.rows()), n = static_cast<std::size_t>(e.cols());
  std::vector<std::int32_t> count(m, 0);
  for (std::size_t j = 0; j < n; ++j)
    for (SparseMatrix::InnerIterator it(e, static_cast<Eigen::Index>(j)); it; ++it)
      if (used[static_cast<std::size_t>(it.row())] && it.value() != 0)
        ++count[static_cast<std::size_t>(it.row())];
  // The columns of each row (CSR of the used part).
  std::vector<std::size_t> start(m + 1, 0);
  for (std::size_t r = 0; r < m; ++r) start[r + 1] = start[r] + static_cast<std::size_t>(count[r]);
  std::vector<std::int32_t> columns(start[m]);
  {
    std::vector<std::size_t> at(start.begin(), start.end() - 1);
    for (std::size_t j = 0; j < n; ++j)
      for (SparseMatrix::InnerIterator it(e, static_cast<Eigen::Index>(j)); it; ++it)
        if (used[static_cast<std::size_t>(it.row())] && it.value() != 0)
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
    for (SparseMatrix::InnerIterator it(e, j); it; ++it) {
      const auto row = static_cast<std::size_t>(it.row());
      if (used[row] && it.value() != 0 && --count[row] == 1) queue.push_back(row);
    }
  }
  std::vector<std::int32_t> left;
  for (std::size_t j = 0; j < n; ++j)
    if (alive[j]) left.push_back(static_cast<std::int32_t>(j));
  if (left.empty()) return {};
  // The columns left fall apart into groups that share no row: each is ranked alone.
  std::vector<std::int32_t> parent(n);
  for (std::size_t j = 0; j < n; ++j) parent[j] = static_cast<std::int32_t>(j);
  const auto root = [&parent](std::int32_t j) {
    while (parent[static_cast<std::size_t>(j)] != j)
      j = parent[static_cast<std::size_t>(j)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(j)])];
    return j;
  };
  std::vector<std::int32_t> first_on_row(m, -1);
  for (const std::int32_t j : left)
    for (SparseMatrix::InnerIterator it(e, j); it; ++it) {
      const auto row = static_cast<std::size_t>(it.row());
      if (!used[row] || it.value() == 0) continue;
      if (first_on_row[row] < 0) {
        first_on_row[row] = j;
      } else {
        const std::int32_t a = root(j), b = root(first_on_row[row]);
        if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
      }
    }
  std::vector<std::pair<std::int32_t, std::int32_t>> by_group;  // (group, column)
  for (const std::int32_t j : left) by_group.emplace_back(root(j), j);
  std::sort(by_group.begin(), by_group.end());
  std::vector<std::int32_t> out, row_of(m, -1), rows, group;
  for (std::size_t g = 0; g < by_group.size();) {
    group.clear();
    std::size_t h = g;
    for (; h < by_group.size() && by_group[h].first == by_group[g].first; ++h)
      group.push_back(by_group[h].second);
    g = h;
    if (group.size() == 1) continue;  // a column with entries is independent on its own
    rows.clear();
    for (const std::int32_t j : group)
      for (SparseMatrix::InnerIterator it(e, j); it; ++it) {
        const auto row = static_cast<std::size_t>(it.row());
        if (used[row] && it.value() != 0 && row_of[row] < 0) {
          row_of[row] = static_cast<std::int32_t>(rows.size());
          rows.push_back(static_cast<std::int32_t>(row));
        }
      }
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()),
                                                  static_cast<Eigen::Index>(group.size()));
    for (std::size_t k = 0; k < group.size(); ++k)
      for (SparseMatrix::InnerIterator it(e, group[k]); it; ++it)
        if (used[static_cast<std::size_t>(it.row())] && it.value() != 0)
          dense(row_of[static_cast<std::size_t>(it.row())], static_cast<Eigen::Index>(k)) = it.value();
    for (const std::int32_t r : rows) row_of[static_cast<std::size_t>(r)] = -1;
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(dense);
    qr.setThreshold(1e-10);
    const Eigen::Index rank = qr.rank();
    if (rank == dense.cols()) continue;
    const auto& order = qr.colsPermutation().indices();
    Eigen::MatrixXd basis(dense.rows(), rank), dependent(dense.rows(), dense.cols() - rank);
    for (Eigen::Index k = 0; k < rank; ++k) basis.col(k) = dense.col(order(k));
    for (Eigen::Index k = rank; k < dense.cols(); ++k) {
      dependent.col(k - rank) = dense.col(order(k));
      out.push_back(group[static_cast<std::size_t>(order(k))]);
    }
    const Eigen::MatrixXd weights = basis.colPivHouseholderQr().solve(dependent);
    for (Eigen::Index d = 0; d < weights.cols(); ++d)
      for (Eigen::Index k = 0; k < rank; ++k)
        if (weights(k, d) != 0)
          in_kept.push_back({group[static_cast<std::size_t>(order(k))],
                             group[static_cast<std::size_t>(order(rank + d))], weights(k, d)});
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

// The cells of the truncated hierarchical basis from the full tree (whose splits decided the
// domains): the nodes in `whole` become cells, their subtrees dropped. The tree is renumbered
// breadth first from the base triangles (nodes 0 .. T0 - 1 stay theirs), so that the cells
// stay in order of level, as the full tree's leaves are.
void detail::integrate_whole(AdaptiveLoopSpace& space, std::size_t roots, std::vector<std::int32_t>& whole,
                             std::vector<Cell>& kept, const std::vector<int>& kept_level,
                             std::vector<Cell>& leaves, std::vector<int>& leaf_level) {
  whole.resize(space.tree.size(), -1);
  const std::vector<AdaptiveLoopSpace::Node> full = std::move(space.tree);
  std::vector<Cell> full_leaves = std::move(leaves);
  const std::vector<int> full_level = std::move(leaf_level);
  const std::vector<std::array<VertexHandle, 3>> full_anchors = std::move(space.anchors);
  leaves.clear(), leaf_level.clear(), space.anchors.clear();
  std::vector<std::int32_t> queue;  // the full tree's node of each new node
  for (std::size_t r = 0; r < roots; ++r) queue.push_back(static_cast<std::int32_t>(r));
  space.tree.assign(roots, {});
  for (std::size_t at = 0; at < queue.size(); ++at) {
    const auto old = static_cast<std::size_t>(queue[at]);
    const bool is_whole = whole[old] >= 0;
    if (is_whole || full[old].cell >= 0) {
      const auto k = static_cast<std::size_t>(is_whole ? whole[old] : full[old].cell);
      space.tree[at].cell = static_cast<std::int32_t>(leaves.size());
      Cell c = std::move(is_whole ? kept[k] : full_leaves[k]);
      c.node = static_cast<std::int32_t>(at);
      space.anchors.push_back(is_whole ? c.anchors : full_anchors[k]);
      leaves.push_back(std::move(c));
      leaf_level.push_back(is_whole ? kept_level[k] : full_level[k]);
    } else {
      space.tree[at].first_child = static_cast<std::int32_t>(space.tree.size());
      for (std::int32_t k = 0; k < 4; ++k) queue.push_back(full[old].first_child + k);
      space.tree.resize(space.tree.size() + 4);
    }
  }
}

// The truncated hierarchical basis (LoopBasisKind::truncated_hierarchical): the active
// functions in the order the control vertices were found (level by level), and the expansion
// x_l = T_l S x_{l-1} + the active level-l coefficients, row by row. A control vertex whose
// function lies in Ω_l takes its own coefficient if it is active and nothing if it is covered
// (finer functions carry the values there: the truncation T_l); any other takes its rule's
// combination of the rows one level up.
void detail::truncated_hierarchical_basis(const ControlNet& net, const RgbMesh& mesh,
                                          const std::vector<Cell>& cells, AdaptiveLoopSpace& space) {
  const std::size_t m = net.vertex.size();
  space.basis = LoopBasisKind::truncated_hierarchical;
  std::vector<std::int32_t> own(m, -1);
  std::vector<char> predicted(m);
  std::size_t n = 0;
  for (std::size_t r = 0; r < m; ++r) {
    const AdaptiveLoopSpace::ControlVertex& v = net.vertex[r];
    predicted[r] = !v.in_domain;
    if (!v.in_domain || v.covered) continue;
    if (!v.vertex.valid())
      throw std::logic_error("build_adaptive_loop_space: an active function at no RGB vertex");
    own[r] = static_cast<std::int32_t>(n++);
  }
  space.expansion = expand(net, own, predicted, n);
  std::vector<char> used(m, 0);
  for (const Cell& c : cells)
    for (const std::int32_t d : c.vertices) used[static_cast<std::size_t>(d)] = 1;
  std::vector<Dependency> in_kept;
  const std::vector<std::int32_t> dependent = dependent_columns(space.expansion, used, in_kept);
  space.dependent_left_out = dependent.size();
  space.constant_coefficients = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(n));
  if (!dependent.empty()) {
    // The functions sum to one; with the dependent ones written in the kept ones, so does the
    // kept ones' combination below.
    for (const Dependency& d : in_kept) space.constant_coefficients(d.kept) += d.weight;
    std::vector<std::int32_t> renumber(n, -1);
    std::vector<char> out(n, 0);
    for (const std::int32_t j : dependent) out[static_cast<std::size_t>(j)] = 1;
    std::size_t kept = 0;
    for (std::size_t j = 0; j < n; ++j)
      if (!out[j])
        space.constant_coefficients(static_cast<Eigen::Index>(kept)) =
            space.constant_coefficients(static_cast<Eigen::Index>(j)),
        renumber[j] = static_cast<std::int32_t>(kept++);
    space.constant_coefficients.conservativeResize(static_cast<Eigen::Index>(kept));
    for (std::size_t r = 0; r < m; ++r)
      if (own[r] >= 0) own[r] = renumber[static_cast<std::size_t>(own[r])];
    n = kept;
    space.expansion = expand(net, own, predicted, n);
  }
  space.vertex.clear();
  space.num_base = 0;
  space.coefficient_of_vertex.assign(static_cast<std::size_t>(mesh.vertex_slots()), -1);
  space.coefficient_control.clear();
  space.coefficient_level.clear();
  for (std::size_t r = 0; r < m; ++r) {
    if (own[r] < 0) continue;
    const AdaptiveLoopSpace::ControlVertex& v = net.vertex[r];
    space.coefficient_of_vertex[static_cast<std::size_t>(v.vertex.idx)] = own[r];
    space.vertex.push_back(v.vertex);
    space.coefficient_control.push_back(static_cast<std::int32_t>(r));
    space.coefficient_level.push_back(v.level);
  }
  space.truncated_expansion = space.expansion;
  // The hierarchical (untruncated) view of the same functions, for the details that coarsening
  // weighs: a THB coefficient is the value, at its control vertex, of the untruncated sum of the
  // functions of its level and coarser (THB's preservation of coefficients), so the sums'
  // control values take the coefficients where functions are and their rules elsewhere, and a
  // function's detail is its coefficient less its rule's prediction from the level above.
  for (std::size_t r = 0; r < m; ++r) predicted[r] = own[r] < 0;
  space.accumulated = expand(net, own, predicted, n);
  std::vector<Eigen::Triplet<double, SparseMatrix::StorageIndex>> entries;
  for (std::size_t i = 0; i < n; ++i) {
    const auto r = static_cast<std::size_t>(space.coefficient_control[i]);
    for (std::size_t k = net.rule_start[r]; k < net.rule_start[r + 1]; ++k)
      entries.emplace_back(static_cast<SparseMatrix::StorageIndex>(i), net.rule[k].first, net.rule[k].second);
  }
  space.prediction.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(m));
  space.prediction.setFromTriplets(entries.begin(), entries.end());
}

}  // namespace rgbmesh::fem
