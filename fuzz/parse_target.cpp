// In-memory fuzz targets: the parsers that take a file's bytes (vtk_io/src/parsers.hpp) and the
// validation of VTK XML files before VTK sees them (xml_check.hpp). RGBMESH_FUZZ_FORMAT names
// the one this executable fuzzes: off, obj, ply, vtk, stl, xyz (also .pwn) or xml (.vtp, .vtu).
//
// The input is handed over as the reader gets it from a mapped file (read.cpp): text formats
// without a UTF-8 byte-order mark, STL and XML as they are. libFuzzer's buffer ends exactly at
// the input's end, so a read one byte past it is an ASan report (a mapped file would hide it in
// the rest of its last page).

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_support.hpp"
#include "input_file.hpp"
#include "parsers.hpp"
#include "xml_check.hpp"

namespace {

using namespace rgbmesh;
using rgbmesh::fuzz::accepted;

constexpr std::string_view format = RGBMESH_FUZZ_FORMAT;

// As mesh reading calls it, and as point-cloud reading does (vertex cells skipped, normals kept).
template <class Parse>
void mesh_and_cloud(Parse&& parse) {
  accepted([&] { parse(detail::ReadOptions{}); });
  std::vector<Vec3> normals;
  detail::ReadOptions cloud;
  cloud.skip_vertex_cells = true;
  cloud.normals = &normals;
  accepted([&] { parse(cloud); });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const std::string path = "fuzz." + std::string(format);
  const std::string_view text = detail::without_utf8_bom(bytes);
  if (format == "off") {
    accepted([&] { detail::parse_off(text, path); });
  } else if (format == "obj") {
    mesh_and_cloud([&](const detail::ReadOptions& options) { detail::parse_obj(text, path, options); });
  } else if (format == "ply") {
    mesh_and_cloud([&](const detail::ReadOptions& options) { detail::parse_ply(text, path, options); });
  } else if (format == "vtk") {
    mesh_and_cloud(
        [&](const detail::ReadOptions& options) { detail::parse_legacy_vtk(text, path, options); });
  } else if (format == "stl") {
    accepted([&] { detail::parse_stl(bytes, path); });
  } else if (format == "xyz") {
    std::vector<Vec3> normals;
    accepted([&] { detail::parse_xyz(text, path, normals); });
  } else if (format == "3mf") {
    accepted([&] { detail::parse_3mf(bytes, path); });  // lib3mf (uninstrumented) unzips and parses
  } else if (format == "xml") {
    accepted([&] { detail::check_vtk_xml(bytes, path, "PolyData"); });
    accepted([&] { detail::check_vtk_xml(bytes, path, "UnstructuredGrid"); });
  } else {
    static_assert(format == "off" || format == "obj" || format == "ply" || format == "vtk" ||
                      format == "stl" || format == "xyz" || format == "xml" || format == "3mf",
                  "RGBMESH_FUZZ_FORMAT: off, obj, ply, vtk, stl, xyz, xml or 3mf");
  }
  return 0;
}
