#pragma once
// Readers of our own, for formats where VTK 9.1 has no reader (OFF) or where its reader crashes,
// accepts damaged files or silently misreads (STL, OBJ, PLY, legacy VTK; see vtk_io.hpp), and the
// conversion of VTK cell lists into faces shared with the VTK-based readers. One file each:
// parse_stl.cpp, parse_off.cpp, parse_obj.cpp, parse_ply.cpp, parse_legacy_vtk.cpp, xyz.cpp,
// cells.cpp; what they share is in parse_common.hpp.
//
// Each parser takes the whole file (mapped, see input_file.hpp; text formats without a UTF-8
// byte-order mark) and throws InputError with a message that starts with `path` (and names the
// line where there is one). Memory is reserved only for what the bytes present can hold.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "rgbmesh/soup.hpp"
#include "rgbmesh/vec3.hpp"

namespace rgbmesh::detail {

struct SavedState;  // rgb_state_io.hpp

// What a reader keeps besides the surface polygons. The defaults are those of mesh reading.
struct ReadOptions {
  // Point clouds: vertex cells (VTK vertices and poly-vertices, OBJ 'p' elements) are skipped
  // instead of being an error, since they are how most tools mark points for display.
  bool skip_vertex_cells = false;
  // When set, receives one normal per point where the file has them (PLY nx, ny, nz); left
  // empty otherwise.
  std::vector<Vec3>* normals = nullptr;
  // VTK XML only: when set, receives the file's RGB state arrays (rgb_state_io.hpp).
  SavedState* saved_state = nullptr;
};

// read_polygon_soup with these options (read_rgb_mesh asks for the state this way).
PolygonSoup read_mesh_soup(const std::filesystem::path& path, const ReadOptions& options);

// Every triangle's three corners as separate points, as the file stores them (merging them is the
// caller's); coordinates single precision, as the format has them. Binary when the file is as long
// as its triangle count says, ASCII when it starts with "solid" and holds text; any other file,
// and any ASCII keyword out of place, is an InputError.
PolygonSoup parse_stl(std::string_view data, const std::string& path);
// The face count is exact: faces beyond it are an error, not ignored.
PolygonSoup parse_off(std::string_view text, const std::string& path);
PolygonSoup parse_obj(std::string_view text, const std::string& path, const ReadOptions& options = {});
PolygonSoup parse_ply(std::string_view data, const std::string& path, const ReadOptions& options = {});
PolygonSoup parse_legacy_vtk(std::string_view data, const std::string& path, const ReadOptions& options = {});
// 3MF through lib3mf (read_3mf.cpp): the triangles of every mesh object in the build, with the
// build items' and components' transforms applied (mirroring ones turn the triangles back
// outwards); supports and "other" objects are left out. A note says how many meshes and the
// file's unit (coordinates are kept as the file has them).
PolygonSoup parse_3mf(std::string_view data, const std::string& path);

// A point cloud as text (.xyz, .pwn): one point per line, "x y z" or "x y z nx ny nz", the same
// number of columns on every line; empty lines and '#' comments are skipped. Errors name the
// line as "path:line: ...". Normals go to `normals` when the file has them.
PolygonSoup parse_xyz(std::string_view text, const std::string& path, std::vector<Vec3>& normals);

using CellList = std::vector<std::vector<std::int64_t>>;

// Cells of a polygonal data set in VTK's numbering (vertices, lines, polygons, strips): polygons
// become faces, strips triangles; any vertex or line cell is an InputError naming it (vertex
// cells are skipped when options.skip_vertex_cells).
void append_poly_data_cells(const CellList& verts, const CellList& lines, const CellList& polys,
                            const CellList& strips, const std::string& path, PolygonSoup& soup,
                            const ReadOptions& options = {});

// Cells of an unstructured grid with their VTK cell types: triangles, quads, pixels, polygons and
// strips become faces; any other type is an InputError naming the cell (vertex and poly-vertex
// cells are skipped when options.skip_vertex_cells).
void append_grid_cells(const CellList& cells, const std::vector<int>& types, const std::string& path,
                       PolygonSoup& soup, const ReadOptions& options = {});

}  // namespace rgbmesh::detail
