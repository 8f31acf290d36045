#pragma once
// The refinement stages of `rgbmesh refine`, applied in the order given on the command line.

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"

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

struct StageTotals {
  std::uint64_t splits = 0, removals = 0;
  double seconds = 0;
};

// Runs the stages in order on the mesh, reporting progress on stderr for long stages.
StageTotals run_stages(RgbMesh& mesh, const std::vector<Stage>& stages);

}  // namespace rgbmesh::cli
