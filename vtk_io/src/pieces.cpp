// A snapshot in pieces and their summary (.pvtp): the output of a run on several processes.

#include <string>
#include <vector>

#include "rgbmesh/vtk_io.hpp"
#include "xml_datasets.hpp"
#include "xml_stream.hpp"

namespace rgbmesh {

MeshSnapshot snapshot_piece(const MeshSnapshot& whole, const std::vector<std::int32_t>& part, std::int32_t which) {
  if (part.size() != whole.triangles.size())
    throw std::invalid_argument("snapshot_piece: one part per cell needed");
  CellPiece<3> cells = cell_piece(whole.triangles, whole.points.size(), part, which);
  MeshSnapshot piece;
  piece.triangles = std::move(cells.cells);
  const auto take = [](const auto& from, const std::vector<std::size_t>& rows, auto& to) {
    if (from.empty()) return;
    for (const std::size_t r : rows) to.push_back(from[r]);
  };
  take(whole.points, cells.point_rows, piece.points);
  take(whole.vertex_level, cells.point_rows, piece.vertex_level);
  take(whole.vertex_handle, cells.point_rows, piece.vertex_handle);
  take(whole.vertex_rule, cells.point_rows, piece.vertex_rule);  // sharp features: each point's rule
  take(whole.triangle_level, cells.cell_rows, piece.triangle_level);
  take(whole.triangle_color, cells.cell_rows, piece.triangle_color);
  take(whole.triangle_handle, cells.cell_rows, piece.triangle_handle);
  piece.point_data = array_rows(whole.point_data, cells.point_rows);
  piece.cell_data = array_rows(whole.cell_data, cells.cell_rows);
  return piece;
}

namespace {

// One array's declaration in a summary file.
std::string declaration(const std::string& name, detail::XmlType type, int components) {
  return "      <PDataArray type=\"" + std::string(detail::type_name(type)) + "\" Name=\"" + detail::xml_attribute(name) +
         "\" NumberOfComponents=\"" + std::to_string(components) + "\"/>\n";
}

// A summary file of pieces: `kind` is PPolyData or PUnstructuredGrid; the point and cell
// arrays' declarations, the points' type, and the pieces (relative to the summary's folder).
void write_summary(const std::filesystem::path& path, const char* kind, const std::string& point_arrays,
                   const std::string& cell_arrays, detail::XmlType points, const std::vector<std::string>& pieces) {
  std::string xml = "<?xml version=\"1.0\"?>\n<VTKFile type=\"" + std::string(kind) +
                    "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <" + kind +
                    " GhostLevel=\"0\">\n    <PPointData>\n" + point_arrays + "    </PPointData>\n    <PCellData>\n" +
                    cell_arrays + "    </PCellData>\n    <PPoints>\n" + declaration("Points", points, 3) + "    </PPoints>\n";
  for (const std::string& piece : pieces) xml += "    <Piece Source=\"" + detail::xml_attribute(piece) + "\"/>\n";
  xml += "  </" + std::string(kind) + ">\n</VTKFile>\n";
  write_text_atomically(path, xml);
}

}  // namespace

void write_pvtp(const std::filesystem::path& pvtp, const MeshSnapshot& like, const std::vector<std::string>& pieces) {
  // The arrays `like` is written with, from a one-point, one-cell stand-in (like may be the
  // whole mesh, or an empty piece); the RGB state belongs to the whole mesh, not the pieces.
  MeshSnapshot stand_in;
  stand_in.points.resize(1);
  stand_in.triangles.resize(1);
  if (!like.vertex_level.empty()) stand_in.vertex_level.resize(1);
  if (!like.vertex_rule.empty()) stand_in.vertex_rule.resize(1);
  if (!like.triangle_level.empty()) stand_in.triangle_level.resize(1);
  if (!like.triangle_color.empty()) stand_in.triangle_color.resize(1);
  for (const NamedArray& a : like.point_data)
    stand_in.point_data.push_back({a.name, a.components, std::vector<double>(static_cast<std::size_t>(a.components)), a.same_as_points});
  for (const NamedArray& a : like.cell_data)
    stand_in.cell_data.push_back({a.name, a.components, std::vector<double>(static_cast<std::size_t>(a.components)), false});
  const detail::XmlDataSet d = detail::snapshot_data_set(stand_in, false);
  const auto declarations = [](const std::vector<detail::XmlArray>& arrays) {
    std::string xml;
    for (const detail::XmlArray& a : arrays) xml += declaration(a.name, a.type, a.components);
    return xml;
  };
  write_summary(pvtp, "PPolyData", declarations(d.point_data), declarations(d.cell_data), d.coordinates.type, pieces);
}

void write_quadratic_pvtu(const std::filesystem::path& pvtu, const std::vector<NamedArray>& point_data,
                          const std::vector<NamedArray>& cell_data, const std::vector<std::string>& pieces) {
  // write_quadratic_triangles writes the points and every array as Float64.
  const auto declarations = [](const std::vector<NamedArray>& arrays) {
    std::string xml;
    for (const NamedArray& a : arrays) xml += declaration(a.name, detail::XmlType::float64, a.components);
    return xml;
  };
  write_summary(pvtu, "PUnstructuredGrid", declarations(point_data), declarations(cell_data), detail::XmlType::float64,
                pieces);
}

}  // namespace rgbmesh
