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
  MeshSnapshot piece;
  std::vector<std::int32_t> point_of(whole.points.size(), -1);
  std::vector<std::size_t> points, cells;
  for (std::size_t c = 0; c < whole.triangles.size(); ++c) {
    if (part[c] != which) continue;
    cells.push_back(c);
    std::array<std::int32_t, 3> t{};
    for (int k = 0; k < 3; ++k) {
      const auto p = static_cast<std::size_t>(whole.triangles[c][k]);
      if (point_of[p] < 0) {
        point_of[p] = static_cast<std::int32_t>(points.size());
        points.push_back(p);
      }
      t[k] = point_of[p];
    }
    piece.triangles.push_back(t);
  }
  const auto take = [](const auto& from, const std::vector<std::size_t>& rows, auto& to) {
    if (from.empty()) return;
    for (const std::size_t r : rows) to.push_back(from[r]);
  };
  take(whole.points, points, piece.points);
  take(whole.vertex_level, points, piece.vertex_level);
  take(whole.vertex_handle, points, piece.vertex_handle);
  take(whole.triangle_level, cells, piece.triangle_level);
  take(whole.triangle_color, cells, piece.triangle_color);
  take(whole.triangle_handle, cells, piece.triangle_handle);
  const auto take_arrays = [](const std::vector<NamedArray>& from, const std::vector<std::size_t>& rows,
                              std::vector<NamedArray>& to) {
    for (const NamedArray& a : from) {
      NamedArray b{a.name, a.components, {}, a.same_as_points};
      if (!a.same_as_points) {
        const auto k = static_cast<std::size_t>(a.components);
        for (const std::size_t r : rows)
          b.values.insert(b.values.end(), a.values.begin() + static_cast<std::ptrdiff_t>(r * k),
                          a.values.begin() + static_cast<std::ptrdiff_t>((r + 1) * k));
      }
      to.push_back(std::move(b));
    }
  };
  take_arrays(whole.point_data, points, piece.point_data);
  take_arrays(whole.cell_data, cells, piece.cell_data);
  return piece;
}

namespace {

std::string declarations(const std::vector<detail::XmlArray>& arrays) {
  std::string xml;
  for (const detail::XmlArray& a : arrays)
    xml += "      <PDataArray type=\"" + std::string(detail::type_name(a.type)) + "\" Name=\"" + detail::xml_attribute(a.name) +
           "\" NumberOfComponents=\"" + std::to_string(a.components) + "\"/>\n";
  return xml;
}

}  // namespace

void write_pvtp(const std::filesystem::path& pvtp, const MeshSnapshot& like, const std::vector<std::string>& pieces) {
  // The arrays `like` is written with, from a one-point, one-cell stand-in (like may be the
  // whole mesh, or an empty piece); the RGB state belongs to the whole mesh, not the pieces.
  MeshSnapshot stand_in;
  stand_in.points.resize(1);
  stand_in.triangles.resize(1);
  if (!like.vertex_level.empty()) stand_in.vertex_level.resize(1);
  if (!like.triangle_level.empty()) stand_in.triangle_level.resize(1);
  if (!like.triangle_color.empty()) stand_in.triangle_color.resize(1);
  for (const NamedArray& a : like.point_data)
    stand_in.point_data.push_back({a.name, a.components, std::vector<double>(static_cast<std::size_t>(a.components)), a.same_as_points});
  for (const NamedArray& a : like.cell_data)
    stand_in.cell_data.push_back({a.name, a.components, std::vector<double>(static_cast<std::size_t>(a.components)), false});
  const detail::XmlDataSet d = detail::snapshot_data_set(stand_in, false);
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"PPolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <PPolyData GhostLevel=\"0\">\n"
      "    <PPointData>\n" + declarations(d.point_data) + "    </PPointData>\n"
      "    <PCellData>\n" + declarations(d.cell_data) + "    </PCellData>\n"
      "    <PPoints>\n"
      "      <PDataArray type=\"" + std::string(detail::type_name(d.coordinates.type)) +
      "\" Name=\"Points\" NumberOfComponents=\"3\"/>\n"
      "    </PPoints>\n";
  for (const std::string& piece : pieces) xml += "    <Piece Source=\"" + detail::xml_attribute(piece) + "\"/>\n";
  xml +=
      "  </PPolyData>\n"
      "</VTKFile>\n";
  write_text_atomically(pvtp, xml);
}

void write_quadratic_pvtu(const std::filesystem::path& pvtu, const std::vector<NamedArray>& point_data,
                          const std::vector<NamedArray>& cell_data, const std::vector<std::string>& pieces) {
  // write_quadratic_triangles writes the points and every array as Float64.
  const auto float64 = [](const std::vector<NamedArray>& arrays) {
    std::string xml;
    for (const NamedArray& a : arrays)
      xml += "      <PDataArray type=\"" + std::string(detail::type_name(detail::XmlType::float64)) + "\" Name=\"" +
             detail::xml_attribute(a.name) + "\" NumberOfComponents=\"" + std::to_string(a.components) + "\"/>\n";
    return xml;
  };
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <PUnstructuredGrid GhostLevel=\"0\">\n"
      "    <PPointData>\n" + float64(point_data) + "    </PPointData>\n"
      "    <PCellData>\n" + float64(cell_data) + "    </PCellData>\n"
      "    <PPoints>\n"
      "      <PDataArray type=\"" + std::string(detail::type_name(detail::XmlType::float64)) +
      "\" Name=\"Points\" NumberOfComponents=\"3\"/>\n"
      "    </PPoints>\n";
  for (const std::string& piece : pieces) xml += "    <Piece Source=\"" + detail::xml_attribute(piece) + "\"/>\n";
  xml +=
      "  </PUnstructuredGrid>\n"
      "</VTKFile>\n";
  write_text_atomically(pvtu, xml);
}

}  // namespace rgbmesh
