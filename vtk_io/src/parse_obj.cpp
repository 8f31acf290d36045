// Wavefront OBJ: vertices, faces and OpenSubdiv's sharpness tags; every other statement is
// skipped.

#include <set>

#include "parse_common.hpp"
#include "parsers.hpp"

namespace rgbmesh::detail {

namespace {

// OpenSubdiv's tag line (regression/common/shape_utils.cpp writes and reads them):
// "t NAME nI/nF/nS" then nI integers, nF numbers and nS words. Vertices count from 0.
void parse_tag(const TokenLines& lines, PolygonSoup& soup, std::set<std::string>& ignored) {
  const auto& tokens = lines.tokens();
  if (tokens.size() < 3) throw lines.error("a tag needs a name and its counts (t NAME nI/nF/nS ...)");
  const std::string name(tokens[1]);
  std::int64_t counts[3];
  {
    const std::string_view c = tokens[2];
    const std::size_t s1 = c.find('/'), s2 = s1 == std::string_view::npos ? s1 : c.find('/', s1 + 1);
    if (s2 == std::string_view::npos || !parse_integer(c.substr(0, s1), counts[0]) ||
        !parse_integer(c.substr(s1 + 1, s2 - s1 - 1), counts[1]) || !parse_integer(c.substr(s2 + 1), counts[2]) ||
        counts[0] < 0 || counts[1] < 0 || counts[2] < 0)
      throw lines.error("'" + printable(c) + "' is not a tag's argument counts (nI/nF/nS)");
  }
  if (static_cast<std::int64_t>(tokens.size()) - 3 != counts[0] + counts[1] + counts[2])
    throw lines.error("tag '" + printable(name) + "' declares " + std::to_string(counts[0] + counts[1] + counts[2]) +
                      " arguments but has " + std::to_string(tokens.size() - 3));
  std::vector<std::int64_t> ints;
  std::vector<float> floats;
  std::size_t k = 3;
  for (std::int64_t i = 0; i < counts[0]; ++i, ++k) {
    std::int64_t v = 0;
    if (!parse_integer(tokens[k], v)) throw lines.error("'" + printable(tokens[k]) + "' is not an integer");
    ints.push_back(v);
  }
  for (std::int64_t i = 0; i < counts[1]; ++i, ++k) {
    double x = 0;
    if (!parse_number(tokens[k], x)) throw lines.error("'" + printable(tokens[k]) + "' is not a number");
    if (!(x >= 0.0) || !std::isfinite(x))
      throw lines.error("sharpness " + printable(tokens[k]) + " is not a number of 0 or more (10: infinitely sharp)");
    floats.push_back(static_cast<float>(x));
  }
  const auto sharpness = [&](std::size_t i) { return floats.size() == 1 ? floats[0] : floats[i]; };
  if (name == "crease") {
    if (ints.empty() || ints.size() % 2 != 0 || (floats.size() != 1 && floats.size() != ints.size() / 2))
      throw lines.error("a crease tag needs pairs of vertices and one sharpness, or one per pair (t crease 2/1/0 A B S)");
    for (std::size_t i = 0; i < ints.size(); i += 2) {
      if (ints[i] < 0 || ints[i + 1] < 0 || ints[i] > INT32_MAX || ints[i + 1] > INT32_MAX)
        throw lines.error("crease tag vertex " + std::to_string(ints[ints[i] < 0 ? i : i + 1]) +
                          " is out of range (tags count vertices from 0)");
      soup.sharp.edges.push_back(
          {static_cast<std::int32_t>(ints[i]), static_cast<std::int32_t>(ints[i + 1]), sharpness(i / 2)});
    }
  } else if (name == "corner") {
    if (ints.empty() || (floats.size() != 1 && floats.size() != ints.size()))
      throw lines.error("a corner tag needs vertices and one sharpness, or one per vertex (t corner 1/1/0 V S)");
    for (std::size_t i = 0; i < ints.size(); ++i) {
      if (ints[i] < 0 || ints[i] > INT32_MAX)
        throw lines.error("corner tag vertex " + std::to_string(ints[i]) + " is out of range (tags count vertices from 0)");
      soup.sharp.vertices.push_back({static_cast<std::int32_t>(ints[i]), sharpness(i)});
    }
  } else if (name == "creasemethod") {
    const std::string method = counts[2] == 1 ? lowercase(tokens[k]) : "";
    if (method == "normal" || method == "uniform") {
      soup.sharp.method = CreaseMethod::uniform;
    } else if (method == "chaikin") {
      soup.sharp.method = CreaseMethod::chaikin;
    } else {
      throw lines.error("the creasemethod tag takes one word, 'normal' or 'chaikin' (t creasemethod 0/0/1 chaikin)");
    }
  } else if (name == "interpolateboundary") {
    if (ints.size() != 1) throw lines.error("the interpolateboundary tag takes one integer (t interpolateboundary 1/0/0 2)");
    if (ints[0] == 2) {
      soup.boundary_corners = false;  // edges only: what rgbmesh does anyway
    } else if (ints[0] == 1) {
      soup.boundary_corners = true;
    } else {
      throw lines.error("interpolateboundary " + std::to_string(ints[0]) +
                        " is not supported: 2 (boundary edges sharp) and 1 (also corners at vertices of one face) are");
    }
  } else if (name == "hole") {
    throw lines.error("hole tags are not supported (the tagged faces would be read as part of the surface)");
  } else if (ignored.insert(name).second) {
    soup.notes.push_back("ignored OBJ tag '" + printable(name) + "' (line " + std::to_string(lines.number()) +
                         "): only crease, corner, creasemethod and interpolateboundary tags change the surface");
  }
}

}  // namespace

PolygonSoup parse_obj(std::string_view text, const std::string& path, const ReadOptions& options) {
  check_text(text, path);
  TokenLines lines(text, path);
  PolygonSoup soup;
  // Faces may refer to vertices defined further down; those are checked once all are known.
  struct ForwardReference {
    std::int64_t line, index;
  };
  std::vector<ForwardReference> forward;
  std::set<std::string> ignored_tags;
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
    } else if (command == "t") {
      parse_tag(lines, soup, ignored_tags);
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
