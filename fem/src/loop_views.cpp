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
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "edge_key.hpp"
#include "for_each_index.hpp"
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
  const std::size_t per_element = grid.size();
  const auto grid_index = [m](int i, int j) { return static_cast<std::size_t>(j * (m + 1) - j * (j - 1) / 2 + i); };
  std::map<const LoopQuadrature*, Eigen::MatrixXd> weights;  // n x grid points
  const std::size_t cells = space.elements.size();
  std::vector<const Eigen::MatrixXd*> weights_of(cells);
  for (std::size_t e = 0; e < cells; ++e) {
    const LoopSpace::Element& el = space.elements[e];
    Eigen::MatrixXd& w = weights[el.rule.get()];
    if (w.size() == 0) {
      w.resize(static_cast<Eigen::Index>(el.dofs.size()), static_cast<Eigen::Index>(per_element));
      for (std::size_t g = 0; g < per_element; ++g)
        w.col(static_cast<Eigen::Index>(g)) =
            loop_rule_basis(*el.rule, grid[g][0] / double(m), grid[g][1] / double(m)).value;
    }
    weights_of[e] = &w;
  }
  // Numbering (serial, in element order: the same view on any number of cores). A grid point
  // on an element's corner is shared by the corner's DOF, one on an edge by the edge's end DOFs
  // and its place counted from the lower one; each edge met keeps the first of its m - 1 inner
  // points. A point is evaluated in the first element that meets it (`source`).
  std::vector<std::int32_t> at_corner(space.num_dofs(), -1);
  std::unordered_map<std::uint64_t, std::int32_t> edge_first;
  edge_first.reserve(cells * 2);
  std::vector<std::int32_t> point(cells * per_element);
  std::vector<std::pair<std::int32_t, std::int32_t>> source;  // (element, grid point)
  source.reserve(cells * (per_element / 2 + 1));
  for (std::size_t e = 0; e < cells; ++e) {
    const std::vector<std::int32_t>& d = space.elements[e].dofs;
    std::int32_t* mine = point.data() + e * per_element;
    const auto fresh = [&](std::size_t g) {
      source.emplace_back(static_cast<std::int32_t>(e), static_cast<std::int32_t>(g));
      return static_cast<std::int32_t>(source.size() - 1);
    };
    // The three corners.
    for (const auto& [corner, g] : {std::pair{d[0], grid_index(0, 0)}, std::pair{d[1], grid_index(m, 0)},
                                    std::pair{d[2], grid_index(0, m)}}) {
      std::int32_t& p = at_corner[static_cast<std::size_t>(corner)];
      if (p < 0) p = fresh(g);
      mine[g] = p;
    }
    // The three edges' inner points: t steps from a towards b at grid point place(t).
    const auto edge = [&](std::int32_t a, std::int32_t b, auto place) {
      if (m < 2) return;
      const auto [it, inserted] = edge_first.emplace(detail::edge_key(a, b), static_cast<std::int32_t>(source.size()));
      const auto from_lower = [&](int t) { return a < b ? t : m - t; };  // steps from the lower end
      if (inserted)
        for (int s = 1; s < m; ++s) fresh(place(from_lower(s)));
      for (int t = 1; t < m; ++t) mine[place(t)] = it->second + (from_lower(t) - 1);
    };
    edge(d[0], d[1], [&](int t) { return grid_index(t, 0); });
    edge(d[1], d[2], [&](int t) { return grid_index(m - t, t); });
    edge(d[0], d[2], [&](int t) { return grid_index(0, t); });
    // The inner points.
    for (int j = 1; j < m; ++j)
      for (int i = 1; i + j < m; ++i) mine[grid_index(i, j)] = fresh(grid_index(i, j));
  }
  // Positions and values, on every core.
  MeshSnapshot view;
  view.points.resize(source.size());
  std::vector<double> values(source.size());
  detail::for_each_index(source.size(), [&](std::size_t k) {
    const auto [e, g] = source[k];
    const LoopSpace::Element& el = space.elements[static_cast<std::size_t>(e)];
    const Eigen::MatrixXd& w = *weights_of[static_cast<std::size_t>(e)];
    Vec3 x;
    double value = 0;
    for (std::size_t i = 0; i < el.dofs.size(); ++i)
      value += w(static_cast<Eigen::Index>(i), g) * u(el.dofs[i]);
    for (std::size_t i = 0; i < el.surface_dofs(); ++i)
      x += w(static_cast<Eigen::Index>(i), g) * space.control[static_cast<std::size_t>(el.dofs[i])];
    view.points[k] = space.projection ? (*space.projection)(x) : x;
    values[k] = value;
  });
  // m² triangles an element, on every core.
  const std::size_t per_cell = static_cast<std::size_t>(m) * static_cast<std::size_t>(m);
  view.triangles.resize(cells * per_cell);
  std::vector<double> element(cells * per_cell);
  detail::for_each_index(cells, [&](std::size_t e) {
    const std::int32_t* mine = point.data() + e * per_element;
    std::size_t k = e * per_cell;
    for (int j = 0; j < m; ++j)
      for (int i = 0; i + j < m; ++i) {
        view.triangles[k] = {mine[grid_index(i, j)], mine[grid_index(i + 1, j)], mine[grid_index(i, j + 1)]};
        element[k++] = static_cast<double>(e);
        if (i + j + 1 < m) {
          view.triangles[k] = {mine[grid_index(i + 1, j)], mine[grid_index(i + 1, j + 1)], mine[grid_index(i, j + 1)]};
          element[k++] = static_cast<double>(e);
        }
      }
  });
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
      const Eigen::VectorXd w = loop_rule_corner_limit(*e.rule, corner);
      double value = 0;
      for (std::size_t i = 0; i < e.dofs.size(); ++i) value += w(static_cast<Eigen::Index>(i)) * u(e.dofs[i]);
      out(dof) = value;
      done[static_cast<std::size_t>(dof)] = 1;
    }
  }
  return out;
}

Eigen::VectorXd loop_values_on(const LoopSpace& space, const Eigen::VectorXd& u, const SurfaceMesh& p1) {
  // The ghosts of LoopBoundary::completed are DOFs without a vertex.
  const std::size_t at_vertices_count = static_cast<std::size_t>(
      std::count_if(space.vertex.begin(), space.vertex.end(), [](VertexHandle v) { return v.valid(); }));
  if (p1.order != 1 || p1.num_dofs() != at_vertices_count)
    throw std::invalid_argument("loop_values_on: the P1 mesh of the Loop space's triangles is needed");
  const Eigen::VectorXd at_vertices = loop_vertex_values(space, u);
  Eigen::VectorXd out = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(p1.num_dofs()),
                                                  std::numeric_limits<double>::quiet_NaN());
  for (std::size_t d = 0; d < space.num_dofs(); ++d) {
    if (!space.vertex[d].valid()) continue;
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
