#pragma once
// The refinement stages of `rgbmesh refine`, applied in the order given on the command line.

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "resources.hpp"

namespace rgbmesh::cli {

struct Stage {
  enum Kind { uniform, ball, max_edge, geometric_tol, budget, max_level, random_walk, coarsen_all } kind;
  std::string text;  // as the user wrote it, for messages: "--ball 0,0,1,0.2,5"
  double x = 0, y = 0, z = 0, radius = 0, length = 0;
  int level = 0;
  std::uint64_t count = 0, seed = 0;
};

// Parsers for the option values; throw InputError naming the option on bad values.
Stage parse_uniform(const std::string& value);
Stage parse_ball(const std::string& value);
Stage parse_max_edge(const std::string& value);
Stage parse_geometric_tol(const std::string& value);
Stage parse_budget(const std::string& value);
Stage parse_max_level(const std::string& value);
Stage parse_random_walk(const std::string& value);
Stage parse_coarsen_all();

struct StageResult {
  std::string text;
  std::uint64_t splits = 0, removals = 0;
  double seconds = 0;
};

struct StageTotals {
  std::uint64_t splits = 0, removals = 0;
  double seconds = 0;
  // Splits per second over the stages that only split, removals per second over those that
  // only removed (stages doing both, like a random walk, count in neither); 0 if none.
  double splits_per_second = 0, removals_per_second = 0;
  std::vector<StageResult> stages;
};

// Runs the stages in order on the mesh, reporting progress on stderr for long stages. Memory:
// a uniform level or a budget whose mesh (plus, when `output_vertex_bytes` > 0, its output at
// that many bytes per vertex) would pass the ceiling is refused before it starts; any other
// stage that reaches the ceiling stops there. Both are a ResourceError with the figures.
StageTotals run_stages(RgbMesh& mesh, const std::vector<Stage>& stages, const MemoryCeiling& ceiling,
                       double output_vertex_bytes = 0);

// The memory that writing a mesh of that many vertices takes, per vertex (the snapshot and the
// writer's own copies; VTK XML files carry control points and limits too).
double output_bytes_per_vertex(const std::string& output_path);

// Refuses (ResourceError) to write the mesh to `output_path` when writing would pass the
// ceiling: after open-ended stages the final size was not known before.
void check_output_memory(const RgbMesh& mesh, const std::string& output_path, const MemoryCeiling& ceiling);

}  // namespace rgbmesh::cli
