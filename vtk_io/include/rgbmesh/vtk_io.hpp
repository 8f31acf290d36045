#pragma once
/// \file
/// Mesh files.
///
/// Reading: only regular files are read (a FIFO, device, socket or directory is refused and
/// named, so are symbolic-link loops and dangling links); the file is mapped, not copied, and every
/// count it declares is checked against its size before memory is reserved for it, so a damaged
/// or huge garbage file is refused at once with little memory. Text formats skip a UTF-8 byte-order
/// mark. VTP and VTU go through VTK's XML readers after the whole header has been validated against
/// the file (counts, array attributes, binary size and compression headers, cell offsets), since
/// those readers crash or allocate without limit on damaged headers. STL, OFF (VTK has none), OBJ,
/// PLY and legacy VTK are read by parsers of our own, because VTK 9.1's readers for them read out
/// of bounds or abort the process on bad input (out-of-range indices, truncated files, short cell
/// lists), accept damaged files (an STL whose triangle count disagrees with its length, misspelled
/// keywords) and silently lose data (OBJ and PLY coordinates in single precision, OBJ "nan" read as
/// 0, PLY polygons with more than 255 vertices cut short).
///
/// Writing is atomic: a temporary file in the target's directory, flushed to disk and renamed
/// onto the target once complete; the temporary is removed on failure (and on SIGINT, SIGTERM,
/// SIGHUP, see remove_temporaries_on_signals). A target that is a symbolic link stays a link:
/// the file it leads to is replaced.
///
/// Errors: bad or unreadable input is an InputError whose message starts with the file path;
/// failing to write is an OutputError naming the path (rgbmesh/errors.hpp). VTK's own messages are captured while
/// it works, never printed.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/snapshot.hpp"
#include "rgbmesh/soup.hpp"

namespace rgbmesh {

/// For help texts: ".obj, .off, .ply, .stl, .vtk, .vtp, .vtu" and ".obj, .off, .ply, .stl, .vtp, .vtu".
std::string supported_input_extensions();
std::string supported_output_extensions();

/// The faces and points exactly as the file has them (format chosen by the extension, case-
/// insensitive; coordinates in double precision where the file has them). Points are merged only
/// where the format itself duplicates them: STL, which stores every triangle's corners separately,
/// has exactly coincident points merged (and numbered_vertices false: messages name its vertices
/// by position). Triangle strips become triangles (skipping the zero-area
/// joints of stitched strips). Non-surface cells (vertices, lines, volume cells; OBJ 'l' and 'p')
/// are an InputError naming the cell (or line). Indices are passed through unchecked, for
/// prepare_triangle_mesh to name the face with a bad one (OBJ reports them with their line).
PolygonSoup read_polygon_soup(const std::filesystem::path& path);

/// read_polygon_soup + prepare_triangle_mesh, with the file path prefixed to any InputError (a
/// MeshDefectError stays one).
TriangleMeshData read_mesh(const std::filesystem::path& path, const SoupOptions& options = {});

/// A mesh file as an RgbMesh. VTK XML files that rgbmesh wrote (.vtp, .vtu) carry the complete
/// RGB state (rgb_state.hpp; docs/concepts.md lists the arrays): the mesh is then restored as
/// it was written, with its levels, colours, control points and limit positions, ready to be
/// refined or coarsened further (restored = true). Any other file, and a VTK XML file without
/// the state, gives the base mesh of its triangles (read_mesh, then RgbMesh::from_triangles;
/// notes as read_mesh's). options.repair does not apply to a file with a state (restored exactly;
/// a note says so). A state that is inconsistent with itself or with the file's cells and
/// arrays is an InputError "<path>: inconsistent RGB state: <what>"; nothing half-built escapes.
struct RgbMeshFile {
  RgbMesh mesh;
  bool restored = false;           ///< the file had a state
  std::vector<std::string> notes;  ///< repairs of a file without state, one line each
};
RgbMeshFile read_rgb_mesh(const std::filesystem::path& path, const SoupOptions& options = {});
/// The whole mesh of a distributed run's cycle from its summary (.pvtp) and the pieces it
/// names beside it, each carrying its piece's state (MeshSnapshot::piece_state): joined by the
/// vertices' ancestry, rebuilt, and checked against every piece's triangles and Points.
/// InputError naming the summary or the piece where they are inconsistent.
RgbMeshFile read_rgb_pieces(const std::filesystem::path& summary);

/// Points to fit a surface to: a point cloud, or the vertices (and faces) of a mesh file.
struct PointCloud {
  std::vector<Vec3> points;
  /// One per point when the file has usable normals (.xyz/.pwn with 6 columns, PLY nx ny nz,
  /// VTP/VTU point normals); empty otherwise.
  std::vector<Vec3> normals;
  /// The file's surface polygons exactly as read_polygon_soup gives them (unchecked: the caller
  /// decides whether they make a surface); empty for a point cloud.
  std::vector<std::vector<std::int64_t>> faces;
  /// As PolygonSoup::numbered_vertices: false for STL, whose messages name positions.
  bool numbered_vertices = true;
  std::vector<std::string> notes;  ///< what was ignored, one line each
};

/// For help texts: the mesh input extensions plus ".xyz, .pwn".
std::string supported_point_cloud_extensions();

/// Reads a point cloud through the same validated readers as read_polygon_soup (same checks,
/// same messages), except that vertex cells (VTK vertices and poly-vertices, OBJ 'p') are
/// skipped instead of rejected and a file without faces is fine. Also reads .xyz and .pwn:
/// "x y z" or "x y z nx ny nz" per line. InputError naming the file (and the line, for text
/// formats) for any reading error, no points, or a non-finite coordinate. Normals that are zero
/// or not finite are kept as they are (users of the normals skip them); a set in which none is
/// usable is dropped, with a note.
PointCloud read_point_cloud(const std::filesystem::path& path);

/// How the binary data of VTK XML files (.vtp, .vtu) is compressed.
enum class Compression {
  lz4,   ///< The default: the fastest to write and to read. VTK 8.2 and later read it (ParaView
         ///< 5.6 and later).
  zlib,  ///< Smaller files (about 0.8 times lz4's), several times slower to write (level 1);
         ///< every VTK XML reader reads it.
  none,  ///< Raw binary: no compression work, the largest files.
};

/// "lz4", "zlib", "none".
const char* compression_name(Compression compression);
/// Sets `compression` to the one named "lz4", "zlib" or "none" (exactly); false for any other name.
bool compression_from_name(const std::string& name, Compression& compression);

/// How write_mesh and write_point_cloud write.
struct WriteOptions {
  /// VTK XML files only; the other formats are not compressed.
  Compression compression = Compression::lz4;
  /// When set, called on the calling thread while the file is written, with the fraction
  /// done: 0 first, then not decreasing, and 1 once the file is complete (before it replaces
  /// the target). VTK XML files report after every batch of 64 compressed blocks (2 MiB of
  /// data), OBJ and OFF every 100,000 lines, PLY and STL only at their start and end. For PLY
  /// and STL it runs inside VTK's writer: it must not read or write files through rgbmesh. An
  /// exception it throws fails the write (the temporary file is removed) and is rethrown
  /// unchanged.
  std::function<void(double fraction)> progress;
};

/// Writes points as VTK XML PolyData (.vtp only), one vertex cell per point so that ParaView
/// shows them, with every NamedArray as Float64 point data. Atomic, like write_mesh. InputError
/// for another extension; std::invalid_argument for arrays of the wrong size.
void write_point_cloud(const std::filesystem::path& path, const std::vector<Vec3>& points,
                       const std::vector<NamedArray>& point_data, const WriteOptions& options = {});

/// Writes quadratic triangles as VTK XML UnstructuredGrid (.vtu only) of VTK_QUADRATIC_TRIANGLE
/// cells, which ParaView draws curved (raise the representation's "Nonlinear Subdivision Level"
/// to see the curvature and the quadratic variation of the data): six nodes per cell, the
/// corners, then the middles of edges 0-1, 1-2 and 2-0, with every NamedArray as Float64 point
/// or cell data. Atomic and compressed as write_mesh. InputError for another extension;
/// std::invalid_argument for indices or arrays of the wrong size.
void write_quadratic_triangles(const std::filesystem::path& path, const std::vector<Vec3>& points,
                               const std::vector<std::array<std::int32_t, 6>>& cells,
                               const std::vector<NamedArray>& point_data, const std::vector<NamedArray>& cell_data,
                               const WriteOptions& options = {});

/// Writes by extension: .obj, .ply (binary), .stl (binary), .off, .vtp, .vtu. The XML formats are
/// appended raw binary, compressed as options.compression says (lz4 by default), with point
/// data "level" (UInt8), cell data "level" and "color" (UInt8: 0 green, 1 red, 2 blue) and every
/// NamedArray as a Float64 array: the files VTK's XML writers make (file version 1.0, 64-bit
/// headers, VTK's compressors), written block by block from the snapshot's memory by our own
/// writer, the blocks compressed on every core, so that writing needs little memory besides
/// the snapshot (connectivity and offsets are Int32 in the file). OBJ, PLY and STL carry geometry only, and
/// PLY/STL store single-precision coordinates. An unknown extension is an InputError; an
/// inconsistent snapshot (sizes, indices) is std::invalid_argument.
void write_mesh(const std::filesystem::path& path, const MeshSnapshot& mesh, const WriteOptions& options);
/// write_mesh with the default WriteOptions (kept for source and binary compatibility).
void write_mesh(const std::filesystem::path& path, const MeshSnapshot& mesh);

/// The snapshot of `mesh` to write to `path`: points at the shown control points, or at the
/// limit positions; VTK XML files (.vtp, .vtu) also get the point data "control_point" and
/// "limit". Computes the limit positions it needs (RgbMesh::compute_limits leaves the mesh as
/// it was). Made lean for writing: no vertex_handle or triangle_handle arrays, and the one of
/// "control_point" and "limit" that the points already are is NamedArray::same_as_points
/// (written from the points' memory) instead of a copy.
MeshSnapshot snapshot_for_file(RgbMesh& mesh, const std::filesystem::path& path, bool limit_points = false);

/// Writes `mesh` as write_mesh(path, snapshot_for_file(mesh, path, limit_points), options)
/// does, the same file byte for byte, but VTK XML files (.vtp, .vtu) are computed from the mesh
/// block by block as they are written, without a snapshot: besides the mesh, writing needs
/// about 1 byte per vertex (13 where the mesh has free slots) and a few MB, and the blocks are
/// compressed on every core. What the command-line tool uses for its mesh outputs.
void write_rgb_mesh(const std::filesystem::path& path, RgbMesh& mesh, const WriteOptions& options = {},
                    bool limit_points = false);

/// The sharp edges of a mesh (MeshSnapshot::sharp, its interior edges of sharpness above 0) as
/// lines for ParaView, which draws them over the surface: VTK XML PolyData (.vtp only), one line
/// cell per edge between the snapshot's points it joins, with cell data "sharpness" and point
/// data "vertex_rule" (0 smooth, 1 dart, 2 crease, 3 corner). Atomic like write_mesh. Returns
/// false, writing nothing, when there is no sharp edge.
bool write_sharp_edges(const std::filesystem::path& path, const MeshSnapshot& mesh, const WriteOptions& options = {});
/// The same for `mesh`, its points where write_rgb_mesh puts them (shown control points, or
/// limit positions: then the limits must be known, as write_rgb_mesh leaves them).
bool write_sharp_edges(const std::filesystem::path& path, const RgbMesh& mesh, bool limit_points = false,
                       const WriteOptions& options = {});
/// Where the tool writes a mesh file's sharp edges: "part.vtp" -> "part.creases.vtp".
std::filesystem::path sharp_edges_path(const std::filesystem::path& mesh_file);

/// Makes SIGINT, SIGTERM and SIGHUP remove the temporary files of writes in progress before the
/// process dies of the signal (where the host has not set its own handler or ignored the
/// signal), and makes exceeding the file-size limit (SIGXFSZ) a write error instead of death.
/// The CLI calls it first thing; a program embedding rgbmesh may.
void remove_temporaries_on_signals();

/// Has those signals remove `path` too, until forget_on_signals(the returned number): for a
/// file that only means something while the process runs (the CLI's run-folder lock). -1 when
/// it cannot (the path is longer than 4095 bytes, or 32 files are registered already).
int remove_on_signals(const std::filesystem::path& path);
void forget_on_signals(int registration);

/// Replaces `path` by a file holding `contents`, atomically.
void write_text_atomically(const std::filesystem::path& path, const std::string& contents);

/// One piece of a snapshot split among processes: the cells whose `part` is `which`, the points
/// they use (in their order), and every point and cell array restricted alike (not the RGB
/// state, which belongs to the whole mesh).
MeshSnapshot snapshot_piece(const MeshSnapshot& whole, const std::vector<std::int32_t>& part, std::int32_t which);

/// The summary file (.pvtp) of a data set written as pieces (.vtp files, relative to the
/// summary's folder): the arrays are those the pieces of `like` (the whole snapshot, or any
/// piece) are written with, so that ParaView and VTK's vtkXMLPPolyDataReader open the pieces
/// as one data set. Written atomically.
void write_pvtp(const std::filesystem::path& pvtp, const MeshSnapshot& like, const std::vector<std::string>& pieces);
/// The summary file (.pvtu) of quadratic triangles written as pieces (write_quadratic_triangles,
/// .vtu files relative to the summary's folder), with the point and cell arrays the pieces
/// have (names and components of point_data and cell_data; their values are not read), so
/// that ParaView and VTK's vtkXMLPUnstructuredGridReader open them as one data set.
void write_quadratic_pvtu(const std::filesystem::path& pvtu, const std::vector<NamedArray>& point_data,
                          const std::vector<NamedArray>& cell_data, const std::vector<std::string>& pieces);

/// A ParaView collection (.pvd) of a time series: one DataSet per (time, file relative to the
/// .pvd's directory). Written atomically.
void write_pvd(const std::filesystem::path& pvd,
               const std::vector<std::pair<double, std::string>>& time_and_relative_file);
/// The same where a time step has several files, each a part of it that ParaView shows together
/// (a mesh and its sharp edges): one DataSet per (time, part number, relative file).
struct PvdEntry {
  double time = 0;
  int part = 0;
  std::string file;
};
void write_pvd(const std::filesystem::path& pvd, const std::vector<PvdEntry>& entries);

}  // namespace rgbmesh
