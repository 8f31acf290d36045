"""rgbmesh: RGB subdivision meshes (adaptive, conforming, Loop-exact) from Python.

A thin binding of the C++ library: the mesh lives in C++, arrays come out as numpy arrays.
"""

from . import _rgbmesh
from ._rgbmesh import InputError, Mesh, OutputError, PreconditionError, read

__all__ = ["Mesh", "read", "InputError", "OutputError", "PreconditionError"]

# The finite-element loop and the fit, where the extension was built with those modules.
for _name in ("Problem", "Solution", "solve", "adapt", "fit"):
    if hasattr(_rgbmesh, _name):
        globals()[_name] = getattr(_rgbmesh, _name)
        __all__.append(_name)
del _name

# VTK and PyVista objects (optional imports, when a conversion is asked for).
from .conversions import from_pyvista, from_vtk, to_pyvista, to_vtk  # noqa: E402

Mesh.to_vtk = to_vtk
Mesh.to_pyvista = to_pyvista
if hasattr(_rgbmesh, "Solution"):
    _rgbmesh.Solution.to_vtk = to_vtk
    _rgbmesh.Solution.to_pyvista = to_pyvista
__all__ += ["to_vtk", "from_vtk", "to_pyvista", "from_pyvista"]
