// OFF (Geomview's Object File Format), ASCII: "OFF", the counts, one vertex per line, one face
// per line. VTK has no reader for it.

#include "parse_common.hpp"
#include "parsers.hpp"

namespace rgbmesh::detail {
namespace {

// "[ST][C][N]OFF": the 3D variants, whose extra per-vertex values are ignored.
bool is_off_header(std::string_view token) {
  for (const std::string_view prefix : {"ST", "C", "N"})
    if (token.substr(0, prefix.size()) == prefix) token.remove_prefix(prefix.size());
  return token == "OFF";
}

}  // namespace

PolygonSoup parse_off(std::string_view text, const std::string& path) {
  check_text(text, path);
  TokenLines lines(text, path);
  PolygonSoup soup;
  if (!lines.next_nonempty()) throw InputError(path + ": the file is empty");

  // The header is optional; the counts may follow it on the same line.
  std::size_t counts_at = 0;
  const std::string_view first = lines.tokens()[0];
  if (first.find("OFF") != std::string_view::npos) {
    if (!is_off_header(first))
      throw lines.error("unsupported OFF variant '" + printable(first) +
                        "' (only OFF, COFF, NOFF and STOFF are read)");
    if (lines.tokens().size() > 1 && lines.tokens()[1] == "BINARY")
      throw lines.error("binary OFF files are not supported");
    counts_at = 1;
    if (lines.tokens().size() == 1) {
      if (!lines.next_nonempty()) throw lines.error("the file ends before the counts 'vertices faces edges'");
      counts_at = 0;
    }
  }
  const auto& counts = lines.tokens();
  std::int64_t n_vertices = -1, n_faces = -1;
  if (counts.size() < counts_at + 2 || !parse_integer(counts[counts_at], n_vertices) ||
      !parse_integer(counts[counts_at + 1], n_faces) || n_vertices < 0 || n_faces < 0)
    throw lines.error("expected the counts 'vertices faces edges' as non-negative integers");

  // A corrupt count must not reserve more than the text could possibly hold.
  soup.points.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(n_vertices, text.size() / 6)));
  soup.faces.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(n_faces, text.size() / 8)));
  for (std::int64_t i = 0; i < n_vertices; ++i) {
    if (!lines.next_nonempty())
      throw lines.error("the file ends after " + std::to_string(i) + " of " + std::to_string(n_vertices) +
                        " vertices");
    soup.points.push_back(parse_point(lines, 0));
  }
  for (std::int64_t f = 0; f < n_faces; ++f) {
    if (!lines.next_nonempty())
      throw lines.error("the file ends after " + std::to_string(f) + " of " + std::to_string(n_faces) +
                        " faces");
    const auto& tokens = lines.tokens();
    std::int64_t n = 0;
    if (!parse_integer(tokens[0], n) || n < 0)
      throw lines.error("'" + printable(tokens[0]) + "' is not a vertex count");
    const auto found = static_cast<std::int64_t>(tokens.size()) - 1;
    if (found < n)
      throw lines.error("expected " + std::to_string(n) + " vertex indices, found " + std::to_string(found));
    std::vector<std::int64_t> face(static_cast<std::size_t>(n));
    for (std::int64_t k = 0; k < n; ++k)
      if (!parse_integer(tokens[k + 1], face[k]))
        throw lines.error("'" + printable(tokens[k + 1]) + "' is not a vertex index");
    soup.faces.push_back(std::move(face));
  }
  // A damaged face count would otherwise silently drop the faces after it.
  if (lines.next_nonempty())
    throw lines.error("data after the last of the " + std::to_string(n_faces) +
                      " faces that the header announces: the face count is wrong or the file is damaged");
  return soup;
}

}  // namespace rgbmesh::detail
