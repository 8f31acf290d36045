"""Conversions between rgbmesh objects and VTK or PyVista data sets.

VTK's Python package (Debian: python3-vtk9) and PyVista are optional: they are imported when a
conversion is asked for. A Mesh becomes a vtkPolyData with the arrays rgbmesh's own .vtp files
carry, the RGB state included, so that from_vtk, or rgbmesh.read of the data set written by any
VTK XML writer, gives back the same RGB mesh.
"""

import numpy as np

# The names of the RGB state's arrays in VTK data sets, as in rgbmesh's .vtp/.vtu files.
_BASE_VERTEX, _PARENTS = "rgb_base_vertex", "rgb_parents"
_VERSION, _BASE_POINTS, _BASE_TRIANGLES = "rgb_state_version", "rgb_base_points", "rgb_base_triangles"
# Version 2: the base mesh's sharp features (vtk_io/src/rgb_state_io.hpp).
_SHARP_EDGES, _EDGE_SHARPNESS = "rgb_sharp_edges", "rgb_sharp_edge_sharpness"
_SHARP_VERTICES, _VERTEX_SHARPNESS, _CREASE_METHOD = "rgb_sharp_vertices", "rgb_sharp_vertex_sharpness", "rgb_crease_method"


def _vtk():
    try:
        from vtkmodules import vtkCommonCore, vtkCommonDataModel
        from vtkmodules.util import numpy_support
    except ImportError as e:
        raise ImportError("rgbmesh: converting to and from VTK data sets needs VTK's Python package "
                          "(Debian: python3-vtk9)") from e
    return vtkCommonCore, vtkCommonDataModel, numpy_support


def _pyvista():
    try:
        import pyvista
    except ImportError as e:
        raise ImportError("rgbmesh: converting to and from PyVista needs the pyvista package "
                          "(VTK data sets without it: to_vtk and from_vtk)") from e
    return pyvista


def _array(values, name, numpy_support):
    a = numpy_support.numpy_to_vtk(np.ascontiguousarray(values), deep=True)
    a.SetName(name)
    return a


def _cells(connectivity, width, numpy_support, vtkCommonDataModel):
    """A vtkCellArray of cells of `width` points from an (m, width) array."""
    connectivity = np.ascontiguousarray(connectivity, dtype=np.int64)
    offsets = np.arange(0, width * (len(connectivity) + 1), width, dtype=np.int64)
    cells = vtkCommonDataModel.vtkCellArray()
    cells.SetData(numpy_support.numpy_to_vtkIdTypeArray(offsets, deep=True),
                  numpy_support.numpy_to_vtkIdTypeArray(connectivity.ravel(), deep=True))
    return cells


def _points(points, numpy_support, vtkCommonCore):
    p = vtkCommonCore.vtkPoints()
    p.SetData(numpy_support.numpy_to_vtk(np.ascontiguousarray(points, dtype=float), deep=True))
    return p


def _mesh_to_vtk(mesh, points, state):
    vtkCommonCore, vtkCommonDataModel, numpy_support = _vtk()
    if points not in ("control", "limit"):
        raise ValueError("points: 'control' or 'limit', got %r" % (points,))
    data = vtkCommonDataModel.vtkPolyData()
    data.SetPoints(_points(mesh.control_points() if points == "control" else mesh.limit_positions(),
                           numpy_support, vtkCommonCore))
    data.SetPolys(_cells(mesh.triangles(), 3, numpy_support, vtkCommonDataModel))
    data.GetPointData().AddArray(_array(mesh.vertex_levels(), "level", numpy_support))
    data.GetCellData().AddArray(_array(mesh.triangle_levels(), "level", numpy_support))
    data.GetCellData().AddArray(_array(mesh.triangle_colors(), "color", numpy_support))
    if state:
        s = mesh.state()
        data.GetPointData().AddArray(_array(s["base_vertex"], _BASE_VERTEX, numpy_support))
        data.GetPointData().AddArray(_array(s["parents"], _PARENTS, numpy_support))
        fields = data.GetFieldData()
        fields.AddArray(_array(np.array([s["version"]], np.int32), _VERSION, numpy_support))
        fields.AddArray(_array(s["base_points"], _BASE_POINTS, numpy_support))
        fields.AddArray(_array(s["base_triangles"], _BASE_TRIANGLES, numpy_support))
        if "sharp_edges" in s:
            if len(s["sharp_edges"]):
                fields.AddArray(_array(s["sharp_edges"].astype(np.int32), _SHARP_EDGES, numpy_support))
                fields.AddArray(_array(s["edge_sharpness"], _EDGE_SHARPNESS, numpy_support))
            if len(s["sharp_vertices"]):
                fields.AddArray(_array(s["sharp_vertices"].astype(np.int32), _SHARP_VERTICES, numpy_support))
                fields.AddArray(_array(s["vertex_sharpness"], _VERTEX_SHARPNESS, numpy_support))
            method = 1 if s["crease_method"] == "chaikin" else 0
            fields.AddArray(_array(np.array([method], np.int32), _CREASE_METHOD, numpy_support))
    sharp = mesh.sharp_features()
    if len(sharp["edges"]) or len(sharp["vertices"]):
        data.GetPointData().AddArray(_array(mesh.vertex_rules(), "vertex_rule", numpy_support))
    return data


def _solution_to_vtk(solution):
    vtkCommonCore, vtkCommonDataModel, numpy_support = _vtk()
    if solution.order == 2:
        # Quadratic triangles (VTK_QUADRATIC_TRIANGLE = 22): corners, then the edge nodes, which
        # ParaView draws curved.
        data = vtkCommonDataModel.vtkUnstructuredGrid()
        cells = np.hstack([solution.triangles, solution.edge_nodes])
        data.SetCells(22, _cells(cells, 6, numpy_support, vtkCommonDataModel))
    else:
        data = vtkCommonDataModel.vtkPolyData()
        data.SetPolys(_cells(solution.triangles, 3, numpy_support, vtkCommonDataModel))
    data.SetPoints(_points(solution.points, numpy_support, vtkCommonCore))
    data.GetPointData().AddArray(_array(solution.u, "solution", numpy_support))
    cells = data.GetCellData()
    cells.AddArray(_array(solution.estimate, "error_indicator", numpy_support))
    cells.AddArray(_array(solution.triangle_levels, "level", numpy_support))
    if solution.marked is not None:
        cells.AddArray(_array(solution.marked.astype(np.uint8), "marked", numpy_support))
    return data


def to_vtk(obj, points="control", state=True):
    """A VTK data set of a Mesh or a Solution.

    Mesh: a vtkPolyData of its triangles, the points at their control points (points='control',
    where the vertices are in the current mesh) or their limit positions ('limit'), with point
    data 'level' and cell data 'level' and 'color', and with state=True the RGB state, so that
    from_vtk (or rgbmesh.read of the data set written as .vtp) restores the same RGB mesh.
    Solution: its nodes and triangles (P2: a vtkUnstructuredGrid of quadratic triangles) with
    point data 'solution' and cell data 'error_indicator', 'level' and, for a cycle, 'marked'.
    """
    from ._rgbmesh import Mesh

    if isinstance(obj, Mesh):
        return _mesh_to_vtk(obj, points, state)
    if hasattr(obj, "estimate") and hasattr(obj, "u"):
        return _solution_to_vtk(obj)
    raise TypeError("to_vtk: a Mesh or a Solution, got %s" % type(obj).__name__)


def _numpy(array, numpy_support):
    return None if array is None else numpy_support.vtk_to_numpy(array)


def from_vtk(data, triangulate=False, point_rows=False):
    """A Mesh from a VTK data set of triangles (vtkPolyData, or any data set whose surface is
    triangles: vtkUnstructuredGrid, ...). With the RGB state's arrays (to_vtk, or a .vtp that
    rgbmesh wrote, read by VTK) it is the RGB mesh they describe, checked as rgbmesh.read checks
    a file; otherwise a base mesh, validated as Mesh.from_arrays validates. triangulate splits
    polygons into triangles (vtkTriangleFilter) instead of refusing them. With point_rows,
    returns (mesh, rows): rows[i] is the row of the data set's point i in the mesh's arrays.
    """
    vtkCommonCore, vtkCommonDataModel, numpy_support = _vtk()
    from ._rgbmesh import InputError, Mesh

    if not isinstance(data, vtkCommonDataModel.vtkDataSet):
        raise TypeError("from_vtk: a VTK data set, got %s" % type(data).__name__)
    if not isinstance(data, vtkCommonDataModel.vtkPolyData):
        from vtkmodules.vtkFiltersGeometry import vtkGeometryFilter

        surface = vtkGeometryFilter()
        surface.SetInputData(data)
        surface.Update()
        data = surface.GetOutput()
    if data.GetNumberOfVerts() or data.GetNumberOfLines() or data.GetNumberOfStrips():
        raise InputError("from_vtk: the data set has vertex, line or strip cells; a surface of triangles is needed")
    polys = data.GetPolys()
    offsets = numpy_support.vtk_to_numpy(polys.GetOffsetsArray())
    sizes = np.diff(offsets)
    if len(sizes) == 0:
        raise InputError("from_vtk: the data set has no triangles")
    if (sizes != 3).any():
        if not triangulate:
            bad = int(np.argmax(sizes != 3))
            raise InputError("from_vtk: cell %d has %d points, not 3 (triangulate=True splits polygons)"
                             % (bad, sizes[bad]))
        from vtkmodules.vtkFiltersCore import vtkTriangleFilter

        triangles = vtkTriangleFilter()
        triangles.SetInputData(data)
        triangles.Update()
        return from_vtk(triangles.GetOutput(), point_rows=point_rows)
    triangles = numpy_support.vtk_to_numpy(polys.GetConnectivityArray()).reshape(-1, 3)
    points = numpy_support.vtk_to_numpy(data.GetPoints().GetData()).astype(float)
    pd, fd, cd = data.GetPointData(), data.GetFieldData(), data.GetCellData()
    state = [pd.GetArray(_BASE_VERTEX), pd.GetArray(_PARENTS), fd.GetArray(_BASE_POINTS), fd.GetArray(_BASE_TRIANGLES)]
    if all(a is not None for a in state):
        version = fd.GetArray(_VERSION)
        levels, cell_levels, colors = pd.GetArray("level"), cd.GetArray("level"), cd.GetArray("color")
        method = fd.GetArray(_CREASE_METHOD)
        sharp = dict(
            sharp_edges=_numpy(fd.GetArray(_SHARP_EDGES), numpy_support),
            edge_sharpness=_numpy(fd.GetArray(_EDGE_SHARPNESS), numpy_support),
            sharp_vertices=_numpy(fd.GetArray(_SHARP_VERTICES), numpy_support),
            vertex_sharpness=_numpy(fd.GetArray(_VERTEX_SHARPNESS), numpy_support),
            crease_method="chaikin" if method is not None and int(numpy_support.vtk_to_numpy(method)[0]) == 1
            else "uniform")
        if sharp["sharp_edges"] is not None:
            sharp["sharp_edges"] = sharp["sharp_edges"].reshape(-1, 2)
        mesh, rows = Mesh.from_state(
            numpy_support.vtk_to_numpy(state[2]).reshape(-1, 3), numpy_support.vtk_to_numpy(state[3]).reshape(-1, 3),
            numpy_support.vtk_to_numpy(state[0]), numpy_support.vtk_to_numpy(state[1]).reshape(-1, 2),
            triangles=triangles, vertex_levels=_numpy(levels, numpy_support),
            triangle_levels=_numpy(cell_levels, numpy_support), triangle_colors=_numpy(colors, numpy_support),
            version=int(numpy_support.vtk_to_numpy(version)[0]) if version is not None else 1, **sharp)
    else:
        mesh, rows = Mesh.from_arrays(points, triangles), np.arange(len(points), dtype=np.int32)
    return (mesh, rows) if point_rows else mesh


def to_pyvista(obj, points="control", state=True):
    """to_vtk's data set as a PyVista object (pyvista.wrap), for plotting in PyVista."""
    return _pyvista().wrap(to_vtk(obj, points=points, state=state))


def from_pyvista(data, triangulate=False, point_rows=False):
    """from_vtk of a PyVista data set (PyVista's objects are VTK data sets)."""
    return from_vtk(data, triangulate=triangulate, point_rows=point_rows)
