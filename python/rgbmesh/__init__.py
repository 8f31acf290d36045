"""rgbmesh: RGB subdivision meshes (adaptive, conforming, Loop-exact) from Python.

A thin binding of the C++ library: the mesh lives in C++, arrays come out as numpy arrays.
"""

from ._rgbmesh import InputError, Mesh, PreconditionError

__all__ = ["Mesh", "InputError", "PreconditionError"]
