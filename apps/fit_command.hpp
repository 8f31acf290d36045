#pragma once
// `rgbmesh fit`: Loop subdivision surfaces fitted to scanned points (rgbmesh::fit).

#include <cstddef>
#include <string>

#include "cli_options.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh::cli {

struct FitArgs {
  Compression compression = Compression::lz4;  // of the .vtp files (--compression)
  std::string target;        // points: a point cloud (.xyz, .pwn, or a mesh format without faces) or a mesh
  std::string base;          // empty: built from the target (decimated, or reconstructed and decimated)
  bool triangulate = false;  // split the polygons of --target's and --base's faces (polygons.hpp)
  bool ignore_faces = false;  // fit --target's vertices as a point cloud
  std::string reconstruction = "automatic";  // automatic, poisson, advancing-front
  bool repair = false;       // repair --target's faces and --base first (rgbmesh::repair)
  double sharp_angle = 0;    // > 0: keep the target's edges sharper than this (--sharp-angle)
  std::size_t base_faces = 1000;
  int levels = 3;
  std::string loss = "huber";  // huber, cauchy, none
  double smooth = 1e-3;
  int iterations = 30;
  std::string out = "out-fit";  // apart from adapt's "out", so that the two never clear each other's
  std::string report;
  std::string command_line;  // for the report; may be empty
  std::string memory_limit;  // --memory-limit's text ("": the default ceiling)
  // Escalation (a rejected fit of a base built from the target tries finer bases and one more
  // level, fit_command.cpp): off with --no-retry; bounded by time and base size.
  bool retry = true;
  double retry_seconds = 300;
  std::size_t max_base_faces = 16000;
};

// Reads the target, builds or reads the base, runs the fit, measures it in both directions
// (fit/distances.hpp) and writes, into DIR (after removing a previous run's outputs, see
// output_dir.hpp):
//   base.obj                   the starting base (given, the target, decimated or reconstructed)
//   fitted_base.obj            the fitted control points on the base's triangles
//   initial_limit_surface.vtp  the starting base's limit surface
//   limit_surface.vtp          the fitted limit surface, with point data "distance_to_target" and
//                              cell data "targets" (targets whose closest point lies in the
//                              triangle) and "rms_distance" (their RMS distance to the surface;
//                              0 where there are none)
//   targets.vtp                the targets as vertices (a mesh target's vertices and the points
//                              spread over its triangles), with point data "distance" (to the
//                              fitted limit surface: the figures the RMS and maximum come from)
// and the JSON report; returns the exit code. InputError on bad arguments or input, and when the
// fitted surface fails the two-sided check (after the files are written, so that the user can
// see where); ResourceError when a stage passes the memory ceiling.
int run_fit(const FitArgs& args);

// The subcommand's options on the tool, bound to `args` (the object must stay where add() saw it).
struct FitCommand {
  CLI::App* app = nullptr;
  CLI::Option* out = nullptr;
  FitArgs args;
  void add(CLI::App& tool, CompressionOption& compression);
};

}  // namespace rgbmesh::cli
