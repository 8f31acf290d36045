#pragma once
// Small base meshes for the tests, built from their definitions (no files).

#include <array>
#include <cstdint>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "rgbmesh/canonical.hpp"
#include "rgbmesh/mesh.hpp"

namespace rgbmesh::testing {

struct BaseMesh {
  std::string name;
  std::vector<Vec3> points;
  std::vector<std::array<std::int32_t, 3>> triangles;
  SharpFeatures sharp{};  ///< creases and corners (none for most meshes)
  RgbMesh build() const { return RgbMesh::from_triangles(points, triangles, sharp); }
};

// GoogleTest prints parameters with this (the name, not the bytes).
inline void PrintTo(const BaseMesh& m, std::ostream* os) { *os << m.name; }

BaseMesh single_triangle();
BaseMesh diamond();                          // two triangles sharing one interior edge
BaseMesh tetrahedron();                      // closed, valence 3
BaseMesh octahedron();                       // closed, valence 4
BaseMesh icosahedron();                      // closed, valence 5
BaseMesh cube();                             // closed, valences 4, 5 and 6 (two triangles per face)
BaseMesh bipyramid(int n);                   // closed, two poles of valence n, equator valence 4
BaseMesh torus(int rings, int sides);        // closed, genus 1
BaseMesh grid_with_holes(int n, int holes);  // open, 1 + holes boundary loops
BaseMesh fan_disk(int n);                    // open disk, centre of valence n
BaseMesh double_torus();                     // closed, genus 2
// Closed: a short cylinder (radius 1) as CAD tessellators write one: n vertices on each rim,
// one band of side quads split in two, each end disk fanned from one rim vertex (needles, and
// caps of nearly 180° next to the fan's vertex, which has valence n + 1). Not in
// all_base_meshes: a shape-poor mesh for the finite elements' tests.
BaseMesh cad_pillbox(int n, double height);

// With sharp features (not in all_base_meshes): a cube whose 12 edges are infinitely sharp; an
// octahedron with one infinitely sharp edge (its ends are darts); an icosahedron with a path
// of creases of sharpness 0.4 .. 10 and a semi-sharp corner, by either creasing method.
BaseMesh sharp_cube();
BaseMesh octahedron_with_darts();
BaseMesh graded_icosahedron(CreaseMethod method);

// Every mesh above, for parameterised tests.
std::vector<BaseMesh> all_base_meshes();

// The triangles as vertex triples rotated to start at the smallest index, sorted: two meshes
// with the same vertices have the same triangulation iff these are equal.
std::vector<std::array<std::int32_t, 3>> canonical_triangles(const RgbMesh& m);

// The triangles by their corners' names (canonical.hpp), each rotated to start at its
// smallest name (the orientation kept): equal for two meshes of one base with the same
// triangulation, whatever their handles.
std::set<std::array<VertexName, 3>> named_triangles(const RgbMesh& m);

}  // namespace rgbmesh::testing
