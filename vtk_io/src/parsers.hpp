#pragma once
// Readers of our own, for formats where VTK 9.1 has no reader (OFF) or where its reader crashes or
// silently misreads bad files (OBJ, PLY, legacy VTK; see vtk_io.hpp), and the conversion of VTK
// cell lists into faces shared with the VTK-based readers.
//
// Every function throws InputError with a message that starts with `path` (and names the line
// where there is one).

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "rgbmesh/soup.hpp"

namespace rgbmesh::detail {

PolygonSoup parse_off(std::string_view text, const std::string& path);
PolygonSoup parse_obj(std::string_view text, const std::string& path);
PolygonSoup parse_ply(std::string_view data, const std::string& path);
PolygonSoup parse_legacy_vtk(std::string_view data, const std::string& path);

using CellList = std::vector<std::vector<std::int64_t>>;

// Cells of a polygonal data set in VTK's numbering (vertices, lines, polygons, strips): polygons
// become faces, strips triangles; any vertex or line cell is an InputError naming it.
void append_poly_data_cells(const CellList& verts, const CellList& lines, const CellList& polys,
                            const CellList& strips, const std::string& path, PolygonSoup& soup);

// Cells of an unstructured grid with their VTK cell types: triangles, quads, pixels, polygons and
// strips become faces; any other type is an InputError naming the cell.
void append_grid_cells(const CellList& cells, const std::vector<int>& types, const std::string& path,
                       PolygonSoup& soup);

}  // namespace rgbmesh::detail
