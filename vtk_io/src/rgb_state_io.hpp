#pragma once
// The RGB state in VTK XML files (.vtp, .vtu): how RgbState (rgb_state.hpp) is stored as VTK
// arrays, and read back. Format version 1 (version 2 adds the sharp features):
//
//   point data  rgb_base_vertex     Int32, 1 component: the point's base index, -1 if inserted
//               rgb_parents         Int32, 2 components: the points whose edge it split (-1 -1
//                                   for a base vertex)
//   field data  rgb_state_version   Int32, 1 value: 1
//               rgb_base_points     Float64, 3 components: the base mesh's control points
//               rgb_base_triangles  Int32, 3 components: the base mesh's triangles
//   version 2, field data (each array only where the mesh has such features):
//               rgb_sharp_edges             Int32, 2 components: base vertices of sharp edges
//               rgb_sharp_edge_sharpness    Float64, 1 component: their sharpness
//               rgb_sharp_vertices          Int32, 1 component: sharp base vertices
//               rgb_sharp_vertex_sharpness  Float64, 1 component: their sharpness
//               rgb_crease_method           Int32, 1 value: 0 uniform, 1 Chaikin
//
// A piece of a distributed run's output carries its piece's state (save_piece_state) in field
// data instead, over its points followed by their ancestors (which need not be points of the
// piece): rgb_state_version, rgb_base_points and rgb_base_triangles as above, and
//   field data  rgb_piece_base_vertex  Int32, 1 component: per entry, as rgb_base_vertex
//               rgb_piece_parents      Int32, 2 components: per entry, entries' indices
// read_rgb_pieces joins the pieces of a summary (.pvtp) into the whole mesh.
//
// The file's own cells give the triangles (and with them the trapezoid diagonals), and its
// arrays "level" (point and cell), "color", "control_point" and "limit", when present, are
// compared with what the state gives; so are its Points (what ParaView shows), which must be
// one of the positions rgbmesh writes as points for every point. A file with none of these arrays has no
// state; a file with some but not all of them is refused.

#include <filesystem>
#include <optional>

#include "rgbmesh/rgb_state.hpp"

class vtkDataSet;

namespace rgbmesh::detail {

// The arrays' names.
inline constexpr const char* kBaseVertexArray = "rgb_base_vertex";
inline constexpr const char* kParentsArray = "rgb_parents";
inline constexpr const char* kStateVersionArray = "rgb_state_version";
inline constexpr const char* kBasePointsArray = "rgb_base_points";
inline constexpr const char* kBaseTrianglesArray = "rgb_base_triangles";
inline constexpr const char* kPieceBaseVertexArray = "rgb_piece_base_vertex";
inline constexpr const char* kPieceParentsArray = "rgb_piece_parents";
inline constexpr const char* kSharpEdgesArray = "rgb_sharp_edges";
inline constexpr const char* kSharpEdgeSharpnessArray = "rgb_sharp_edge_sharpness";
inline constexpr const char* kSharpVerticesArray = "rgb_sharp_vertices";
inline constexpr const char* kSharpVertexSharpnessArray = "rgb_sharp_vertex_sharpness";
inline constexpr const char* kCreaseMethodArray = "rgb_crease_method";

// What read_rgb_mesh needs from a VTK XML file besides its points and cells.
struct SavedState {
  std::optional<RgbState> state;
  std::optional<RgbState> piece_state;  // a piece's (then `state` is empty)
  RestoreExpectations expected;  // all but the triangles (read_rgb_mesh adds them)
  bool single_precision_points = false;  // Points stored as Float32 (rounded to 24 bits)
};

// Reads the arrays above from a data set read from `path`; InputError naming the file and the
// array when they are there but malformed.
void read_rgb_state(vtkDataSet& data, const std::filesystem::path& path, SavedState& out);

}  // namespace rgbmesh::detail
