// Wavefront OBJ: vertices and faces; every other statement is skipped.

#include "parse_common.hpp"
#include "parsers.hpp"

namespace rgbmesh::detail {

PolygonSoup parse_obj(std::string_view text, const std::string& path, const ReadOptions& options) {
  check_text(text, path);
  TokenLines lines(text, path);
  PolygonSoup soup;
  // Faces may refer to vertices defined further down; those are checked once all are known.
  struct ForwardReference {
    std::int64_t line, index;
  };
  std::vector<ForwardReference> forward;
  while (lines.next_nonempty()) {
    while (!lines.tokens().empty() && lines.tokens().back().back() == '\\' && lines.continue_line()) {
    }
    if (lines.tokens().empty()) continue;
    const auto& tokens = lines.tokens();
    const std::string_view command = tokens[0];
    if (command == "v") {
      soup.points.push_back(parse_point(lines, 1));
    } else if (command == "f" || command == "fo") {
      std::vector<std::int64_t> face;
      face.reserve(tokens.size() - 1);
      const auto defined = static_cast<std::int64_t>(soup.points.size());
      for (std::size_t k = 1; k < tokens.size(); ++k) {
        // "v", "v/vt", "v//vn" or "v/vt/vn": only the vertex matters.
        const std::string_view vertex = tokens[k].substr(0, tokens[k].find('/'));
        std::int64_t index = 0;
        if (!parse_integer(vertex, index))
          throw lines.error("'" + printable(tokens[k]) + "' is not a vertex reference");
        if (index == 0) throw lines.error("vertex index 0 is invalid (OBJ counts vertices from 1)");
        if (index < 0) {
          if (-index > defined)
            throw lines.error("relative vertex index " + std::to_string(index) +
                              " points before the first vertex (" + std::to_string(defined) +
                              " defined so far)");
          index += defined;
        } else {
          --index;
          if (index >= defined) forward.push_back({lines.number(), index});
        }
        face.push_back(index);
      }
      soup.faces.push_back(std::move(face));
    } else if (command == "p" && options.skip_vertex_cells) {
      continue;
    } else if (command == "l" || command == "p" || command == "curv" || command == "curv2" ||
               command == "surf") {
      const char* what = command == "l" ? "polylines" : command == "p" ? "points" : "free-form geometry";
      throw lines.error("'" + std::string(command) + "' elements (" + what + ") are not surface polygons");
    } else if (!std::isalpha(static_cast<unsigned char>(command[0]))) {
      // Statements other than vertices and faces (vt, vn, g, o, s, usemtl, ...) are skipped, but
      // a line that is no statement at all means the file is damaged or not OBJ.
      throw lines.error("'" + printable(command) + "' is not an OBJ statement");
    }
  }
  const auto n = static_cast<std::int64_t>(soup.points.size());
  for (const auto& ref : forward)
    if (ref.index >= n)
      throw InputError(path + ": line " + std::to_string(ref.line) + ": vertex index " +
                       std::to_string(ref.index + 1) + " is out of range (the file has " + std::to_string(n) +
                       " vertices)");
  return soup;
}

}  // namespace rgbmesh::detail
