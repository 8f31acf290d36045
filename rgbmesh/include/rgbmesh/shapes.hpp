#pragma once
/// \file
/// Small base meshes built from their definitions, for defaults and examples.

#include "rgbmesh/soup.hpp"

namespace rgbmesh {

/// The regular icosahedron inscribed in the unit sphere: 12 vertices of valence 5, 20 triangles.
TriangleMeshData icosahedron();

/// The regular octahedron inscribed in the unit sphere: 6 vertices of valence 4, 8 triangles.
TriangleMeshData octahedron();

/// The square [-ghosts h, side + ghosts h]² in the plane z = 0, h = side / cells, divided into
/// squares of side h, each cut by its diagonal of direction (1, 1): every interior vertex has
/// valence 6 (the regular lattice). `ghosts` rings of cells around [0, side]² give the
/// elements on it complete patches (fem::LoopBoundary::ghost_ring).
TriangleMeshData square_lattice(int cells, double side, int ghosts = 1);

}  // namespace rgbmesh
