"""Meshes the Python tests share."""

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
