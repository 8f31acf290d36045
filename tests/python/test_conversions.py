"""Meshes and solutions to and from VTK data sets (issue 14): the RGB state travels with the data
set, so that a VTK writer's file or the data set itself gives back the same RGB mesh; plain
data sets give base meshes with the files' validation."""

import importlib.util
import os
import subprocess

import numpy as np
import pytest
import rgbmesh

from helpers import icosahedron, write_obj

vtk = pytest.importorskip("vtk")
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402


def adapted_mesh():
    mesh = rgbmesh.Mesh.from_arrays(*icosahedron())
    mesh.refine(ball=(0.0, 1.6, 0.0, 0.5, 4))
    # Coarsen part of it and refine elsewhere, so that slots are reused and some vertices sit
    # before their parents in the point arrays.
    mesh.refine(ball=(0.0, 1.6, 0.0, 0.5, 2), max_level=2)
    mesh.adapt_to(vertex_values=np.where(mesh.vertex_levels() > 2, 0.0, 1.0), coarsen_below=0.5)
    mesh.refine(ball=(1.6, 0.0, 0.0, 0.6, 3))
    assert mesh.validate() == ""
    return mesh


def corners(mesh):
    """The triangles as sets of corner positions (independent of the vertices' order)."""
    p = np.round(mesh.control_points(), 12)
    return {frozenset(map(tuple, p[t])) for t in mesh.triangles()}


def test_a_mesh_comes_back_from_its_vtk_data_set_with_its_rows():
    mesh = adapted_mesh()
    data = mesh.to_vtk()
    assert data.GetNumberOfPoints() == mesh.num_vertices and data.GetNumberOfCells() == mesh.num_triangles
    assert np.array_equal(vtk_to_numpy(data.GetPointData().GetArray("level")), mesh.vertex_levels())
    back, rows = rgbmesh.from_vtk(data, point_rows=True)
    assert back.validate() == "" and back.num_vertices == mesh.num_vertices
    # Row i of the data set is row rows[i] of the new mesh (not the identity here: some vertices
    # came before their parents): same control points, levels.
    assert (rows != np.arange(len(rows))).any()
    assert np.array_equal(back.control_points()[rows], mesh.control_points())
    assert np.array_equal(back.vertex_levels()[rows], mesh.vertex_levels())
    assert corners(back) == corners(mesh)
    # And it refines and coarsens as the original: all the way back to the base.
    back.refine_uniform(0)
    assert np.array_equal(back.control_points(), icosahedron()[0])


def test_a_vtk_writer_s_file_is_read_back_with_the_rgb_state(tmp_path):
    mesh = adapted_mesh()
    writer = vtk.vtkXMLPolyDataWriter()
    writer.SetFileName(str(tmp_path / "from_vtk.vtp"))
    writer.SetInputData(mesh.to_vtk())
    assert writer.Write() == 1
    back = rgbmesh.read(tmp_path / "from_vtk.vtp")
    assert back.num_vertices == mesh.num_vertices and corners(back) == corners(mesh)
    assert back.max_level == mesh.max_level == 3
    # Without the state it is a base mesh of those triangles.
    writer.SetFileName(str(tmp_path / "plain.vtp"))
    writer.SetInputData(mesh.to_vtk(state=False))
    writer.Write()
    assert rgbmesh.read(tmp_path / "plain.vtp").max_level == 0


def test_the_tool_s_file_through_vtk_s_reader_is_the_tool_s_mesh(tmp_path):
    write_obj(tmp_path / "ico.obj", *icosahedron())
    subprocess.run([os.environ["RGBMESH_CLI"], "refine", str(tmp_path / "ico.obj"), str(tmp_path / "r.vtp"), "--ball",
                    "0,1.6,0,0.5,4"], check=True, capture_output=True)
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(str(tmp_path / "r.vtp"))
    reader.Update()
    through_vtk = rgbmesh.from_vtk(reader.GetOutput())
    direct = rgbmesh.read(tmp_path / "r.vtp")
    assert through_vtk.max_level == 4 and corners(through_vtk) == corners(direct)
    # An edited state is refused as read() refuses the file.
    data = reader.GetOutput()
    parents = vtk_to_numpy(data.GetPointData().GetArray("rgb_parents"))
    parents[np.argmax(parents[:, 0] >= 0), 0] = 0  # (a view: edits the data set's array)
    with pytest.raises(ValueError):
        rgbmesh.from_vtk(data)


def test_plain_vtk_surfaces_are_base_meshes():
    sphere = vtk.vtkSphereSource()
    sphere.SetThetaResolution(16)
    sphere.SetPhiResolution(9)
    sphere.Update()
    mesh = rgbmesh.from_vtk(sphere.GetOutput())
    assert mesh.num_vertices == sphere.GetOutput().GetNumberOfPoints() and mesh.validate() == ""
    # Quads: refused, naming the cell, unless asked to triangulate.
    plane = vtk.vtkPlaneSource()
    plane.SetResolution(3, 2)
    plane.Update()
    with pytest.raises(ValueError, match="cell 0 has 4 points"):
        rgbmesh.from_vtk(plane.GetOutput())
    mesh = rgbmesh.from_vtk(plane.GetOutput(), triangulate=True)
    assert (mesh.num_vertices, mesh.num_triangles) == (12, 12)
    # An unstructured grid of triangles: its surface.
    grid = vtk.vtkUnstructuredGrid()
    grid.SetPoints(sphere.GetOutput().GetPoints())
    grid.SetCells(vtk.VTK_TRIANGLE, sphere.GetOutput().GetPolys())
    assert rgbmesh.from_vtk(grid).num_triangles == sphere.GetOutput().GetNumberOfCells()
    with pytest.raises(TypeError):
        rgbmesh.from_vtk(np.zeros((3, 3)))


def test_solutions_become_data_sets_with_their_fields():
    mesh = rgbmesh.Mesh.from_arrays(*icosahedron(unit=True))
    mesh.refine_uniform(2)
    s = rgbmesh.solve(mesh, rgbmesh.Problem.builtin("sphere-peak"))
    data = s.to_vtk()
    assert data.IsA("vtkPolyData") and data.GetNumberOfPoints() == len(s.u)
    assert np.array_equal(vtk_to_numpy(data.GetPointData().GetArray("solution")), s.u)
    assert np.array_equal(vtk_to_numpy(data.GetCellData().GetArray("error_indicator")), s.estimate)
    s2 = rgbmesh.solve(mesh, rgbmesh.Problem.builtin("sphere-peak"), order=2)
    grid = s2.to_vtk()
    assert grid.IsA("vtkUnstructuredGrid") and grid.GetCellType(0) == vtk.VTK_QUADRATIC_TRIANGLE
    assert grid.GetNumberOfPoints() == len(s2.u) and grid.GetNumberOfCells() == mesh.num_triangles


def test_solutions_write_the_tool_s_files(tmp_path):
    mesh = rgbmesh.Mesh.from_arrays(*icosahedron(unit=True))
    mesh.refine_uniform(2)
    for order, name, reader in [(1, "p1.vtp", vtk.vtkXMLPolyDataReader()),
                                (2, "p2.vtu", vtk.vtkXMLUnstructuredGridReader()),
                                (2, "p2_vertices.vtp", vtk.vtkXMLPolyDataReader())]:
        s = rgbmesh.solve(mesh, rgbmesh.Problem.builtin("sphere-peak"), order=order)
        s.write(tmp_path / name)
        reader.SetFileName(str(tmp_path / name))
        reader.Update()
        data = reader.GetOutput()
        nodes = len(s.u) if name.endswith(".vtu") else mesh.num_vertices
        assert data.GetNumberOfPoints() == nodes and data.GetNumberOfCells() == mesh.num_triangles
        assert np.allclose(vtk_to_numpy(data.GetPointData().GetArray("solution")), s.u[:nodes])
        assert (vtk_to_numpy(data.GetCellData().GetArray("marked")) == 0).all()
        assert data.GetPointData().GetArray("error") is not None


@pytest.mark.skipif(importlib.util.find_spec("pyvista") is not None, reason="PyVista is installed")
def test_without_pyvista_its_conversions_say_what_is_missing():
    with pytest.raises(ImportError, match="needs the pyvista package"):
        rgbmesh.Mesh.from_arrays(*icosahedron()).to_pyvista()


@pytest.mark.skipif(importlib.util.find_spec("pyvista") is None, reason="PyVista is not installed")
def test_pyvista_objects_round_trip():
    mesh = adapted_mesh()
    pv = mesh.to_pyvista()
    assert pv.n_points == mesh.num_vertices
    assert corners(rgbmesh.from_pyvista(pv)) == corners(mesh)


def test_meshes_copy_and_pickle_as_the_same_rgb_mesh():
    import copy
    import pickle

    mesh = adapted_mesh()
    for other in (pickle.loads(pickle.dumps(mesh)), copy.deepcopy(mesh), mesh.copy()):
        assert other.validate() == "" and corners(other) == corners(mesh)
        assert np.array_equal(np.sort(other.vertex_levels()), np.sort(mesh.vertex_levels()))
    # A copy is independent: coarsening it leaves the original as it was.
    other = mesh.copy()
    other.refine_uniform(0)
    assert other.num_vertices == 12 and mesh.num_vertices > 12 and mesh.validate() == ""
