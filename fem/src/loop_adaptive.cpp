// The hierarchical Loop space of an adaptive RGB mesh (see loop_adaptive.hpp).

#include "rgbmesh/fem/loop_adaptive.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <unordered_map>

#include "edge_key.hpp"
#include "for_each_index.hpp"
#include "loop_assembly.hpp"
#include "loop_control_net.hpp"
#include "rgbmesh/canonical.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/loop_rules.hpp"
#include "rgbmesh/timing.hpp"

namespace rgbmesh::fem {

namespace {

using detail::Cell;
using detail::ControlNet;

// The RGB vertices among a cell's corners, packed first; the parent's if there are none.
std::array<VertexHandle, 3> anchors_of(const std::vector<std::int32_t>& vertices, const ControlNet& net,
                                       const std::array<VertexHandle, 3>& parent) {
  std::array<VertexHandle, 3> out;
  std::size_t n = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    const VertexHandle v = net.vertex[static_cast<std::size_t>(vertices[k])].vertex;
    if (v.valid()) out[n++] = v;
  }
  return n > 0 ? out : parent;
}

// Eᵀ K E, column by column on every core: K E's column j gathered over the control vertices
// coefficient j reaches, then Eᵀ of it through E's rows. Each column's sums run in a fixed
// order (the results do not depend on the threads), and no intermediate matrix is formed
// (Eigen's general products, which form K E and convert storage orders, took 8 times as long).
SparseMatrix galerkin_product(const SparseMatrix& k, const SparseMatrix& e) {
  const Eigen::SparseMatrix<double, Eigen::RowMajor> rows(e);
  const std::size_t m = static_cast<std::size_t>(e.rows()), n = static_cast<std::size_t>(e.cols());
  std::vector<std::vector<std::pair<std::int32_t, double>>> column(n);
  detail::for_each_index(n, [&](std::size_t j) {
    thread_local std::vector<double> y, acc;
    thread_local std::vector<std::int32_t> y_touched, acc_touched;
    thread_local std::vector<char> y_seen, acc_seen;
    if (y.size() < m) y.assign(m, 0.0), y_seen.assign(m, 0);
    if (acc.size() < n) acc.assign(n, 0.0), acc_seen.assign(n, 0);
    y_touched.clear();
    acc_touched.clear();
    for (SparseMatrix::InnerIterator ej(e, static_cast<Eigen::Index>(j)); ej; ++ej)
      for (SparseMatrix::InnerIterator kk(k, ej.row()); kk; ++kk) {
        const auto r = static_cast<std::size_t>(kk.row());
        if (!y_seen[r]) y_seen[r] = 1, y_touched.push_back(static_cast<std::int32_t>(r));
        y[r] += kk.value() * ej.value();
      }
    for (const std::int32_t r : y_touched) {
      const double yr = y[static_cast<std::size_t>(r)];
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator er(rows, r); er; ++er) {
        const auto i = static_cast<std::size_t>(er.col());
        if (!acc_seen[i]) acc_seen[i] = 1, acc_touched.push_back(static_cast<std::int32_t>(i));
        acc[i] += er.value() * yr;
      }
      y[static_cast<std::size_t>(r)] = 0, y_seen[static_cast<std::size_t>(r)] = 0;
    }
    std::sort(acc_touched.begin(), acc_touched.end());
    auto& out = column[j];
    out.reserve(acc_touched.size());
    for (const std::int32_t i : acc_touched) {
      out.emplace_back(i, acc[static_cast<std::size_t>(i)]);
      acc[static_cast<std::size_t>(i)] = 0, acc_seen[static_cast<std::size_t>(i)] = 0;
    }
  });
  SparseMatrix a(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  std::size_t nonzeros = 0;
  for (const auto& c : column) nonzeros += c.size();
  a.resizeNonZeros(static_cast<Eigen::Index>(nonzeros));
  std::size_t at = 0;
  for (std::size_t j = 0; j < n; ++j) {
    a.outerIndexPtr()[j] = static_cast<SparseMatrix::StorageIndex>(at);
    for (const auto& [i, v] : column[j]) {
      a.innerIndexPtr()[at] = i;
      a.valuePtr()[at++] = v;
    }
    std::vector<std::pair<std::int32_t, double>>().swap(column[j]);
  }
  a.outerIndexPtr()[n] = static_cast<SparseMatrix::StorageIndex>(at);
  return a;
}

// The details' basis (LoopBasisKind::details) on the coefficients numbered by the caller. Every
// control vertex is kept, those only the split cells use too: they are the chain from the base
// that each value comes down (ControlVertex::origin), and cost no matrix entries.
// Hierarchical: an inserted vertex adds its coefficient (a detail) to the value its rule gives
// it. Truncated: an inserted vertex's value is its coefficient, so coarser functions stop where
// finer ones take over.
void details_basis(const ControlNet& net, const RgbMesh& mesh, AdaptiveLoopSpace& space) {
  const std::size_t m = net.vertex.size(), n = space.num_dofs();
  space.coefficient_control.assign(n, -1);
  std::vector<std::int32_t> own(m, -1);
  for (std::size_t r = 0; r < m; ++r) {
    const AdaptiveLoopSpace::ControlVertex& v = net.vertex[r];
    if (v.vertex.valid() && mesh.level(v.vertex) == v.level) {
      own[r] = space.coefficient_of_vertex[static_cast<std::size_t>(v.vertex.idx)];
      space.coefficient_control[static_cast<std::size_t>(own[r])] = static_cast<std::int32_t>(r);
    }
  }
  space.coefficient_level.clear();
  for (const VertexHandle v : space.vertex) space.coefficient_level.push_back(mesh.level(v));
  space.expansion = detail::expand(net, own, std::vector<char>(m, 1), n);
  std::vector<char> predicted(m);
  for (std::size_t r = 0; r < m; ++r) predicted[r] = own[r] < 0;
  space.truncated_expansion = detail::expand(net, own, predicted, n);
  // The prediction of each inserted vertex: the rule of its control vertex.
  std::vector<Eigen::Triplet<double, SparseMatrix::StorageIndex>> entries;
  for (std::size_t i = 0; i < n; ++i) {
    if (space.coefficient_control[i] < 0)
      throw std::logic_error("build_adaptive_loop_space: an inserted vertex without its control vertex");
    if (i < space.num_base) continue;
    const auto r = static_cast<std::size_t>(space.coefficient_control[i]);
    for (std::size_t k = net.rule_start[r]; k < net.rule_start[r + 1]; ++k)
      entries.emplace_back(static_cast<SparseMatrix::StorageIndex>(i), net.rule[k].first, net.rule[k].second);
  }
  space.prediction.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(m));
  space.prediction.setFromTriplets(entries.begin(), entries.end());
}

// The diagonal of Eᵀ K E without the product: each column's eⱼᵀ K eⱼ.
Eigen::VectorXd galerkin_diagonal(const SparseMatrix& k, const SparseMatrix& e) {
  Eigen::VectorXd d(e.cols());
  detail::for_each_index(static_cast<std::size_t>(e.cols()), [&](std::size_t j) {
    thread_local std::vector<double> dense;
    if (dense.size() < static_cast<std::size_t>(e.rows()))
      dense.assign(static_cast<std::size_t>(e.rows()), 0.0);
    for (SparseMatrix::InnerIterator ej(e, static_cast<Eigen::Index>(j)); ej; ++ej)
      dense[static_cast<std::size_t>(ej.row())] = ej.value();
    double sum = 0;
    for (SparseMatrix::InnerIterator ej(e, static_cast<Eigen::Index>(j)); ej; ++ej)
      for (SparseMatrix::InnerIterator kk(k, ej.row()); kk; ++kk)
        sum += ej.value() * kk.value() * dense[static_cast<std::size_t>(kk.row())];
    for (SparseMatrix::InnerIterator ej(e, static_cast<Eigen::Index>(j)); ej; ++ej)
      dense[static_cast<std::size_t>(ej.row())] = 0;
    d(static_cast<Eigen::Index>(j)) = sum;
  });
  return d;
}

// The cells' sides along base edge side `side` of tree node `node`, which covers [t0, t1] of
// the base side (both run the same way: a child's sides on its parent's run as the parent's).
// Per cell side: the cell, its side, and its stretch of the base side.
struct CellSide {
  std::size_t cell = 0;
  int edge = 0;
  double t0 = 0, t1 = 0;
};
void cell_sides(const AdaptiveLoopSpace& space, std::size_t node, int side, double t0, double t1,
                std::vector<CellSide>& out) {
  const AdaptiveLoopSpace::Node& at = space.tree[node];
  if (at.cell >= 0) {
    out.push_back({static_cast<std::size_t>(at.cell), side, t0, t1});
    return;
  }
  // Children 0-2 sit at corners 0-2 (loop_child_patch's numbering): side k of the parent is
  // side k of child k (its first half) and of child k + 1 (its second half).
  const double mid = 0.5 * (t0 + t1);
  const auto first = static_cast<std::size_t>(at.first_child);
  cell_sides(space, first + static_cast<std::size_t>(side), side, t0, mid, out);
  cell_sides(space, first + static_cast<std::size_t>((side + 1) % 3), side, mid, t1, out);
}

// The seams of the cells: along each infinitely sharp base edge, the cells of its two base
// triangles paired where their sides overlap (cells of different levels meet there).
std::vector<LoopSpace::Seam> seams_of(const AdaptiveLoopSpace& space, const RgbMesh& mesh) {
  std::vector<LoopSpace::Seam> seams;
  const auto& base = mesh.base_triangles();
  for (const SharpEdge& e : mesh.sharp_features().edges) {
    if (!loop::is_infinitely_sharp(e.sharpness)) continue;
    // The two base triangles with their sides along a -> b (t from a to b).
    std::array<std::vector<CellSide>, 2> sides;
    int found = 0;
    for (std::size_t t = 0; t < base.size() && found < 2; ++t) {
      for (int k = 0; k < 3; ++k) {
        const std::int32_t p = base[t][static_cast<std::size_t>(k)],
                           q = base[t][static_cast<std::size_t>((k + 1) % 3)];
        if (!((p == e.a && q == e.b) || (p == e.b && q == e.a))) continue;
        std::vector<CellSide>& list = sides[static_cast<std::size_t>(found++)];
        if (p == e.a)
          cell_sides(space, t, k, 0.0, 1.0, list);
        else
          cell_sides(space, t, k, 1.0, 0.0, list);
      }
    }
    if (found != 2) throw std::logic_error("build_adaptive_loop_space: a sharp edge without two triangles");
    // Overlaps of the two sides' stretches, each side's parameters at the overlap's ends.
    for (const CellSide& x : sides[0])
      for (const CellSide& y : sides[1]) {
        const double lo = std::max(std::min(x.t0, x.t1), std::min(y.t0, y.t1));
        const double hi = std::min(std::max(x.t0, x.t1), std::max(y.t0, y.t1));
        if (!(hi > lo)) continue;
        const auto along = [](const CellSide& c, double t) { return (t - c.t0) / (c.t1 - c.t0); };
        seams.push_back(
            {{x.cell, y.cell}, {x.edge, y.edge}, {along(x, lo), along(y, lo)}, {along(x, hi), along(y, hi)}});
      }
  }
  return seams;
}

}  // namespace

// The control values' expansion in the coefficients, row by row in the order the control
// vertices were found (every rule refers to earlier rows): a row is its rule's combination of
// the rows one level up where `predicted`, plus its own coefficient where it has one (`own`).
SparseMatrix detail::expand(const ControlNet& net, const std::vector<std::int32_t>& own,
                            const std::vector<char>& predicted, std::size_t n) {
  const std::size_t m = net.vertex.size();
  // Built as rows (compressed, each in column order), read back by the rows after them.
  std::vector<SparseMatrix::StorageIndex> row_start{0}, columns;
  std::vector<double> values;
  std::vector<double> dense(n, 0.0);
  std::vector<char> seen(n, 0);
  std::vector<std::int32_t> touched;
  for (std::size_t r = 0; r < m; ++r) {
    touched.clear();
    const auto add = [&](std::int32_t col, double w) {
      const auto c = static_cast<std::size_t>(col);
      if (!seen[c]) touched.push_back(col), seen[c] = 1;
      dense[c] += w;
    };
    if (predicted[r])
      for (std::size_t k = net.rule_start[r]; k < net.rule_start[r + 1]; ++k) {
        const auto from = static_cast<std::size_t>(net.rule[k].first);
        for (auto at = static_cast<std::size_t>(row_start[from]);
             at < static_cast<std::size_t>(row_start[from + 1]); ++at)
          add(columns[at], net.rule[k].second * values[at]);
      }
    if (own[r] >= 0) add(own[r], 1.0);
    std::sort(touched.begin(), touched.end());
    for (const std::int32_t col : touched) {
      const auto c = static_cast<std::size_t>(col);
      columns.push_back(col);
      values.push_back(dense[c]);
      dense[c] = 0, seen[c] = 0;
    }
    row_start.push_back(static_cast<SparseMatrix::StorageIndex>(columns.size()));
  }
  return Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>>(
      static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(values.size()),
      row_start.data(), columns.data(), values.data());
}

Eigen::VectorXd AdaptiveLoopSpace::hierarchical_coefficients(const Eigen::VectorXd& truncated) const {
  const SparseMatrix& values =
      basis == LoopBasisKind::truncated_hierarchical ? accumulated : truncated_expansion;
  return truncated - prediction * (values * truncated);
}

Eigen::VectorXd AdaptiveLoopSpace::truncated_coefficients(const Eigen::VectorXd& hierarchical) const {
  if (basis == LoopBasisKind::truncated_hierarchical) {
    // c = a + prediction (accumulated c): a function's prediction reads only coarser levels'
    // functions, so one pass per level makes it exact.
    int deepest = 0;
    for (const int l : coefficient_level) deepest = std::max(deepest, l);
    Eigen::VectorXd c = hierarchical;
    for (int pass = 0; pass < deepest; ++pass) c = hierarchical + prediction * (accumulated * c);
    return c;
  }
  const Eigen::VectorXd control = expansion * hierarchical;
  Eigen::VectorXd out(hierarchical.size());
  for (Eigen::Index i = 0; i < out.size(); ++i)
    out(i) = control(coefficient_control[static_cast<std::size_t>(i)]);
  return out;
}

Eigen::VectorXd AdaptiveLoopSpace::constant() const {
  if (basis == LoopBasisKind::truncated_hierarchical) return constant_coefficients;
  Eigen::VectorXd one = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(num_dofs()));
  one.head(static_cast<Eigen::Index>(num_base)).setOnes();
  return one;
}

AdaptiveLoopSpace build_adaptive_loop_space(const RgbMesh& mesh, std::optional<Projection> projection,
                                            const LoopQuadratureOptions& quadrature, LoopBasisKind basis) {
  if (quadrature.points_per_direction < 0 || quadrature.points_per_direction > 20 ||
      quadrature.extraordinary_depth < 0 || quadrature.extraordinary_depth > 20)
    throw std::invalid_argument(
        "build_adaptive_loop_space: points per direction in [0, 20], depth in [0, 20]");
  AdaptiveLoopSpace space;
  space.cells.projection = std::move(projection);
  space.cells.level = -1;

  // The coefficients: base vertices first, each group in canonical order (a resumed run
  // numbers them as the uninterrupted one).
  std::vector<VertexHandle> order = canonical_vertex_order(mesh);
  std::stable_partition(order.begin(), order.end(), [&mesh](VertexHandle v) { return mesh.level(v) == 0; });
  space.coefficient_of_vertex.assign(static_cast<std::size_t>(mesh.vertex_slots()), -1);
  std::unordered_map<std::uint64_t, std::int32_t> midpoint;  // parents' slots -> inserted vertex
  for (const VertexHandle v : order) {
    space.coefficient_of_vertex[static_cast<std::size_t>(v.idx)] =
        static_cast<std::int32_t>(space.vertex.size());
    space.vertex.push_back(v);
    if (mesh.level(v) == 0) {
      ++space.num_base;
    } else {
      const auto& p = mesh.parents(v);
      midpoint.emplace(detail::edge_key(p[0].idx, p[1].idx), v.idx);
    }
  }

  // Level 0: the base triangles, whose corners are base vertices (slot = index in the input).
  ControlNet net;
  const std::size_t base_count = mesh.num_base_vertices();
  for (std::size_t i = 0; i < base_count; ++i) {
    const VertexHandle v(static_cast<std::int32_t>(i));
    AdaptiveLoopSpace::ControlVertex cv;
    cv.vertex = v;
    net.add(cv, mesh.control_point(v, 0));
  }
  const RingOracle base_rings = triangle_rings(static_cast<std::int32_t>(base_count), mesh.base_triangles());
  // Sharp features reach the cells through their base patches: every child patch carries what
  // its rules need (LoopCreases), level by level.
  const LoopFeatures features =
      mesh.has_sharp_features() ? tagged_features(mesh.sharp_features()) : LoopFeatures{};
  std::vector<LoopPatch> base_patches;
  base_patches.reserve(mesh.base_triangles().size());
  for (const auto& t : mesh.base_triangles()) {
    try {
      base_patches.push_back(gather_loop_patch({t[0], t[1], t[2]}, base_rings, features));
    } catch (const InputError& e) {
      // The space builds on the base mesh, whatever the refinement: refining the RGB mesh
      // does not help, a finer base does.
      std::string why = e.what();
      const std::string coarse = "(the mesh is too coarse there; refine it once)";
      const auto at = why.find(coarse);
      if (at != std::string::npos)
        why.replace(at, coarse.size(),
                    "(the base mesh is too coarse there: refine it once and start from that, e.g. "
                    "rgbmesh refine MESH base.obj --uniform 1, which writes a new base)");
      throw InputError(why);
    }
  }
  std::vector<Cell> level_cells;
  for (const LoopPatch& patch : base_patches) {
    Cell c;
    c.shape = &patch;
    c.vertices = patch.vertices;
    c.anchors = anchors_of(c.vertices, net, {});
    c.node = static_cast<std::int32_t>(space.tree.size());
    space.tree.emplace_back();
    level_cells.push_back(std::move(c));
  }

  // Level by level: a cell is split when a child's patch holds a vertex the RGB mesh inserted
  // at the child's level; otherwise it is an integration cell.
  std::vector<Cell> leaves;
  std::vector<int> leaf_level;
  // Split nodes that the truncated hierarchical basis integrates whole: per node, its index in
  // `kept` (-1: none).
  std::vector<std::int32_t> whole;
  std::vector<Cell> kept;
  std::vector<int> kept_level;
  const auto rgb_midpoint = [&](std::int32_t a, std::int32_t b) -> std::int32_t {
    const VertexHandle va = net.vertex[static_cast<std::size_t>(a)].vertex,
                       vb = net.vertex[static_cast<std::size_t>(b)].vertex;
    if (!va.valid() || !vb.valid()) return -1;
    const auto it = midpoint.find(detail::edge_key(va.idx, vb.idx));
    return it == midpoint.end() ? -1 : it->second;
  };
  // The children of each connectivity met, asked once (the lookups by connectivity copy it),
  // with the parent's edges whose midpoints they hold, each once: four children's patches name
  // about 20 distinct midpoints in 36 places, and each is looked up once a cell instead.
  struct Children {
    std::array<std::shared_ptr<const LoopChildPatch>, 4> kid;
    std::size_t odd_edges = 0;
    std::array<std::vector<std::int32_t>, 4> odd;  // per child vertex: its edge's index, -1 if even
  };
  std::unordered_map<const LoopPatch*, Children> children_of;
  // Per edge of the cell: its RGB midpoint (-2 until looked up, -1 for none) and its control
  // vertex a level down (-1 until found).
  std::vector<std::int32_t> odd_rgb, odd_control;
  for (int level = 0; !level_cells.empty(); ++level) {
    std::vector<Cell> next;
    for (Cell& cell : level_cells) {
      // The domains of the truncated hierarchical basis: the cell is in Ω_level when its
      // corners are RGB vertices, its children all in Ω_level+1 when its edges' midpoints are.
      // A function is in a domain when every cell of its level whose patch holds it is (the
      // cells that exist: a triangle of that level outside the tree is outside both domains,
      // and one of its neighbours in the tree then is too).
      {
        const std::array<std::int32_t, 3> c{cell.vertices[0], cell.vertices[1], cell.vertices[2]};
        bool inside = true, covered = true;
        for (std::size_t k = 0; k < 3; ++k) {
          inside = inside && net.vertex[static_cast<std::size_t>(c[k])].vertex.valid();
          covered = covered && rgb_midpoint(c[k], c[(k + 1) % 3]) >= 0;
        }
        for (const std::int32_t w : cell.vertices) {
          AdaptiveLoopSpace::ControlVertex& cv = net.vertex[static_cast<std::size_t>(w)];
          cv.in_domain = cv.in_domain && inside;
          cv.covered = cv.covered && covered;
        }
      }
      auto [found, fresh] = children_of.try_emplace(cell.shape);
      if (fresh) {
        Children& c = found->second;
        std::map<std::pair<int, int>, std::int32_t> index;
        for (std::size_t k = 0; k < 4; ++k) {
          c.kid[k] = loop_child_patch(*cell.shape, static_cast<int>(k));
          for (const auto& o : c.kid[k]->origin) {
            std::int32_t at = -1;
            if (o[1] >= 0)
              at = index
                       .try_emplace({std::min(o[0], o[1]), std::max(o[0], o[1])},
                                    static_cast<std::int32_t>(index.size()))
                       .first->second;
            c.odd[k].push_back(at);
          }
        }
        c.odd_edges = index.size();
      }
      const Children& children = found->second;
      const auto& kids = children.kid;
      odd_rgb.assign(children.odd_edges, -2);
      odd_control.assign(children.odd_edges, -1);
      const auto rgb_midpoint_of = [&](std::size_t k, std::size_t i) {
        std::int32_t& m = odd_rgb[static_cast<std::size_t>(children.odd[k][i])];
        if (m == -2) {
          const auto o = kids[k]->origin[i];
          m = rgb_midpoint(cell.vertices[static_cast<std::size_t>(o[0])],
                           cell.vertices[static_cast<std::size_t>(o[1])]);
        }
        return m;
      };
      // A cell with two or three irregular corners is split once whatever the mesh: its
      // children have one at most. The function is the same on the children (their control
      // values are the parent's subdivided), and a quadrature rule is built per patch
      // connectivity, which with one irregular corner is that corner's fan alone: a few dozen
      // rules for any base mesh, where an irregular base (a scan, a CAD export) had one per
      // triangle (elephant-with-holes: 1,800 rules, 0.7 GB and 5 s a cycle at 2,800 unknowns).
      // (Corners whose rules change with semi-sharp features do not count: their children keep
      // them along the feature until it decays, and a patch's features make its rule its own.)
      int irregular = 0;
      for (int k = 0; k < 3; ++k)
        irregular +=
            !cell.shape->regular_corner(k) && !(cell.shape->creases && cell.shape->creases->transient(k));
      bool split = irregular >= 2;
      for (std::size_t k = 0; k < 4 && !split; ++k)
        for (std::size_t i = 0; i < kids[k]->origin.size() && !split; ++i)
          split = children.odd[k][i] >= 0 && rgb_midpoint_of(k, i) >= 0;
      if (!split) {
        space.tree[static_cast<std::size_t>(cell.node)].cell = static_cast<std::int32_t>(leaves.size());
        space.anchors.push_back(cell.anchors);
        leaves.push_back(std::move(cell));
        leaf_level.push_back(level);
        continue;
      }
      space.tree[static_cast<std::size_t>(cell.node)].first_child =
          static_cast<std::int32_t>(space.tree.size());
      bool child_in_domain = false;  // for the truncated hierarchical basis's cells
      for (std::size_t k = 0; k < 4; ++k) {
        const auto& kid = kids[k];
        Cell child;
        child.shape = &kid->patch;
        child.vertices.resize(kid->origin.size());
        child.node = static_cast<std::int32_t>(space.tree.size());
        space.tree.emplace_back();
        for (std::size_t i = 0; i < kid->origin.size(); ++i) {
          const auto o = kid->origin[i];
          const std::int32_t a = cell.vertices[static_cast<std::size_t>(o[0])];
          const std::int32_t b = o[1] < 0 ? -1 : cell.vertices[static_cast<std::size_t>(o[1])];
          std::int32_t* odd = b < 0 ? nullptr : &odd_control[static_cast<std::size_t>(children.odd[k][i])];
          std::int32_t cv = b < 0 ? net.even_child[static_cast<std::size_t>(a)] : *odd;
          if (b >= 0 && cv < 0) {
            const auto it = net.odd_child.find(detail::edge_key(a, b));
            if (it != net.odd_child.end()) cv = it->second;
          }
          if (cv < 0) {
            AdaptiveLoopSpace::ControlVertex v;
            v.level = level + 1;
            v.origin = {a, b};
            if (b < 0) {
              v.vertex = net.vertex[static_cast<std::size_t>(a)].vertex;
            } else {
              const std::int32_t slot = rgb_midpoint_of(k, i);
              if (slot >= 0) v.vertex = VertexHandle(slot);
            }
            Vec3 p;
            const auto row = kid->from_parent.row(static_cast<Eigen::Index>(i));
            for (Eigen::Index j = 0; j < row.size(); ++j) {
              if (row(j) == 0) continue;
              const std::int32_t from = cell.vertices[static_cast<std::size_t>(j)];
              net.rule.emplace_back(from, row(j));
              p += row(j) * net.point[static_cast<std::size_t>(from)];
            }
            cv = net.add(v, p);
            if (b < 0)
              net.even_child[static_cast<std::size_t>(a)] = cv;
            else
              net.odd_child.emplace(detail::edge_key(a, b), cv);
          }
          if (odd != nullptr) *odd = cv;
          child.vertices[i] = cv;
        }
        child.anchors = anchors_of(child.vertices, net, cell.anchors);
        child_in_domain =
            child_in_domain || (net.vertex[static_cast<std::size_t>(child.vertices[0])].vertex.valid() &&
                                net.vertex[static_cast<std::size_t>(child.vertices[1])].vertex.valid() &&
                                net.vertex[static_cast<std::size_t>(child.vertices[2])].vertex.valid());
        next.push_back(std::move(child));
      }
      if (basis == LoopBasisKind::truncated_hierarchical && irregular < 2 && !child_in_domain) {
        // No child in Ω_level+1: no finer function reaches the cell, and the truncated
        // hierarchical basis integrates it whole (the split above still decides the domains).
        whole.resize(space.tree.size(), -1);
        whole[static_cast<std::size_t>(cell.node)] = static_cast<std::int32_t>(kept.size());
        kept.push_back(std::move(cell));
        kept_level.push_back(level);
      }
    }
    level_cells = std::move(next);
  }
  if (!kept.empty())
    detail::integrate_whole(space, mesh.base_triangles().size(), whole, kept, kept_level, leaves, leaf_level);

  if (basis == LoopBasisKind::truncated_hierarchical) {
    detail::truncated_hierarchical_basis(net, mesh, leaves, space);
  } else {
    details_basis(net, mesh, space);
  }
  space.control_vertex = std::move(net.vertex);
  for (const AdaptiveLoopSpace::ControlVertex& v : space.control_vertex)
    space.cells.vertex.push_back(v.vertex);
  space.cells.control = std::move(net.point);

  // The cells, with their rules (one per connectivity, shared).
  space.cells.elements.resize(leaves.size());
  std::unordered_map<const LoopPatch*, std::shared_ptr<const LoopQuadrature>> rule_of;
  for (std::size_t e = 0; e < leaves.size(); ++e) {
    LoopSpace::Element& el = space.cells.elements[e];
    el.dofs = std::move(leaves[e].vertices);
    auto [found, fresh] = rule_of.try_emplace(leaves[e].shape);
    if (fresh) found->second = loop_quadrature(*leaves[e].shape, quadrature);
    el.rule = found->second;
    // A side of the cell on the surface's boundary: both ends on it, one triangle beside it
    // (with sharp features: a boundary edge, not a crease, which opens fans too).
    const LoopPatch& shape = *leaves[e].shape;
    for (int k = 0; k < 3; ++k) {
      const int a = k, b = (k + 1) % 3;
      if (!shape.open[static_cast<std::size_t>(a)] || !shape.open[static_cast<std::size_t>(b)]) continue;
      if (shape.creases) {
        const auto& spokes = shape.creases->corner[static_cast<std::size_t>(a)].spokes;
        if (std::none_of(spokes.begin(), spokes.end(),
                         [b](const LoopCreases::Spoke& s) { return s.to == b && s.boundary; }))
          continue;
      }
      const auto beside =
          std::count_if(shape.triangles.begin(), shape.triangles.end(), [a, b](const std::array<int, 3>& t) {
            return std::find(t.begin(), t.end(), a) != t.end() && std::find(t.begin(), t.end(), b) != t.end();
          });
      if (beside == 1) space.cells.boundary.push_back({e, k});
    }
  }
  space.cell_level = std::move(leaf_level);
  if (mesh.has_sharp_features()) space.cells.seams = seams_of(space, mesh);
  return space;
}

double loop_value_at(const AdaptiveLoopSpace& space, const Eigen::VectorXd& control,
                     std::size_t base_triangle, double u, double v) {
  if (base_triangle >= space.tree.size() || !(u >= 0 && v >= 0 && u + v <= 1) ||
      control.size() != static_cast<Eigen::Index>(space.control_vertex.size()))
    throw std::invalid_argument("loop_value_at: no such point, or control values of another space");
  std::size_t node = base_triangle;
  while (space.tree[node].cell < 0) {
    const int child = loop_descend(u, v);
    node = static_cast<std::size_t>(space.tree[node].first_child + child);
  }
  const LoopSpace::Element& cell = space.cells.elements[static_cast<std::size_t>(space.tree[node].cell)];
  const Eigen::VectorXd w = evaluate_loop_basis(cell.rule->patch, u, v).value;
  double sum = 0;
  for (std::size_t i = 0; i < cell.dofs.size(); ++i)
    sum += w(static_cast<Eigen::Index>(i)) * control(cell.dofs[i]);
  return sum;
}

std::vector<double> loop_indicators_on_triangles(const AdaptiveLoopSpace& space, const RgbMesh& mesh,
                                                 const std::vector<double>& per_cell) {
  if (per_cell.size() != space.cells.elements.size())
    throw std::invalid_argument("loop_indicators_on_triangles: one value per cell");
  std::vector<double> squares(static_cast<std::size_t>(mesh.triangle_slots()), 0.0);
  VertexStar star;
  std::vector<TriangleHandle> around, coarse;
  for (std::size_t c = 0; c < per_cell.size(); ++c) {
    around.clear();
    coarse.clear();
    for (const VertexHandle v : space.anchors[c]) {
      if (!v.valid()) continue;
      if (!mesh.alive(v)) throw std::invalid_argument("loop_indicators_on_triangles: not the space's mesh");
      mesh.star(v, star);
      for (const TriangleHandle t : star.triangles) {
        if (std::find(around.begin(), around.end(), t) != around.end()) continue;
        around.push_back(t);
        if (mesh.level(t) <= space.cell_level[c]) coarse.push_back(t);
      }
    }
    const std::vector<TriangleHandle>& share = coarse.empty() ? around : coarse;
    for (const TriangleHandle t : share)
      squares[static_cast<std::size_t>(t.idx)] +=
          per_cell[c] * per_cell[c] / static_cast<double>(share.size());
  }
  for (double& x : squares) x = std::sqrt(x);
  return squares;
}

Eigen::VectorXd loop_values_on(const AdaptiveLoopSpace& space, const Eigen::VectorXd& coefficients,
                               const SurfaceMesh& p1) {
  if (coefficients.size() != static_cast<Eigen::Index>(space.num_dofs()))
    throw std::invalid_argument("loop_values_on: coefficients of another space");
  const Eigen::VectorXd control = space.control_values(coefficients);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> by_slot(space.coefficient_of_vertex.size(), nan);
  for (const LoopSpace::Element& cell : space.cells.elements) {
    for (int k = 0; k < 3; ++k) {
      const VertexHandle v =
          space.control_vertex[static_cast<std::size_t>(cell.dofs[static_cast<std::size_t>(k)])].vertex;
      if (!v.valid() || !std::isnan(by_slot[static_cast<std::size_t>(v.idx)])) continue;
      const Eigen::VectorXd w = loop_corner_limit(cell.rule->patch, k);
      double sum = 0;
      for (std::size_t i = 0; i < cell.dofs.size(); ++i)
        sum += w(static_cast<Eigen::Index>(i)) * control(cell.dofs[i]);
      by_slot[static_cast<std::size_t>(v.idx)] = sum;
    }
  }
  // The truncated hierarchical basis integrates some cells whole over RGB vertices of the next
  // level: those are midpoints of the cells' sides (a deeper one would have made a child of the
  // cell part of the next domain), evaluated there.
  bool missing = false;
  for (const VertexHandle v : p1.vertex)
    missing = missing || (static_cast<std::size_t>(v.idx) < by_slot.size() &&
                          std::isnan(by_slot[static_cast<std::size_t>(v.idx)]));
  if (missing) {
    std::unordered_map<std::uint64_t, std::int32_t> midpoint_of;  // control vertices' edge -> its midpoint
    for (std::size_t r = 0; r < space.control_vertex.size(); ++r) {
      const auto& o = space.control_vertex[r].origin;
      if (o[1] >= 0) midpoint_of.emplace(detail::edge_key(o[0], o[1]), static_cast<std::int32_t>(r));
    }
    constexpr std::array<std::array<double, 2>, 3> at{{{0.5, 0.0}, {0.5, 0.5}, {0.0, 0.5}}};
    for (const LoopSpace::Element& cell : space.cells.elements) {
      for (std::size_t k = 0; k < 3; ++k) {
        const auto it = midpoint_of.find(detail::edge_key(cell.dofs[k], cell.dofs[(k + 1) % 3]));
        if (it == midpoint_of.end()) continue;
        const VertexHandle v = space.control_vertex[static_cast<std::size_t>(it->second)].vertex;
        if (!v.valid() || !std::isnan(by_slot[static_cast<std::size_t>(v.idx)])) continue;
        const Eigen::VectorXd w = evaluate_loop_basis(cell.rule->patch, at[k][0], at[k][1]).value;
        double sum = 0;
        for (std::size_t i = 0; i < cell.dofs.size(); ++i)
          sum += w(static_cast<Eigen::Index>(i)) * control(cell.dofs[i]);
        by_slot[static_cast<std::size_t>(v.idx)] = sum;
      }
    }
  }
  Eigen::VectorXd out(static_cast<Eigen::Index>(p1.vertex.size()));
  for (std::size_t i = 0; i < p1.vertex.size(); ++i) {
    const auto slot = static_cast<std::size_t>(p1.vertex[i].idx);
    if (slot >= by_slot.size() || std::isnan(by_slot[slot]))
      throw std::invalid_argument("loop_values_on: a P1 mesh of another RGB mesh");
    out(static_cast<Eigen::Index>(i)) = by_slot[slot];
  }
  return out;
}

Solution solve_loop(const AdaptiveLoopSpace& space, const Problem& problem, const SolveOptions& options,
                    const LoopNitscheOptions& nitsche) {
  Eigen::VectorXd energies;
  return solve_loop(space, problem, options, energies, nitsche);
}

Solution solve_loop(const AdaptiveLoopSpace& space, const Problem& problem, const SolveOptions& options,
                    Eigen::VectorXd& energies, const LoopNitscheOptions& nitsche) {
  if (!(problem.c >= 0) || !std::isfinite(problem.c))
    throw InputError("problem '" + problem.name + "': the coefficient c must be finite and >= 0");
  if (!problem.source && !problem.source_values)
    throw InputError("problem '" + problem.name + "' has no source");
  detail::LoopSystem s = detail::assemble_loop_system(space.cells, false, problem.c, problem.source,
                                                      problem.source_values, problem.name);
  const auto t0 = std::chrono::steady_clock::now();
  // Nitsche's terms on the cells' boundary sides, as for the uniform space: the cells' control
  // values are the coefficients' expansion, so the terms carry over with it.
  if (!space.cells.boundary.empty()) detail::add_loop_boundary_terms(space.cells, problem, nitsche, s);
  // The system is solved in the truncated basis (the same space; its coarse functions stop
  // where finer ones take over, which is what lets BoomerAMG converge: 21 iterations at 25k
  // unknowns against 215), the result converted to the hierarchical coefficients.
  energies = galerkin_diagonal(s.a, space.expansion);
  const SparseMatrix& e = space.truncated_expansion;
  s.a = galerkin_product(s.a, e);
  s.b = e.transpose() * s.b;
  s.area = e.transpose() * s.area;  // ∫ of each truncated function
  s.seconds += seconds_since(t0);
  SolveOptions truncated_options = options;
  Eigen::VectorXd guess;
  const bool details = space.basis == LoopBasisKind::details;
  if (details && options.initial_guess != nullptr &&
      options.initial_guess->size() == static_cast<Eigen::Index>(space.num_dofs())) {
    guess = space.truncated_coefficients(*options.initial_guess);
    truncated_options.initial_guess = &guess;
  }
  Solution sol =
      !space.cells.boundary.empty()
          ? detail::solve_nitsche_system(s, truncated_options, problem.name, nitsche.penalty,
                                         "LoopNitscheOptions::penalty, 4 by default")
          : detail::solve_closed_loop_system(s, problem, truncated_options,
                                             details ? Eigen::VectorXd::Ones(s.a.rows()) : space.constant());
  if (details) sol.u = space.hierarchical_coefficients(sol.u);
  return sol;
}

std::vector<double> loop_removal_costs(const AdaptiveLoopSpace& space, const RgbMesh& mesh,
                                       const Eigen::VectorXd& u, const Eigen::VectorXd& energies) {
  const auto n = static_cast<Eigen::Index>(space.num_dofs());
  if (u.size() != n || energies.size() != n ||
      space.coefficient_of_vertex.size() != static_cast<std::size_t>(mesh.vertex_slots()))
    throw std::invalid_argument("loop_removal_costs: coefficients of another space or mesh");
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> cost(static_cast<std::size_t>(mesh.vertex_slots()), 0.0);
  const auto weighed = [&](const Eigen::VectorXd& detail, Eigen::Index i) {
    return std::abs(detail(i)) * std::sqrt(std::max(energies(i), 0.0));
  };
  if (space.basis == LoopBasisKind::details) {
    for (const VertexHandle v : mesh.vertices()) {
      const std::int32_t i = space.coefficient_of_vertex[static_cast<std::size_t>(v.idx)];
      if (i < 0) throw std::invalid_argument("loop_removal_costs: a vertex the space does not know");
      cost[static_cast<std::size_t>(v.idx)] =
          static_cast<std::size_t>(i) < space.num_base ? inf : weighed(u, i);
    }
    return cost;
  }
  const Eigen::VectorXd detail = space.hierarchical_coefficients(u);
  // Per vertex slot, the largest of its functions' weighed details, -1 where it has none.
  std::vector<double> own(cost.size(), -1.0);
  for (Eigen::Index i = 0; i < n; ++i) {
    double& at = own[static_cast<std::size_t>(space.vertex[static_cast<std::size_t>(i)].idx)];
    at = std::max(at, weighed(detail, i));
  }
  VertexStar star;
  for (const VertexHandle v : mesh.vertices()) {
    const auto slot = static_cast<std::size_t>(v.idx);
    if (mesh.level(v) == 0) {
      cost[slot] = inf;
    } else if (own[slot] >= 0) {
      cost[slot] = own[slot];
    } else {
      mesh.star(v, star);
      double most = 0;
      for (const VertexHandle w : star.neighbors)
        if (mesh.level(w) >= mesh.level(v)) most = std::max(most, own[static_cast<std::size_t>(w.idx)]);
      cost[slot] = most;
    }
  }
  return cost;
}

}  // namespace rgbmesh::fem
