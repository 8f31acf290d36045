#pragma once
/// \file
/// Small base meshes built from their definitions, for defaults and examples.

#include "rgbmesh/soup.hpp"

namespace rgbmesh {

/// The regular icosahedron inscribed in the unit sphere: 12 vertices of valence 5, 20 triangles.
TriangleMeshData icosahedron();

/// The regular octahedron inscribed in the unit sphere: 6 vertices of valence 4, 8 triangles.
TriangleMeshData octahedron();

}  // namespace rgbmesh
