// The truncated hierarchical basis of the adaptive Loop space (LoopBasisKind::
// truncated_hierarchical): its cells, its dependent functions, its expansion.

#include <algorithm>
#include <stdexcept>

#include "loop_control_net.hpp"
#include "rgbmesh/fem/dependent_columns.hpp"

namespace rgbmesh::fem {

namespace {

using detail::Cell;
using detail::ControlNet;

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
  // Truncated functions near a vertex of high valence can be linearly dependent (Loop's
  // functions are not locally independent there: on anchor.off a valence-34 vertex made three
  // neighbours' truncated level-0 functions sum to three times a fourth's); they are left out.
  const DependentColumns found = dependent_columns(space.expansion, used);
  const std::vector<std::int32_t>& dependent = found.columns;
  space.dependent_left_out = dependent.size();
  space.constant_coefficients = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(n));
  if (!dependent.empty()) {
    // The functions sum to one; with the dependent ones written in the kept ones, so does the
    // kept ones' combination below.
    for (const ColumnDependency& d : found.in_kept) space.constant_coefficients(d.kept) += d.weight;
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
