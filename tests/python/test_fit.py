"""rgbmesh.fit from Python (issue 14): the same fit as the rgbmesh tool on the same target and
base (given, decimated from a scan's faces, reconstructed from a point cloud), a fitted limit
surface close to an analytic target, and errors for bad input."""

import json

import numpy as np
import pytest
import rgbmesh

from helpers import icosahedron, public, tool, write_obj


def ellipsoid_points(n=4000, axes=(1.0, 0.7, 0.5), seed=3):
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    return d / np.linalg.norm(d, axis=1)[:, None] * np.array(axes)


def test_an_ellipsoid_is_fitted_as_the_tool_fits_it(tmp_path):
    target = ellipsoid_points()
    points, triangles = icosahedron(unit=True)
    np.savetxt(tmp_path / "target.xyz", target, fmt="%.17g")
    write_obj(tmp_path / "base.obj", points, triangles)
    tool("fit", "--target", tmp_path / "target.xyz", "--base", tmp_path / "base.obj", "--out", tmp_path / "out",
         "--report", tmp_path / "report.json")
    expected = json.load(open(tmp_path / "report.json"))
    iterations = []
    r = rgbmesh.fit(target, base=(points, triangles), callback=iterations.append)
    # The same fit: the same iterations and distances.
    assert len(r["iterations"]) == len(expected["iterations"]) == len(iterations)
    assert np.isclose(r["rms"], expected["rms"], rtol=1e-6) and np.isclose(r["max"], expected["max"], rtol=1e-6)
    # The fitted limit surface is close to the ellipsoid: the analytic distance of its points.
    assert r["rms"] < 2e-3 * r["diagonal"]
    limit = r["limit_points"]
    implicit = np.sqrt(((limit / np.array([1.0, 0.7, 0.5])) ** 2).sum(axis=1))
    assert np.abs(implicit - 1).max() < 0.02
    # The fitted base is a Mesh with the base's triangles; its limit at level 3 is limit_points.
    fitted = r["mesh"]
    assert fitted.num_vertices == 12 and np.array_equal(fitted.triangles(), triangles)
    fitted.refine_uniform(3)
    assert np.allclose(np.sort(fitted.limit_positions(), axis=0), np.sort(limit, axis=0), atol=1e-12)
    assert r["distances"].shape == (len(target),)
    assert np.isclose(np.sqrt((r["distances"] ** 2).mean()), r["rms"])


def test_a_scan_s_faces_are_decimated_into_the_base_as_the_tool_does(tmp_path):
    path = public("elephant-with-holes.off")
    tool("fit", "--target", path, "--base-faces", 400, "--iterations", 4, "--out", tmp_path / "out",
         "--report", tmp_path / "report.json")
    expected = json.load(open(tmp_path / "report.json"))
    r = rgbmesh.fit(path, base_faces=400, iterations=4)
    assert r["base_source"] == expected["base"]["source"] == "decimated"
    assert r["base"].num_triangles == expected["base"]["faces"]
    assert "106 boundary loops" in r["topology"]
    assert np.isclose(r["rms"], expected["rms"], rtol=1e-6)
    # The same target as arrays: the same fit.
    scan = rgbmesh.read(path)
    r2 = rgbmesh.fit(scan.control_points(), target_triangles=scan.triangles(), base_faces=400, iterations=4)
    assert np.isclose(r2["rms"], r["rms"], rtol=1e-9)


def test_a_point_cloud_gets_a_reconstructed_base():
    r = rgbmesh.fit(public("kitten.xyz"), base_faces=300, iterations=3)
    assert r["base_source"] == "reconstructed"
    assert r["mesh"].validate() == "" and r["rms"] < 0.01 * r["diagonal"]
    assert r["accepted"] and r["reason"] == ""
    assert r["surface_to_target"].shape == (len(r["limit_points"]),)
    assert r["surface_to_target_rms"] < 0.005 * r["diagonal"]


def test_a_fit_that_fails_the_two_sided_check_raises_unless_asked_for():
    # oni.pwn: a mask, whose fitted surface strays from the points where the scan is thin.
    with pytest.raises(ValueError, match="surface-to-target"):
        rgbmesh.fit(public("oni.pwn"), base_faces=300, iterations=3)
    r = rgbmesh.fit(public("oni.pwn"), base_faces=300, iterations=3, check=False)
    assert not r["accepted"] and "surface-to-target" in r["reason"]
    assert r["surface_to_target_rms"] > 0.005 * r["diagonal"]


def test_bad_input_is_refused_with_the_reason():
    points, triangles = icosahedron(unit=True)
    with pytest.raises(ValueError, match=r"target: an \(n, 3\) array"):
        rgbmesh.fit(np.zeros((10, 2)), base=(points, triangles))
    with pytest.raises(ValueError, match="target: point 1 is not finite"):
        rgbmesh.fit(np.array([[0, 0, 0], [np.inf, 0, 0]]), base=(points, triangles))
    refined = rgbmesh.Mesh.from_arrays(points, triangles)
    refined.refine_uniform(1)
    with pytest.raises(ValueError, match="base: the mesh is refined"):
        rgbmesh.fit(ellipsoid_points(100), base=refined)
    with pytest.raises(ValueError, match="loss: 'l1'"):
        rgbmesh.fit(ellipsoid_points(100), base=(points, triangles), loss="l1")
    with pytest.raises(ValueError, match="levels: must be in"):
        rgbmesh.fit(ellipsoid_points(100), base=(points, triangles), levels=9)
    with pytest.raises(ValueError, match="base triangles: triangle 0 has vertex index 12"):
        rgbmesh.fit(ellipsoid_points(100), base=(points, np.array([[0, 1, 12]])))
    with pytest.raises(ValueError, match="no_such_file.xyz"):
        rgbmesh.fit("no_such_file.xyz")
