// VTK cells as faces: shared by the legacy VTK parser and the XML readers.

#include <vtkCellType.h>
#include <vtkCellTypes.h>

#include <cstring>

#include "parse_common.hpp"
#include "parsers.hpp"

namespace rgbmesh::detail {
namespace {

std::string cell_type_name(int type) {
  switch (type) {
    case VTK_EMPTY_CELL:
      return "an empty cell";
    case VTK_VERTEX:
      return "a vertex";
    case VTK_POLY_VERTEX:
      return "a poly-vertex";
    case VTK_LINE:
      return "a line";
    case VTK_POLY_LINE:
      return "a polyline";
    case VTK_TETRA:
      return "a tetrahedron";
    case VTK_VOXEL:
      return "a voxel";
    case VTK_HEXAHEDRON:
      return "a hexahedron";
    case VTK_WEDGE:
      return "a wedge";
    case VTK_PYRAMID:
      return "a pyramid";
    case VTK_POLYHEDRON:
      return "a polyhedron";
    default: {
      const char* name = vtkCellTypes::GetClassNameFromTypeId(type);
      return "a cell of VTK type " + std::to_string(type) +
             (name != nullptr && std::strcmp(name, "UnknownClass") != 0 ? std::string(" (") + name + ")"
                                                                        : "");
    }
  }
}

InputError not_a_surface_cell(const std::string& path, std::size_t cell, int type) {
  return InputError(path + ": cell " + std::to_string(cell) + " is " + cell_type_name(type) +
                    ", not a surface polygon");
}

// Triangle strip -> triangles, every second one reversed so that all share the strip's
// orientation (VTK's convention). Triangles with a repeated id are the zero-area joints that
// stitch several strips into one and are skipped.
void append_strip(const std::vector<std::int64_t>& strip, PolygonSoup& soup) {
  for (std::size_t i = 0; i + 2 < strip.size(); ++i) {
    const std::int64_t a = strip[i], b = strip[i + 1], c = strip[i + 2];
    if (a == b || b == c || a == c) continue;
    if (i % 2 == 0)
      soup.faces.push_back({a, b, c});
    else
      soup.faces.push_back({b, a, c});
  }
}

}  // namespace

void append_poly_data_cells(const CellList& verts, const CellList& lines, const CellList& polys,
                            const CellList& strips, const std::string& path, PolygonSoup& soup,
                            const ReadOptions& options) {
  if (!verts.empty() && !options.skip_vertex_cells)
    throw not_a_surface_cell(path, 0, verts.front().size() <= 1 ? VTK_VERTEX : VTK_POLY_VERTEX);
  if (!lines.empty()) throw not_a_surface_cell(path, 0, lines.front().size() <= 2 ? VTK_LINE : VTK_POLY_LINE);
  soup.faces.insert(soup.faces.end(), polys.begin(), polys.end());
  for (const auto& strip : strips) append_strip(strip, soup);
}

void append_grid_cells(const CellList& cells, const std::vector<int>& types, const std::string& path,
                       PolygonSoup& soup, const ReadOptions& options) {
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const auto& ids = cells[c];
    switch (types[c]) {
      case VTK_TRIANGLE:
      case VTK_QUAD:
      case VTK_POLYGON:
        soup.faces.push_back(ids);
        break;
      case VTK_PIXEL:  // a quad with its last two corners swapped
        if (ids.size() == 4)
          soup.faces.push_back({ids[0], ids[1], ids[3], ids[2]});
        else
          soup.faces.push_back(ids);
        break;
      case VTK_TRIANGLE_STRIP:
        append_strip(ids, soup);
        break;
      case VTK_VERTEX:
      case VTK_POLY_VERTEX:
        if (!options.skip_vertex_cells) throw not_a_surface_cell(path, c, types[c]);
        break;
      default:
        throw not_a_surface_cell(path, c, types[c]);
    }
  }
}

}  // namespace rgbmesh::detail
