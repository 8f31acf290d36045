#include "cli_options.hpp"

#include <cstdlib>

namespace rgbmesh::cli {

const CLI::Validator kNonEmptyPath(
    [](std::string& value) -> std::string {
      return value.empty() ? "must name a file or folder, got an empty string (an unset shell variable?)"
                           : "";
    },
    "");

CLI::Validator number_in(const std::string& what, bool (*ok)(double)) {
  return CLI::Validator(
      [what, ok](std::string& value) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(value.c_str(), &end);
        if (value.empty() || end != value.c_str() + value.size() || !ok(x))
          return "must be " + what + ", got '" + value + "'";
        return "";
      },
      what);
}

const char* const kRepairHelp =
    "Repair the mesh first: merge vertices at equal positions, collapse degenerate and needle triangles, "
    "remove "
    "duplicate ones, split non-manifold edges and vertices, orient consistently (a note says what changed; "
    "nothing moves by more than 1e-6 of the bounding-box diagonal)";

CLI::Option* add_sharp_angle(CLI::App* app, double& degrees) {
  return app
      ->add_option("--sharp-angle", degrees,
                   "Keep the part's edges: an edge whose two triangles' normals differ by more than DEG degrees "
                   "is an infinitely sharp crease (30 is VTK's, Blender's choice), a crease that turns by more "
                   "than DEG a corner; added to the file's own crease tags. Off by default: smooth bases stay "
                   "smooth")
      ->type_name("DEG")
      ->check(number_in("a number of degrees in (0, 180)",
                        [](double x) { return x > 0.0 && x < 180.0; }));
}

CLI::Option* CompressionOption::add_to(CLI::App& where) {
  static const CLI::Validator check(
      [](std::string& value) -> std::string {
        Compression c;
        return compression_from_name(value, c) ? "" : "must be lz4, zlib or none, got '" + value + "'";
      },
      "");
  options_.push_back(
      where
          .add_option("--compression", text_,
                      "Compression of VTK XML outputs (.vtp, .vtu): lz4 (the fastest; ParaView 5.6 "
                      "and later), zlib (smaller, slower; every VTK reader) or none")
          ->type_name("lz4|zlib|none")
          ->check(check));
  return options_.back();
}

Compression CompressionOption::value() const {
  Compression compression = WriteOptions().compression;
  compression_from_name(text_, compression);
  return compression;
}

}  // namespace rgbmesh::cli
