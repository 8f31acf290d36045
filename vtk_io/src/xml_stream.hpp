#pragma once
// Writing VTK XML files (.vtp, .vtu) block by block from arrays that are produced on demand.
//
// vtkXMLWriter needs every array of the data set in memory at once: for a mesh of millions of
// vertices that is a second copy of the mesh (about 100 bytes per vertex next to the mesh's
// 160) while it writes. Here each array is a function that fills any range of its tuples, and
// the file is written one batch of compressed blocks at a time, so writing needs the mesh plus
// a few MB. The file is the one VTK's writer makes with SetDataModeToAppended,
// EncodeAppendedDataOff and a 64-bit header (VTK XML file version 1.0): appended raw data,
// each array compressed in blocks by VTK's own compressors (vtkLZ4DataCompressor,
// vtkZLibDataCompressor), which VTK's readers and ParaView read as they read VTK's files.
//
// Blocks are compressed on every core: the fill functions are called from several threads at
// once, on disjoint ranges.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh::detail {

enum class XmlType { uint8, int32, int64, float64 };

// VTK's name of a type ("UInt8", "Int32", "Int64", "Float64").
const char* type_name(XmlType type);

struct XmlArray {
  std::string name;
  XmlType type = XmlType::float64;
  int components = 1;
  std::size_t tuples = 0;
  // Writes tuples [first, first + count) to `out`: count * components values of `type`.
  std::function<void(std::size_t first, std::size_t count, void* out)> fill;
};

// A PolyData (.vtp) of triangles or of vertex cells (a point cloud), or an UnstructuredGrid
// (.vtu) of triangles or of quadratic triangles (VTK_QUADRATIC_TRIANGLE: six nodes, the
// corners then the middles of edges 0-1, 1-2, 2-0). The offsets and cell types are made by
// the writer.
struct XmlDataSet {
  enum class Kind { poly_triangles, poly_vertices, grid_triangles, grid_quadratic_triangles };
  Kind kind = Kind::poly_triangles;
  std::size_t points = 0;
  std::size_t cells = 0;
  std::vector<XmlArray> field_data, point_data, cell_data;
  XmlArray coordinates;   // Float64, 3 components, one tuple per point
  XmlArray connectivity;  // Int32, 3 (triangles), 6 (quadratic triangles) or 1 (vertices) values per cell
};

// Writes `data` to `file` (a new file: replace_atomically's temporary). std::invalid_argument
// for arrays of the wrong size; std::runtime_error when the file cannot be written.
// `progress`, when set, is called with the fraction of the data written after every batch of
// blocks (not at 0 or 1: the caller reports those).
void write_vtk_xml(const std::filesystem::path& file, const XmlDataSet& data, Compression compression,
                   const std::function<void(double)>& progress);

// `value` with XML's special characters escaped, for an attribute value.
std::string xml_attribute(const std::string& value);

// An array filled from memory the caller keeps alive while the file is written.
XmlArray borrowed_array(std::string name, XmlType type, int components, std::size_t tuples, const void* values);

}  // namespace rgbmesh::detail
