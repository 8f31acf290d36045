"""The Python package rgbmesh (issue 14), first slice: a mesh from numpy arrays with the files'
validation, arrays out, uniform refinement; the same mesh and positions as the rgbmesh tool
gives for the same input and stages."""

import os
import subprocess

import numpy as np
import pytest
import rgbmesh

from helpers import icosahedron, write_obj

vtk = pytest.importorskip("vtk")
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402


def test_uniform_refinement_counts_and_invariants():
    points, triangles = icosahedron()
    mesh = rgbmesh.Mesh.from_arrays(points, triangles)
    assert (mesh.num_vertices, mesh.num_triangles) == (12, 20)
    inserted = mesh.refine_uniform(3)
    # Each level adds a vertex per edge and splits each triangle in four.
    assert (mesh.num_vertices, mesh.num_triangles, inserted) == (642, 1280, 630)
    assert mesh.validate() == ""
    levels = mesh.vertex_levels()
    assert levels.shape == (642,) and levels.max() == 3 and (levels == 0).sum() == 12
    tri = mesh.triangles()
    assert tri.shape == (1280, 3) and tri.min() == 0 and tri.max() == 641
    # Coarsening back to level 0 gives the base mesh's control points again.
    mesh.refine_uniform(0)
    assert np.array_equal(mesh.control_points(), points)


def test_the_same_limit_positions_as_the_tool(tmp_path):
    points, triangles = icosahedron()
    base = tmp_path / "ico.obj"
    write_obj(base, points, triangles)
    out = tmp_path / "refined.vtp"
    subprocess.run([os.environ["RGBMESH_CLI"], "refine", str(base), str(out), "--uniform", "2", "--limit"], check=True,
                   capture_output=True)
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(str(out))
    reader.Update()
    data = reader.GetOutput()
    tool_points = vtk_to_numpy(data.GetPoints().GetData())
    tool_triangles = vtk_to_numpy(data.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    mesh = rgbmesh.Mesh.from_arrays(points, triangles)
    mesh.refine_uniform(2)
    mine = mesh.limit_positions()
    # The same triangles by their corners' positions, the positions to the last digits.
    assert mine.shape == tool_points.shape
    key = lambda p: tuple(np.round(p, 12))
    index = {key(p): i for i, p in enumerate(tool_points)}
    mapped = np.array([index[key(p)] for p in mine])
    assert np.abs(tool_points[mapped] - mine).max() < 1e-15
    assert {tuple(sorted(mapped[t])) for t in mesh.triangles()} == {tuple(sorted(t)) for t in tool_triangles}


@pytest.mark.parametrize("points, triangles, message", [
    (np.zeros((3, 3)), np.array([[0, 1, 5]]), "vertex index 5, out of range"),
    (np.zeros((3, 2)), np.array([[0, 1, 2]]), "points: an (n, 3) array is needed"),
    (np.array([[0, 0, 0], [1, 0, np.nan], [0, 1, 0]]), np.array([[0, 1, 2]]), "point 1 is not finite"),
])
def test_bad_input_is_a_value_error_naming_the_element(points, triangles, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        rgbmesh.Mesh.from_arrays(points, triangles)
    assert issubclass(rgbmesh.InputError, ValueError)


def test_built_in_criteria_and_the_level_cap():
    points, triangles = icosahedron()
    mesh = rgbmesh.Mesh.from_arrays(points, triangles)
    r = mesh.refine(ball=(0.0, 1.6, 0.0, 0.5, 4), max_level=3)
    assert r["splits"] > 0 and mesh.max_level == 3 and mesh.validate() == ""
    before = mesh.num_triangles
    mesh.refine(budget=before + 200)
    assert before + 200 <= mesh.num_triangles <= before + 210  # a split adds 2 to 4 triangles
    with pytest.raises(ValueError, match="uniform: level 99"):
        mesh.refine(uniform=99)


def test_a_user_indicator_refines_and_coarsens_back_to_the_base():
    points, triangles = icosahedron()
    mesh = rgbmesh.Mesh.from_arrays(points, triangles)
    # Refine where the triangles' centres lie in the upper half, three times.
    for _ in range(3):
        p, t = mesh.control_points(), mesh.triangles()
        centre_z = p[t].mean(axis=1)[:, 2]
        mesh.adapt_to(triangle_values=(centre_z > 0).astype(float))
        assert mesh.validate() == ""
    refined = mesh.num_vertices
    levels = mesh.vertex_levels()
    assert refined > 12 and levels.max() == 3
    # The upper half got finer (forced splits reach a little below the equator), the lower cap
    # (z < -1, the base's lowest vertices at -1.62) not at all.
    z = mesh.control_points()[levels > 0][:, 2]
    assert (z > 0).mean() > 0.8 and z.min() > -1.0
    # Coarsen everything: every inserted vertex's value below the threshold, until none goes.
    while mesh.num_vertices > 12:
        r = mesh.adapt_to(vertex_values=np.zeros(mesh.num_vertices), coarsen_below=1.0)
        assert r["removals"] > 0 and mesh.validate() == ""
    assert np.array_equal(mesh.control_points(), points)
    assert {tuple(sorted(t)) for t in mesh.triangles()} == {tuple(sorted(t)) for t in triangles}
    with pytest.raises(ValueError, match="one value per triangle"):
        mesh.adapt_to(triangle_values=np.zeros(3))
    with pytest.raises(ValueError, match="triangle_values: row 7 is not finite"):
        mesh.adapt_to(triangle_values=np.where(np.arange(mesh.num_triangles) == 7, np.nan, 1.0))
    with pytest.raises(ValueError, match="vertex_values: row 3 is not finite"):
        mesh.adapt_to(vertex_values=np.where(np.arange(mesh.num_vertices) == 3, np.inf, 1.0))


def test_written_and_read_back_with_the_rgb_state(tmp_path):
    points, triangles = icosahedron()
    mesh = rgbmesh.Mesh.from_arrays(points, triangles)
    mesh.refine(ball=(0.0, 1.6, 0.0, 0.5, 3))
    path = tmp_path / "adapted.vtp"
    mesh.write(path)
    back = rgbmesh.read(path)
    # The RGB state restores the same mesh: levels, triangles and control points.
    assert back.num_vertices == mesh.num_vertices and back.validate() == ""
    assert np.array_equal(np.sort(back.vertex_levels()), np.sort(mesh.vertex_levels()))
    key = lambda m: {tuple(sorted(map(tuple, np.round(m.control_points()[t], 12)))) for t in m.triangles()}
    assert key(back) == key(mesh)
    # Other formats: the base mesh of their triangles.
    mesh.write(tmp_path / "adapted.obj", limit=True)
    assert rgbmesh.read(tmp_path / "adapted.obj").num_vertices == mesh.num_vertices


def test_bad_files_and_unwritable_paths(tmp_path):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nf 1 2 7\n")
    with pytest.raises(ValueError, match="bad.obj: line 3"):
        rgbmesh.read(bad)
    points, triangles = icosahedron()
    mesh = rgbmesh.Mesh.from_arrays(points, triangles)
    with pytest.raises(OSError):
        mesh.write(tmp_path / "no" / "such" / "folder" / "x.vtp")
    with pytest.raises(ValueError, match="compression 'zip'"):
        mesh.write(tmp_path / "x.vtp", compression="zip")


def test_levels_colours_and_parents_describe_the_rgb_structure():
    points, triangles = icosahedron()
    mesh = rgbmesh.Mesh.from_arrays(points, triangles)
    mesh.refine(ball=(0.0, 1.6, 0.0, 0.5, 3))
    parents, levels = mesh.parents(), mesh.vertex_levels()
    base = levels == 0
    assert (parents[base] == -1).all() and (parents[~base] >= 0).all()
    # A vertex is finer than both its parents, and its parents are joined by no edge now (it
    # split that edge).
    assert (levels[parents[~base]].max(axis=1) < levels[~base]).all()
    edges = {tuple(sorted(e)) for t in mesh.triangles() for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
    assert not any(tuple(sorted(p)) in edges for p in parents[~base])
    colours, tlevels = mesh.triangle_colors(), mesh.triangle_levels()
    assert set(np.unique(colours)) <= {0, 1, 2} and 1 in colours and 2 in colours
    assert tlevels.shape == colours.shape == (mesh.num_triangles,) and tlevels.max() == 3


def test_read_repairs_when_asked(tmp_path):
    # The octahedron with its edge (0, 2) split at its midpoint on one side only, the crack
    # closed by a zero-area triangle (as OpenSCAD exports do), written as an STL file.
    points = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1], [0.5, 0.5, 0]], float)
    faces = [[0, 6, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5],
             [6, 2, 4], [0, 2, 6]]
    path = tmp_path / "crack.stl"
    with open(path, "w") as f:
        f.write("solid crack\n")
        for face in faces:
            f.write("facet normal 0 0 0\nouter loop\n")
            for v in face:
                f.write("vertex %.17g %.17g %.17g\n" % tuple(points[v]))
            f.write("endloop\nendfacet\n")
        f.write("endsolid crack\n")
    with pytest.raises(ValueError, match=r"zero area \(its corners .* are collinear\) \(repair=True collapses degenerate"):
        rgbmesh.read(path)
    with pytest.warns(UserWarning, match="repaired: collapsed 1 zero-area triangle"):
        mesh = rgbmesh.read(path, repair=True)
    assert mesh.validate() == ""
    p, t = mesh.control_points(), mesh.triangles()
    # Closed (every edge in two triangles), the octahedron's volume 4/3.
    edges = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    assert (np.unique(edges, axis=0, return_counts=True)[1] == 2).all()
    volume = np.einsum("ij,ij->i", p[t[:, 0]], np.cross(p[t[:, 1]], p[t[:, 2]])).sum() / 6
    assert abs(abs(volume) - 4 / 3) < 1e-12
