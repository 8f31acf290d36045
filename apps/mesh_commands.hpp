#pragma once
// The subcommands that work on one mesh file: info, convert and refine. Each registers its
// options on the tool (add) and runs once parsed (run).

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "cli_options.hpp"
#include "resources.hpp"
#include "stages.hpp"

namespace rgbmesh::cli {

// A mesh file as an RgbMesh, its notes printed (read_rgb_mesh with the reading options of the
// tool's flags); for a base mesh (no saved state) also note_rounded_edges.
RgbMesh load_mesh(const std::string& path, bool triangulate, bool repair, double sharp_angle);
// Notes (once) how far the limit surface of a base mesh strays from its vertices when that is
// more than 1% of the diagonal and no --sharp-angle was given, naming --sharp-angle.
void note_rounded_edges(const std::string& path, const RgbMesh& mesh, double sharp_angle);

// rgbmesh info MESH: a mesh's statistics, or what a point cloud is.
struct InfoCommand {
  CLI::App* app = nullptr;
  std::string path;
  bool json = false, triangulate = false, repair = false;
  double sharp_angle = 0;
  void add(CLI::App& tool);
  void run() const;
};

// rgbmesh convert IN OUT: any input format to any output format, through the mesh's checks.
struct ConvertCommand {
  CLI::App* app = nullptr;
  std::string in, out;
  bool triangulate = false, repair = false;
  double sharp_angle = 0;
  void add(CLI::App& tool, CompressionOption& compression);
  void run(Compression compression) const;
};

// rgbmesh refine IN OUT [STAGE ...]: selective refinement stages in command-line order.
// (Registered options point into the object: it must stay where add() saw it.)
struct RefineCommand {
  CLI::App* app = nullptr;
  std::string in, out;
  bool stats = false, triangulate = false, limit = false, repair = false;
  double sharp_angle = 0;
  void add(CLI::App& tool, CompressionOption& compression);
  void run(Compression compression, const MemoryCeiling& ceiling) const;

 private:
  struct StageOption {
    CLI::Option* option;
    std::vector<std::string> values;
    Stage (*parse)(const std::string&);
  };
  std::vector<StageOption> stage_options_;  // reserved once: the options bind to its elements
  CLI::Option* coarsen_all_ = nullptr;
  std::vector<Stage> stages() const;
};

}  // namespace rgbmesh::cli
