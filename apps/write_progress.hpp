#pragma once
// How the tool writes its output files: the compression of VTK XML files (--compression) and a
// progress line on stderr for writes that take more than two seconds.

#include <string>

#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh::cli {

// Options for writing `path`: the compression, and progress that prints nothing during the
// first two seconds of the write; after that "rgbmesh: writing PATH: 40%, 3.1 s", rewritten in
// place at most every second on a terminal, a new line every 5 seconds otherwise, and a last
// line at 100% when the file is complete.
WriteOptions output_options(const std::string& path, Compression compression);

}  // namespace rgbmesh::cli
