#pragma once
/// \file
/// What one process of a distributed mesh holds: its own triangles and ghost layers as the
/// whole mesh has them, the rest as coarse as the RGB rules allow.

#include <vector>

#include "rgbmesh/mesh.hpp"

namespace rgbmesh::parallel {

/// A copy of `mesh` coarsened away from the kept triangles (`keep`, per triangle slot): every
/// vertex above `floor` is removed, finest first and for as long as any can be, except the
/// corners of the kept triangles and of `ghost_layers` layers of triangles around them (each
/// layer: the triangles with a corner in the previous ones). The kept and ghost triangles stay
/// as they are (the same corners, handles and positions); elsewhere the mesh keeps only what
/// conformity and the RGB rules need between them and the floor. Its size against the whole
/// mesh's is the memory a process needs when the mesh is distributed.
RgbMesh local_view(const RgbMesh& mesh, const std::vector<char>& keep, int floor, int ghost_layers = 1);

}  // namespace rgbmesh::parallel
