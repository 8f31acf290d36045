#pragma once
/// \file
/// Small base meshes built from their definitions, for defaults and examples.

#include "rgbmesh/soup.hpp"

namespace rgbmesh {

/// The regular icosahedron inscribed in the unit sphere: 12 vertices of valence 5, 20 triangles.
TriangleMeshData icosahedron();

/// The regular octahedron inscribed in the unit sphere: 6 vertices of valence 4, 8 triangles.
TriangleMeshData octahedron();

/// The unit cube [0, 1]³ as 12 triangles (each face cut by a diagonal), its 12 edges infinitely
/// sharp (sharp): its Loop limit surface is exactly the cube's surface. The domain of
/// fem::cube_cosine.
TriangleMeshData sharp_unit_cube();

/// The square [-ghosts h, side + ghosts h]² in the plane z = 0, h = side / cells, divided into
/// squares of side h, each cut by its diagonal of direction (1, 1): every interior vertex has
/// valence 6 (the regular lattice). With ghosts = 1, the elements of
/// fem::LoopBoundary::ghost_ring cover [0, side]² exactly (with g rings, the g - 1 inner ones
/// become elements too). Refining the mesh thins its ghost ring, and the elements' domain grows
/// by half a cell each level: build the lattice at the size wanted instead.
TriangleMeshData square_lattice(int cells, double side, int ghosts = 1);

}  // namespace rgbmesh
