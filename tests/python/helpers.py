"""What the Python tests share: meshes, the rgbmesh tool, the public test data."""

import os
import subprocess

import numpy as np


def icosahedron(unit=False):
    """The icosahedron's points and counter-clockwise triangles (on the unit sphere if unit)."""
    t = (1 + 5 ** 0.5) / 2
    points = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
                       [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], float)
    if unit:
        points /= np.linalg.norm(points, axis=1)[:, None]
    triangles = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
                          [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
                          [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]])
    return points, triangles


def write_obj(path, points, triangles):
    with open(path, "w") as f:
        for p in points:
            f.write("v %.17g %.17g %.17g\n" % tuple(p))
        for t in triangles:
            f.write("f %d %d %d\n" % tuple(np.asarray(t) + 1))


def tool(*args):
    """Runs the rgbmesh tool (RGBMESH_CLI) with these arguments; fails the test if it fails."""
    return subprocess.run([os.environ["RGBMESH_CLI"], *map(str, args)], check=True, capture_output=True, text=True)


def public(name):
    """A public test file (scripts/fetch-test-data.sh); fails, not skips, when it is missing."""
    path = os.path.join(os.environ["RGBMESH_PUBLIC_DATA"], name)
    assert os.path.exists(path), "missing public test data %s: run scripts/fetch-test-data.sh" % path
    return path
