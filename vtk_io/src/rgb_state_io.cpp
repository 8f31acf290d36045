// The RGB state as VTK arrays (rgb_state_io.hpp), and read_rgb_mesh (vtk_io.hpp). Everything
// read here is checked before use: array types, component and tuple counts, and that each value
// is an integer in range where an index is expected; restore_state checks the rest.

#include "rgb_state_io.hpp"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkPointSet.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkTypeInt32Array.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "input_file.hpp"
#include "io_common.hpp"
#include "parsers.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh {
namespace detail {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void bad(const fs::path& path, const std::string& what) {
  throw InputError(path.string() + ": inconsistent RGB state: " + what);
}

// The array `name` with `components` components and `tuples` tuples (any tuple count if
// tuples < 0); nullptr when absent.
vtkDataArray* array_of(vtkFieldData* data, const char* name, int components, vtkIdType tuples, const fs::path& path,
                       const char* where) {
  if (data == nullptr) return nullptr;
  vtkDataArray* a = vtkDataArray::SafeDownCast(data->GetAbstractArray(name));
  if (a == nullptr) {
    if (data->GetAbstractArray(name) != nullptr) bad(path, std::string(where) + " array '" + name + "' is not numeric");
    return nullptr;
  }
  if (a->GetNumberOfComponents() != components)
    bad(path, std::string(where) + " array '" + name + "' has " + std::to_string(a->GetNumberOfComponents()) +
                  " components, not " + std::to_string(components));
  if (tuples >= 0 && a->GetNumberOfTuples() != tuples)
    bad(path, std::string(where) + " array '" + name + "' has " + std::to_string(a->GetNumberOfTuples()) +
                  " tuples, not " + std::to_string(tuples));
  return a;
}

// Every value of an integer-valued array, checked to be an integer in [lo, hi].
std::vector<std::int32_t> integers(vtkDataArray* a, std::int64_t lo, std::int64_t hi, const fs::path& path) {
  const vtkIdType n = a->GetNumberOfTuples() * a->GetNumberOfComponents();
  std::vector<std::int32_t> out(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i) {
    const double x = a->GetComponent(i / a->GetNumberOfComponents(), static_cast<int>(i % a->GetNumberOfComponents()));
    if (!(x >= static_cast<double>(lo) && x <= static_cast<double>(hi)) || x != std::floor(x))
      bad(path, std::string("array '") + a->GetName() + "' value " + std::to_string(i) + " is " + shortest(x) +
                    ", not an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
    out[static_cast<std::size_t>(i)] = static_cast<std::int32_t>(x);
  }
  return out;
}

std::vector<Vec3> vectors(vtkDataArray* a) {
  std::vector<Vec3> out;
  if (a == nullptr) return out;
  out.reserve(static_cast<std::size_t>(a->GetNumberOfTuples()));
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i) {
    double p[3];
    a->GetTuple(i, p);
    out.emplace_back(p[0], p[1], p[2]);
  }
  return out;
}

// Version 2's sharp features (rgb_state_io.hpp); from_triangles checks what they name.
SharpFeatures sharp_features_of(vtkFieldData* field, const fs::path& path) {
  SharpFeatures s;
  vtkDataArray* edges = array_of(field, kSharpEdgesArray, 2, -1, path, "field data");
  vtkDataArray* edge_sharpness = array_of(field, kSharpEdgeSharpnessArray, 1, -1, path, "field data");
  vtkDataArray* vertices = array_of(field, kSharpVerticesArray, 1, -1, path, "field data");
  vtkDataArray* vertex_sharpness = array_of(field, kSharpVertexSharpnessArray, 1, -1, path, "field data");
  vtkDataArray* method = array_of(field, kCreaseMethodArray, 1, 1, path, "field data");
  const auto values = [&](vtkDataArray* a, vtkDataArray* of, const char* name) {
    std::vector<float> out;
    if ((a == nullptr) != (of == nullptr) || (a != nullptr && a->GetNumberOfTuples() != of->GetNumberOfTuples()))
      bad(path, std::string("the array '") + name + "' does not match its vertices");
    if (a == nullptr) return out;
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i) {
      const double x = a->GetComponent(i, 0);
      if (!(x >= 0.0 && x <= 1e30)) bad(path, std::string("array '") + name + "' value " + std::to_string(i) + " is " + shortest(x));
      out.push_back(static_cast<float>(x));
    }
    return out;
  };
  const std::vector<float> es = values(edge_sharpness, edges, kSharpEdgeSharpnessArray);
  const std::vector<float> vs = values(vertex_sharpness, vertices, kSharpVertexSharpnessArray);
  if (edges != nullptr) {
    const std::vector<std::int32_t> ends = integers(edges, 0, INT32_MAX, path);
    for (std::size_t i = 0; i < es.size(); ++i) s.edges.push_back({ends[2 * i], ends[2 * i + 1], es[i]});
  }
  if (vertices != nullptr) {
    const std::vector<std::int32_t> ids = integers(vertices, 0, INT32_MAX, path);
    for (std::size_t i = 0; i < vs.size(); ++i) s.vertices.push_back({ids[i], vs[i]});
  }
  if (method != nullptr) s.method = integers(method, 0, 1, path)[0] == 1 ? CreaseMethod::chaikin : CreaseMethod::uniform;
  return s;
}

std::vector<std::uint8_t> bytes_of(vtkDataArray* a, const fs::path& path) {
  std::vector<std::uint8_t> out;
  if (a == nullptr) return out;
  for (const std::int32_t x : integers(a, 0, 255, path)) out.push_back(static_cast<std::uint8_t>(x));
  return out;
}

}  // namespace

void read_rgb_state(vtkDataSet& data, const fs::path& path, SavedState& out) {
  vtkFieldData* field = data.GetFieldData();
  vtkPointData* point_data = data.GetPointData();
  const vtkIdType n = data.GetNumberOfPoints();
  vtkDataArray* version = array_of(field, kStateVersionArray, 1, 1, path, "field data");
  vtkDataArray* base_points = array_of(field, kBasePointsArray, 3, -1, path, "field data");
  vtkDataArray* base_triangles = array_of(field, kBaseTrianglesArray, 3, -1, path, "field data");
  vtkDataArray* base_vertex = array_of(point_data, kBaseVertexArray, 1, n, path, "point data");
  vtkDataArray* parents = array_of(point_data, kParentsArray, 2, n, path, "point data");
  vtkDataArray* piece_base_vertex = array_of(field, kPieceBaseVertexArray, 1, -1, path, "field data");
  vtkDataArray* piece_parents = array_of(field, kPieceParentsArray, 2, -1, path, "field data");
  if (piece_base_vertex != nullptr || piece_parents != nullptr) {
    // A piece: its entries (its points first, then their ancestors) in field data.
    for (const auto& [array, name] : {std::pair{version, kStateVersionArray},
                                      {base_points, kBasePointsArray},
                                      {base_triangles, kBaseTrianglesArray},
                                      {piece_base_vertex, kPieceBaseVertexArray},
                                      {piece_parents, kPieceParentsArray}})
      if (array == nullptr) bad(path, std::string("the array '") + name + "' is missing");
    if (piece_base_vertex->GetNumberOfTuples() != piece_parents->GetNumberOfTuples() ||
        piece_base_vertex->GetNumberOfTuples() < n)
      bad(path, "the piece's arrays have " + std::to_string(piece_base_vertex->GetNumberOfTuples()) +
                    " and " + std::to_string(piece_parents->GetNumberOfTuples()) + " entries for " +
                    std::to_string(n) + " points");
    RgbState s;
    s.version = integers(version, INT32_MIN, INT32_MAX, path)[0];
    s.base_points = vectors(base_points);
    const std::vector<std::int32_t> corners = integers(base_triangles, 0, INT32_MAX, path);
    for (std::size_t i = 0; i + 2 < corners.size(); i += 3)
      s.base_triangles.push_back({corners[i], corners[i + 1], corners[i + 2]});
    s.sharp = sharp_features_of(field, path);
    s.base_vertex = integers(piece_base_vertex, -1, INT32_MAX, path);
    const std::vector<std::int32_t> ends = integers(piece_parents, -1, INT32_MAX, path);
    for (std::size_t i = 0; i + 1 < ends.size(); i += 2) s.parents.push_back({ends[i], ends[i + 1]});
    out.piece_state = std::move(s);
    if (auto* points = vtkPointSet::SafeDownCast(&data); points != nullptr && points->GetPoints() != nullptr)
      out.single_precision_points = points->GetPoints()->GetDataType() == VTK_FLOAT;
    return;
  }
  const int present = (version != nullptr) + (base_points != nullptr) + (base_triangles != nullptr) +
                      (base_vertex != nullptr) + (parents != nullptr);
  if (present == 0) return;  // no state: a base mesh
  if (present < 5) {
    for (const auto& [array, name] : {std::pair{version, kStateVersionArray}, {base_points, kBasePointsArray},
                                      {base_triangles, kBaseTrianglesArray}, {base_vertex, kBaseVertexArray},
                                      {parents, kParentsArray}})
      if (array == nullptr) bad(path, std::string("the array '") + name + "' is missing");
  }
  RgbState s;
  s.version = integers(version, INT32_MIN, INT32_MAX, path)[0];
  if (s.version < 1 || s.version > RgbState::kVersion)
    bad(path, "version " + std::to_string(s.version) + " is not supported (this build reads versions 1 to " +
                  std::to_string(RgbState::kVersion) + ")");
  s.sharp = sharp_features_of(field, path);
  s.base_points = vectors(base_points);
  const std::vector<std::int32_t> corners = integers(base_triangles, 0, INT32_MAX, path);
  for (std::size_t i = 0; i + 2 < corners.size(); i += 3) s.base_triangles.push_back({corners[i], corners[i + 1], corners[i + 2]});
  s.base_vertex = integers(base_vertex, -1, INT32_MAX, path);
  const std::vector<std::int32_t> ends = integers(parents, -1, INT32_MAX, path);
  s.parents.reserve(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i + 1 < ends.size(); i += 2) s.parents.push_back({ends[i], ends[i + 1]});
  out.state = std::move(s);

  RestoreExpectations& x = out.expected;
  const vtkIdType cells = data.GetNumberOfCells();
  x.vertex_level = bytes_of(array_of(point_data, "level", 1, n, path, "point data"), path);
  x.triangle_level = bytes_of(array_of(data.GetCellData(), "level", 1, cells, path, "cell data"), path);
  x.triangle_color = bytes_of(array_of(data.GetCellData(), "color", 1, cells, path, "cell data"), path);
  x.control_points = vectors(array_of(point_data, "control_point", 3, n, path, "point data"));
  x.limits = vectors(array_of(point_data, "limit", 3, n, path, "point data"));
  if (auto* points = vtkPointSet::SafeDownCast(&data); points != nullptr && points->GetPoints() != nullptr)
    out.single_precision_points = points->GetPoints()->GetDataType() == VTK_FLOAT;
}

namespace {

// The file's Points are what ParaView shows and what a user edits, but the restored mesh takes
// its positions from the state alone: an edit would be dropped without a word. So every point
// must be where the state puts it as rgbmesh writes points: all at their shown control points
// (refine, convert), all at their limit positions (refine --limit, adapt --geometry loop), or
// all at those projected onto the unit sphere (adapt --geometry sphere). Within 1e-9 of the
// points' bounding-box diagonal, as control_point and limit are checked, plus the rounding of
// Float32 where the file stores Points so (2^-24 of each coordinate; twice that for margin).
void check_points(const fs::path& path, const std::vector<Vec3>& points, RestoredMesh& r, bool single_precision) {
  if (points.empty()) return;
  r.mesh.compute_limits();  // leaves the mesh as it is
  // 0: the shown control point, 1: the limit position, 2: that on the unit sphere.
  const auto position = [&](int kind, std::size_t i) {
    if (kind == 0) return r.mesh.control_point(r.vertex[i]);
    const Vec3 p = r.mesh.limit_position(r.vertex[i]);
    return kind == 1 ? p : p * (1.0 / norm(p));
  };
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& p : points) {
    lo = Vec3(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
    hi = Vec3(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
  }
  const double absolute = 1e-9 * std::max(norm(hi - lo), 1e-300);
  const double relative = single_precision ? std::ldexp(1.0, -23) : 0.0;
  // The kind that matches the longest run of points is the one the file was written with; its
  // first mismatch is the point to name.
  std::size_t worst = 0;
  double distance = 0;
  for (int kind = 0; kind < 3; ++kind) {
    std::size_t i = 0;
    double d = 0;
    for (; i < points.size(); ++i) {
      const Vec3 expected = position(kind, i);
      d = norm(points[i] - expected);
      if (!(d <= absolute + relative * norm(expected))) break;
    }
    if (i == points.size()) return;
    if (i >= worst) {
      worst = i;
      distance = d;
    }
  }
  char away[32];
  std::snprintf(away, sizeof away, "%.3g", distance);
  bad(path, "point " + std::to_string(worst) + ": its position (Points) is " + away +
                " away from where the state puts it (moved points? the state decides where points are)");
}

}  // namespace

}  // namespace detail

namespace {

// A file's cells as the triangles of its state: each a triangle of its points (InputError
// naming the cell otherwise).
std::vector<std::array<std::int32_t, 3>> triangles_with_state(const std::filesystem::path& path,
                                                               const PolygonSoup& soup) {
  std::vector<std::array<std::int32_t, 3>> out;
  out.reserve(soup.faces.size());
  for (std::size_t j = 0; j < soup.faces.size(); ++j) {
    const auto& f = soup.faces[j];
    if (f.size() != 3)
      detail::bad(path, "cell " + std::to_string(j) + " has " + std::to_string(f.size()) +
                            " vertices (a file with a state has triangles only)");
    for (const std::int64_t v : f)
      if (v < 0 || v >= static_cast<std::int64_t>(soup.points.size()))
        detail::bad(path, "cell " + std::to_string(j) + " names point " + std::to_string(v) + " of " +
                              std::to_string(soup.points.size()));
    out.push_back({static_cast<std::int32_t>(f[0]), static_cast<std::int32_t>(f[1]), static_cast<std::int32_t>(f[2])});
  }
  return out;
}

}  // namespace

RgbMeshFile read_rgb_mesh(const std::filesystem::path& path, const SoupOptions& options) {
  detail::SavedState saved;
  detail::ReadOptions read_options;
  read_options.saved_state = &saved;
  const PolygonSoup soup = detail::read_mesh_soup(path, read_options);
  RgbMeshFile file;
  if (!saved.state) {
    try {
      TriangleMeshData data = prepare_triangle_mesh(soup, options);
      file.notes = std::move(data.notes);
      file.mesh = RgbMesh::from_triangles(data.points, data.triangles, data.sharp);
    } catch (const InputError& e) {
      detail::rethrow_for_file(path, e);
    }
    return file;
  }
  // The file's cells are the triangles as written, in the state's point numbering.
  saved.expected.triangles = triangles_with_state(path, soup);
  RestoredMesh restored;
  try {
    restored = restore_state(*saved.state, saved.expected);
  } catch (const InputError& e) {
    throw InputError(path.string() + ": " + e.what());
  }
  detail::check_points(path, soup.points, restored, saved.single_precision_points);
  file.mesh = std::move(restored.mesh);
  file.restored = true;
  // The state is the mesh exactly as rgbmesh wrote it, checked point by point: nothing to repair,
  // and repairing would break the state.
  if (options.repair) file.notes.push_back("the file has an RGB state: restored exactly, not repaired");
  return file;
}

namespace {

namespace fs = std::filesystem;

// The pieces a summary (.pvtp) names, relative to its folder: file names only (a summary
// rgbmesh writes names the pieces beside it; anything else is refused, not followed).
std::vector<std::string> piece_sources(const fs::path& summary) {
  const detail::InputFile file(summary);
  const std::string_view xml = file.bytes();
  if (xml.find("<VTKFile") == std::string_view::npos || xml.find("PPolyData") == std::string_view::npos)
    throw InputError(summary.string() + ": not a VTK summary of polygon pieces (.pvtp)");
  std::vector<std::string> out;
  const std::string_view tag = "<Piece Source=\"";
  for (std::size_t at = xml.find(tag); at != std::string_view::npos; at = xml.find(tag, at + 1)) {
    const std::size_t from = at + tag.size(), to = xml.find('"', from);
    if (to == std::string_view::npos) throw InputError(summary.string() + ": a Piece's Source is not closed");
    const std::string name(xml.substr(from, to - from));
    if (name.empty() || name.find_first_of("/\\&<>") != std::string::npos || name == "." || name == "..")
      throw InputError(summary.string() + ": piece " + std::to_string(out.size()) +
                       " is not a file name beside the summary (rgbmesh writes its pieces there)");
    out.push_back(name);
  }
  if (out.empty()) throw InputError(summary.string() + ": names no pieces");
  return out;
}

}  // namespace

RgbMeshFile read_rgb_pieces(const std::filesystem::path& summary) {
  const std::vector<std::string> sources = piece_sources(summary);
  struct Piece {
    fs::path path;
    PolygonSoup soup;
    detail::SavedState saved;
  };
  std::vector<Piece> pieces(sources.size());
  std::vector<RgbState> states;
  for (std::size_t k = 0; k < sources.size(); ++k) {
    Piece& piece = pieces[k];
    piece.path = summary.parent_path() / sources[k];
    detail::ReadOptions read_options;
    read_options.saved_state = &piece.saved;
    piece.soup = detail::read_mesh_soup(piece.path, read_options);
    if (!piece.saved.piece_state)
      throw InputError(piece.path.string() +
                       ": carries no piece state (written before pieces could be resumed?)");
    states.push_back(std::move(*piece.saved.piece_state));
    piece.saved.piece_state.reset();
  }
  std::vector<std::vector<std::int32_t>> entry_of;
  RgbState whole;
  RestoreExpectations expected;
  try {
    whole = join_piece_states(states, entry_of);
  } catch (const InputError& e) {
    throw InputError(summary.string() + ": " + e.what());
  }
  // The pieces' cells are the whole mesh's triangles, each once.
  for (std::size_t k = 0; k < pieces.size(); ++k)
    for (std::array<std::int32_t, 3> t : triangles_with_state(pieces[k].path, pieces[k].soup)) {
      for (std::int32_t& c : t) c = entry_of[k][static_cast<std::size_t>(c)];
      expected.triangles.push_back(t);
    }
  RestoredMesh restored;
  try {
    restored = restore_state(whole, expected);
  } catch (const InputError& e) {
    throw InputError(summary.string() + ": " + e.what());
  }
  // Each piece's Points where the restored mesh puts them.
  std::vector<VertexHandle> all = std::move(restored.vertex);
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    restored.vertex.clear();
    for (std::size_t i = 0; i < pieces[k].soup.points.size(); ++i)
      restored.vertex.push_back(all[static_cast<std::size_t>(entry_of[k][i])]);
    detail::check_points(pieces[k].path, pieces[k].soup.points, restored,
                         pieces[k].saved.single_precision_points);
  }
  RgbMeshFile file;
  file.mesh = std::move(restored.mesh);
  file.restored = true;
  return file;
}

}  // namespace rgbmesh
