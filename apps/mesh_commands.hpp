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

// rgbmesh info MESH: a mesh's statistics, or what a point cloud is.
struct InfoCommand {
  CLI::App* app = nullptr;
  std::string path;
  bool json = false, triangulate = false, repair = false;
  void add(CLI::App& tool);
  void run() const;
};

// rgbmesh convert IN OUT: any input format to any output format, through the mesh's checks.
struct ConvertCommand {
  CLI::App* app = nullptr;
  std::string in, out;
  bool triangulate = false, repair = false;
  void add(CLI::App& tool, CompressionOption& compression);
  void run(Compression compression) const;
};

// rgbmesh refine IN OUT [STAGE ...]: selective refinement stages in command-line order.
// (Registered options point into the object: it must stay where add() saw it.)
struct RefineCommand {
  CLI::App* app = nullptr;
  std::string in, out;
  bool stats = false, triangulate = false, limit = false, repair = false;
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
