#pragma once
#include <string>

namespace rgbmesh::cli {

// The job `rgbmesh` runs without arguments: an embedded base mesh, selectively refined
// around a feature, written for ParaView into out_dir. Returns the exit code.
int run_default_job(const std::string& out_dir);

}  // namespace rgbmesh::cli
