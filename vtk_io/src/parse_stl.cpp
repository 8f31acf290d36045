// STL, binary and ASCII. vtkSTLReader 9.1 accepts a binary file whose triangle count disagrees
// with its length (it reads what is there) and ASCII files with misspelled keywords (it looks at
// few of them), so STL has a strict parser of its own: it is a simple format.
//
// Binary: an 80-byte header, a little-endian uint32 triangle count, then 50 bytes per triangle
// (normal, three corners as little-endian float32, a 2-byte attribute). ASCII:
//   solid NAME
//     facet normal nx ny nz
//       outer loop
//         vertex x y z      (three times)
//       endloop
//     endfacet
//   endsolid NAME
// with any number of facets and of solids, keywords in any case. Some binary files start their
// header with "solid" too: a file is binary when its length is exactly what its count says.

#include "input_file.hpp"
#include "parse_common.hpp"
#include "parsers.hpp"

namespace rgbmesh::detail {
namespace {

constexpr std::size_t header_bytes = 84, triangle_bytes = 50;

bool equals_lowercase(std::string_view word, std::string_view keyword) {
  if (word.size() != keyword.size()) return false;
  for (std::size_t i = 0; i < word.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(word[i])) != keyword[i]) return false;
  return true;
}

// Whitespace-separated words that know their line.
class Words {
 public:
  Words(std::string_view text, const std::string& path) : text_(text), path_(path) {}

  std::string_view next() {
    while (pos_ < text_.size() && is_space(text_[pos_])) line_ += text_[pos_++] == '\n';
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    return text_.substr(start, pos_ - start);
  }

  // The rest of the current line (a solid's name), skipped.
  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }

  void expect(std::string_view keyword) {
    const std::string_view word = next();
    if (word.empty())
      throw error("the file ends where '" + std::string(keyword) + "' should follow: it is truncated");
    if (!equals_lowercase(word, keyword))
      throw error("expected '" + std::string(keyword) + "', found '" + printable(word) + "'");
  }

  double number() {
    const std::string_view word = next();
    if (word.empty()) throw error("the file ends inside a facet: it is truncated");
    double value = 0;
    if (!parse_number(word, value)) throw error("'" + printable(word) + "' is not a number");
    return value;
  }

  InputError error(const std::string& what) const {
    return InputError(path_ + ": line " + std::to_string(line_) + ": " + what);
  }

 private:
  std::string_view text_;
  const std::string& path_;
  std::size_t pos_ = 0;
  std::int64_t line_ = 1;
};

// STL coordinates are single precision by the format, and vtkSTLReader stored ASCII ones as
// float too: rounding them keeps "exactly coincident corners are one vertex" what it was.
// Each coordinate goes through a volatile float: GCC 12.2's SLP vectorizer at -O2 fused the x
// and y round trips and dropped their rounding (x and y came back as parsed, z rounded), so
// that an ASCII STL and its binary twin read differently.
Vec3 stl_point(double x, double y, double z) {
  const auto single = [](double value) {
    const volatile float rounded = static_cast<float>(value);
    return static_cast<double>(rounded);
  };
  return {single(x), single(y), single(z)};
}

PolygonSoup parse_ascii_stl(std::string_view text, const std::string& path) {
  check_text(text, path);
  Words words(text, path);
  PolygonSoup soup;
  words.expect("solid");
  words.skip_line();
  for (;;) {
    const std::string_view word = words.next();
    if (word.empty()) throw words.error("the file ends before 'endsolid': it is truncated");
    if (equals_lowercase(word, "endsolid")) {
      words.skip_line();
      const std::string_view after = words.next();
      if (after.empty()) return soup;
      // Several solids may follow each other.
      if (!equals_lowercase(after, "solid"))
        throw words.error("expected 'solid' or the end of the file after 'endsolid', found '" +
                          printable(after) + "'");
      words.skip_line();
      continue;
    }
    if (!equals_lowercase(word, "facet"))
      throw words.error("expected 'facet' or 'endsolid', found '" + printable(word) + "'");
    words.expect("normal");
    for (int k = 0; k < 3; ++k) words.number();  // recomputed from the corners by whoever needs it
    words.expect("outer");
    words.expect("loop");
    const auto first = static_cast<std::int64_t>(soup.points.size());
    for (int corner = 0; corner < 3; ++corner) {
      words.expect("vertex");
      const double x = words.number(), y = words.number(), z = words.number();
      soup.points.push_back(stl_point(x, y, z));
    }
    words.expect("endloop");
    words.expect("endfacet");
    soup.faces.push_back({first, first + 1, first + 2});
  }
}

PolygonSoup parse_binary_stl(std::string_view data, std::uint32_t count) {
  PolygonSoup soup;
  soup.points.reserve(3 * static_cast<std::size_t>(count));
  soup.faces.reserve(count);
  const bool swap = host_is_big_endian();
  for (std::size_t t = 0; t < count; ++t) {
    const char* corners = data.data() + header_bytes + t * triangle_bytes + 12;  // after the normal
    const auto first = static_cast<std::int64_t>(soup.points.size());
    for (int corner = 0; corner < 3; ++corner) {
      const char* xyz = corners + 12 * corner;
      soup.points.push_back({load<float>(xyz, swap), load<float>(xyz + 4, swap), load<float>(xyz + 8, swap)});
    }
    soup.faces.push_back({first, first + 1, first + 2});
  }
  return soup;
}

// An ASCII file starts with "solid" and holds only text (a binary header may start with
// "solid" too, but its count and triangles are binary).
bool looks_like_ascii(std::string_view data) {
  const std::string_view text = without_utf8_bom(data);
  const std::size_t word = text.find_first_not_of(" \t\r\n");
  if (word == std::string_view::npos || !equals_lowercase(text.substr(word, 5), "solid")) return false;
  const std::string_view start = text.substr(0, 1024);
  return std::all_of(start.begin(), start.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u >= 32 || is_space(c);
  });
}

}  // namespace

PolygonSoup parse_stl(std::string_view data, const std::string& path) {
  std::uint32_t count = 0;
  std::uint64_t expected = 0;
  if (data.size() >= header_bytes) {
    count = load<std::uint32_t>(data.data() + 80, host_is_big_endian());
    expected = header_bytes + triangle_bytes * static_cast<std::uint64_t>(count);
    if (data.size() == expected) return parse_binary_stl(data, count);
  }
  if (looks_like_ascii(data)) return parse_ascii_stl(without_utf8_bom(data), path);
  if (data.size() < header_bytes)
    throw InputError(path + ": cannot read: a binary STL file needs an 84-byte header, the file has " +
                     std::to_string(data.size()) + " bytes");
  const std::string announced = "the binary STL header announces " + std::to_string(count) + " triangles (" +
                                std::to_string(expected) + " bytes), the file has " +
                                std::to_string(data.size()) + " bytes";
  if (data.size() < expected) throw InputError(path + ": cannot read: " + announced + ": it is truncated");
  throw InputError(path + ": cannot read: " + announced + ": the count or the file is damaged");
}

}  // namespace rgbmesh::detail
