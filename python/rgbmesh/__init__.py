"""rgbmesh: RGB subdivision meshes (adaptive, conforming, Loop-exact) from Python.

A thin binding of the C++ library: the mesh lives in C++, arrays come out as numpy arrays.
"""

from ._rgbmesh import InputError, Mesh, OutputError, PreconditionError, read

__all__ = ["Mesh", "read", "InputError", "OutputError", "PreconditionError"]
