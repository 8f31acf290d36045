#pragma once
// The validation of a VTK XML file (.vtp, .vtu) before VTK's reader sees it.
//
// VTK 9.1's XML readers trust the file: a negative count crashes them, a compressed array whose
// header says 0 blocks makes them read through a null pointer, a negative component count makes
// them resize a vector to 2^64 elements, and they allocate whatever the counts announce before
// reading a byte of data. So the whole header is checked here, against the file: the XML (well
// formed up to the appended data), the file attributes (type, byte_order, header_type,
// compressor), every Piece count (a non-negative integer, backed by an array that the file
// holds), and every DataArray: type, NumberOfComponents, format (ascii, binary, appended),
// offset within the appended data, and the size header of binary data (byte count, or block
// count and sizes when compressed) against the values the counts require and the bytes the file
// has. The cell offsets are decoded, since VTK sizes the connectivity by the last one, and so are
// the cell types of unstructured grids, since VTK leaks them when it fails to read them. Every
// ASCII value must be a number of its array's type (VTK silently reads "1,5" as 1 and 300 as a
// UInt8 44), and no data section may hold two arrays of one name (VTK then reads through a null
// pointer).
//
// Files as VTK and ParaView write them pass: ascii, inline base64, appended raw or base64, any
// of VTK's compressors, 32- or 64-bit headers, either byte order.

#include <string>
#include <string_view>

namespace rgbmesh::detail {

// `data`: the whole file. `data_set`: "PolyData" (.vtp) or "UnstructuredGrid" (.vtu).
// InputError "<path>: cannot read: <what is wrong>" on the first problem.
void check_vtk_xml(std::string_view data, const std::string& path, std::string_view data_set);

}  // namespace rgbmesh::detail
