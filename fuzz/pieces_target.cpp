// Fuzz target: a piece of a distributed run (.vtp with its piece's state in field data), read
// through read_rgb_pieces as --resume reads a run's last cycle: the input is written as the
// piece, beside a summary (.pvtp) that names it twice (two pieces that are one: the join must
// take each vertex once). Accepted or refused with an InputError; anything else is a finding.

#include <cstdint>
#include <fstream>
#include <string>

#include "fuzz_support.hpp"
#include "rgbmesh/vtk_io.hpp"

using namespace rgbmesh;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fuzz::ScratchInput input(".vtp", data, size);
  const std::filesystem::path summary = input.path().string() + ".pvtp";
  {
    std::ofstream out(summary);
    const std::string name = input.path().filename().string();
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PPolyData\" version=\"1.0\">\n  <PPolyData "
           "GhostLevel=\"0\">\n"
        << "    <Piece Source=\"" << name << "\"/>\n    <Piece Source=\"" << name
        << "\"/>\n  </PPolyData>\n</VTKFile>\n";
  }
  RgbMeshFile file;
  if (fuzz::accepted([&] { file = read_rgb_pieces(summary); })) {
    if (const std::string problem = file.mesh.validate(true); !problem.empty())
      fuzz::finding("read_rgb_pieces gave a mesh that validate() refuses: " + problem);
  }
  std::filesystem::remove(summary);
  return 0;
}
