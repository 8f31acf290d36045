"""Sharp features from Python (issue 42): creases and corners in and out as numpy arrays, through
OBJ tags, sharp_angle, the RGB state (files, pickling, VTK objects), against the tool."""

import os
import pickle

import numpy as np
import pytest

import rgbmesh
from helpers import public, tool


def unit_cube():
    points = np.array([[i & 1, (i >> 1) & 1, (i >> 2) & 1] for i in range(8)], float)
    faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    triangles = np.array([t for f in faces for t in ([f[0], f[1], f[2]], [f[0], f[2], f[3]])])
    edges = np.array(sorted({tuple(sorted((f[k], f[(k + 1) % 4]))) for f in faces for k in range(4)}))
    return points, triangles, edges


def on_cube_faces(p):
    return np.min(np.minimum(np.abs(p), np.abs(1 - p)), axis=1)


def test_a_cube_with_sharp_edges_stays_a_cube():
    points, triangles, edges = unit_cube()
    smooth = rgbmesh.Mesh.from_arrays(points, triangles)
    sharp = rgbmesh.Mesh.from_arrays(points, triangles, sharp_edges=edges)
    assert len(sharp.sharp_features()["edges"]) == 12
    for m in (smooth, sharp):
        m.refine_uniform(3)
    assert on_cube_faces(sharp.limit_positions()).max() < 1e-12
    assert on_cube_faces(smooth.limit_positions()).max() > 0.1
    # The same from the angle alone.
    detected = rgbmesh.Mesh.from_arrays(points, triangles, sharp_angle=30)
    np.testing.assert_array_equal(detected.sharp_features()["edges"], edges)
    rules = sharp.vertex_rules()
    assert (rules[:8] == 3).all()  # the cube's corners
    ends, sharpness = sharp.edges()
    assert ends.shape == (sharp.num_triangles * 3 // 2, 2) and sharpness.shape == (len(ends),)
    assert (sharpness == 10).sum() == 12 * 8  # each cube edge in 8 pieces at level 3


def test_semi_sharp_and_chaikin_round_trip_through_files_pickles_and_vtk(tmp_path):
    points, triangles, edges = unit_cube()
    m = rgbmesh.Mesh.from_arrays(points, triangles, sharp_edges=edges[:4], edge_sharpness=[0.5, 1.5, 2.5, 10],
                                 sharp_vertices=[7], vertex_sharpness=[2.0], crease_method="chaikin")
    m.refine(ball=(0, 0, 0, 0.6, 4))
    features = m.sharp_features()
    assert features["method"] == "chaikin"
    np.testing.assert_array_equal(features["edge_sharpness"], [0.5, 1.5, 2.5, 10])
    limits = m.limit_positions()
    path = tmp_path / "m.vtp"
    m.write(path)
    assert os.path.exists(tmp_path / "m.vtp")
    for back in (rgbmesh.read(path), pickle.loads(pickle.dumps(m)), rgbmesh.from_vtk(m.to_vtk())):
        assert back.sharp_features()["method"] == "chaikin"
        np.testing.assert_array_equal(back.sharp_features()["edges"], features["edges"])
        np.testing.assert_allclose(back.limit_positions(), limits, atol=1e-12)
        np.testing.assert_array_equal(back.vertex_rules(), m.vertex_rules())


def test_obj_tags_and_the_tool_agree(tmp_path):
    shape = public("opensubdiv/loop_cube_creases1.obj")
    m = rgbmesh.read(shape)
    assert len(m.sharp_features()["edges"]) == 12
    m.refine_uniform(2)
    out = tmp_path / "tool.obj"
    tool("refine", shape, out, "--uniform", 2)
    refined = rgbmesh.read(out)  # its tags are the level-2 edges' sharpness
    np.testing.assert_allclose(refined.control_points(), m.control_points(), atol=1e-12)
    assert len(refined.sharp_features()["edges"]) == int((m.edges()[1] > 0).sum())  # a closed cube


def test_bad_sharp_arguments_are_value_errors():
    points, triangles, edges = unit_cube()
    with pytest.raises(ValueError, match="not an edge"):
        rgbmesh.Mesh.from_arrays(points, triangles, sharp_edges=[[0, 7]])
    with pytest.raises(ValueError, match="edge_sharpness"):
        rgbmesh.Mesh.from_arrays(points, triangles, sharp_edges=edges, edge_sharpness=[1.0])
    with pytest.raises(ValueError, match="crease_method"):
        rgbmesh.Mesh.from_arrays(points, triangles, crease_method="loop")
    with pytest.raises(ValueError, match="sharp_angle"):
        rgbmesh.Mesh.from_arrays(points, triangles, sharp_angle=200)
