// The pictures of a Loop-basis solution (see loop_elements.hpp): a view finer than the mesh,
// the values at the vertices' limit positions, and values handed over in the order of a P1
// mesh of the same triangles (how the tools and the bindings show and transfer them). Apart
// from the space and its solves because it only reads a solution, through the public basis.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <unordered_map>
#include <stdexcept>
#include <vector>

#include "rgbmesh/fem/loop_basis.hpp"
#include "rgbmesh/fem/loop_elements.hpp"

namespace rgbmesh::fem {

MeshSnapshot loop_refined_view(const LoopSpace& space, const Eigen::VectorXd& u, int levels) {
  if (levels < 0 || levels > 6) throw std::invalid_argument("loop_refined_view: levels in [0, 6]");
  const int m = 1 << levels;
  // The grid points (i/m, j/m) of the parameter triangle, and the basis there, once per rule.
  std::vector<std::array<int, 2>> grid;
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i + j <= m; ++i) grid.push_back({i, j});
  const auto grid_index = [m](int i, int j) { return j * (m + 1) - j * (j - 1) / 2 + i; };
  std::map<const LoopQuadrature*, Eigen::MatrixXd> weights;  // n x grid points
  MeshSnapshot view;
  std::vector<double> values;
  std::vector<double> element;
  // A grid point on an element's edge or corner is shared: named by the edge's end DOFs and
  // its place counted from the lower one (hashed: a run's view has millions of them).
  struct KeyHash {
    std::size_t operator()(const std::array<std::int64_t, 3>& k) const {
      std::uint64_t h = static_cast<std::uint64_t>(k[0]) * 0x9E3779B97F4A7C15ull;
      h ^= static_cast<std::uint64_t>(k[1]) + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
      h ^= static_cast<std::uint64_t>(k[2]) + 0x94D049BB133111EBull + (h << 6) + (h >> 2);
      return static_cast<std::size_t>(h);
    }
  };
  std::unordered_map<std::array<std::int64_t, 3>, std::int32_t, KeyHash> shared;
  const std::size_t cells = space.elements.size(), per_cell = static_cast<std::size_t>(m) * static_cast<std::size_t>(m);
  shared.reserve(cells * (3 * static_cast<std::size_t>(m) / 2 + 1));
  view.points.reserve(cells * per_cell / 2 + cells);
  values.reserve(cells * per_cell / 2 + cells);
  view.triangles.reserve(cells * per_cell);
  element.reserve(cells * per_cell);
  std::vector<std::int32_t> point(grid.size());
  for (std::size_t e = 0; e < space.elements.size(); ++e) {
    const LoopSpace::Element& el = space.elements[e];
    Eigen::MatrixXd& w = weights[el.rule.get()];
    if (w.size() == 0) {
      w.resize(static_cast<Eigen::Index>(el.dofs.size()), static_cast<Eigen::Index>(grid.size()));
      for (std::size_t g = 0; g < grid.size(); ++g)
        w.col(static_cast<Eigen::Index>(g)) =
            evaluate_loop_basis(el.rule->patch, grid[g][0] / double(m), grid[g][1] / double(m)).value;
    }
    const std::array<std::int64_t, 3> d = {el.dofs[0], el.dofs[1], el.dofs[2]};
    for (std::size_t g = 0; g < grid.size(); ++g) {
      const int i = grid[g][0], j = grid[g][1];
      std::array<std::int64_t, 3> key{-1, -1, -1};
      const auto on_edge = [&](std::int64_t a, std::int64_t b, int t) {  // t steps from a towards b
        key = a < b ? std::array<std::int64_t, 3>{a, b, t} : std::array<std::int64_t, 3>{b, a, m - t};
      };
      if (j == 0)
        on_edge(d[0], d[1], i);
      else if (i + j == m)
        on_edge(d[1], d[2], j);
      else if (i == 0)
        on_edge(d[0], d[2], j);
      if (key[0] >= 0 && (key[2] == 0 || key[2] == m))
        key = {key[2] == 0 ? key[0] : key[1], -1, 0};  // a corner
      if (key[0] >= 0) {
        const auto [it, inserted] = shared.emplace(key, static_cast<std::int32_t>(view.points.size()));
        point[g] = it->second;
        if (!inserted) continue;
      } else {
        point[g] = static_cast<std::int32_t>(view.points.size());
      }
      Vec3 x;
      double value = 0;
      for (std::size_t k = 0; k < el.dofs.size(); ++k) {
        const double wk = w(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(g));
        x += wk * space.control[static_cast<std::size_t>(el.dofs[k])];
        value += wk * u(el.dofs[k]);
      }
      view.points.push_back(space.projection ? (*space.projection)(x) : x);
      values.push_back(value);
    }
    for (int j = 0; j < m; ++j) {
      for (int i = 0; i + j < m; ++i) {
        view.triangles.push_back({point[static_cast<std::size_t>(grid_index(i, j))],
                                  point[static_cast<std::size_t>(grid_index(i + 1, j))],
                                  point[static_cast<std::size_t>(grid_index(i, j + 1))]});
        element.push_back(static_cast<double>(e));
        if (i + j + 1 < m) {
          view.triangles.push_back({point[static_cast<std::size_t>(grid_index(i + 1, j))],
                                    point[static_cast<std::size_t>(grid_index(i + 1, j + 1))],
                                    point[static_cast<std::size_t>(grid_index(i, j + 1))]});
          element.push_back(static_cast<double>(e));
        }
      }
    }
  }
  view.point_data.push_back({"solution", 1, std::move(values)});
  view.cell_data.push_back({"element", 1, std::move(element)});
  return view;
}

Eigen::VectorXd loop_vertex_values(const LoopSpace& space, const Eigen::VectorXd& u) {
  Eigen::VectorXd out = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(space.num_dofs()),
                                                  std::numeric_limits<double>::quiet_NaN());
  std::vector<char> done(space.num_dofs(), 0);
  for (const LoopSpace::Element& e : space.elements) {
    for (int corner = 0; corner < 3; ++corner) {
      const std::int32_t dof = e.dofs[static_cast<std::size_t>(corner)];
      if (done[static_cast<std::size_t>(dof)]) continue;
      const Eigen::VectorXd w = loop_corner_limit(e.rule->patch, corner);
      double value = 0;
      for (std::size_t i = 0; i < e.dofs.size(); ++i) value += w(static_cast<Eigen::Index>(i)) * u(e.dofs[i]);
      out(dof) = value;
      done[static_cast<std::size_t>(dof)] = 1;
    }
  }
  return out;
}

Eigen::VectorXd loop_values_on(const LoopSpace& space, const Eigen::VectorXd& u, const SurfaceMesh& p1) {
  if (p1.order != 1 || p1.num_dofs() != space.num_dofs())
    throw std::invalid_argument("loop_values_on: the P1 mesh of the Loop space's triangles is needed");
  const Eigen::VectorXd at_vertices = loop_vertex_values(space, u);
  Eigen::VectorXd out = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(p1.num_dofs()),
                                                  std::numeric_limits<double>::quiet_NaN());
  for (std::size_t d = 0; d < space.num_dofs(); ++d) {
    const std::size_t slot = static_cast<std::size_t>(space.vertex[d].idx);
    const std::int32_t to = slot < p1.dof_of_vertex.size() ? p1.dof_of_vertex[slot] : -1;
    if (to < 0 || static_cast<std::size_t>(to) >= p1.num_dofs())
      throw std::invalid_argument("loop_values_on: the P1 mesh is not of the Loop space's vertices");
    out(to) = at_vertices(static_cast<Eigen::Index>(d));
  }
  return out;
}

std::vector<double> loop_element_values_on(const LoopSpace& space, const std::vector<double>& per_element,
                                           const SurfaceMesh& p1) {
  if (per_element.size() != space.elements.size() || p1.triangle.size() != space.elements.size())
    throw std::invalid_argument("loop_element_values_on: one value per element of the same triangles");
  std::int32_t slots = 0;
  for (const LoopSpace::Element& e : space.elements) slots = std::max(slots, e.triangle.idx + 1);
  std::vector<double> by_slot(static_cast<std::size_t>(slots), 0.0);
  for (std::size_t e = 0; e < space.elements.size(); ++e)
    by_slot[static_cast<std::size_t>(space.elements[e].triangle.idx)] = per_element[e];
  std::vector<double> out;
  out.reserve(p1.triangle.size());
  for (const TriangleHandle t : p1.triangle) {
    if (t.idx < 0 || t.idx >= slots)
      throw std::invalid_argument("loop_element_values_on: the P1 mesh is not of the Loop space's triangles");
    out.push_back(by_slot[static_cast<std::size_t>(t.idx)]);
  }
  return out;
}

}  // namespace rgbmesh::fem
