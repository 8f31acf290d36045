#!/usr/bin/python3
"""What the Python package costs on top of the C++ library: building each numpy array of a mesh
of about 10^6 vertices, as a fraction of refining that mesh, in the same process.

    PYTHONPATH=build/python bench/python_overhead.py [--repeat N]

Two references: uniform refinement of a 32 x 32 torus to level 5 (1,048,576 vertices; the
level-by-level sweep, the fastest refinement there is) and an adaptive one (a geometric
criterion through the RGB queues) to a mesh of the same size. Each array is timed twice: the
first call may compute something (the limit positions, and the control points of the vertices
shown above their insertion level, which come from them), the second only builds the array.
The figures are the best of --repeat runs, each on a new mesh.
"""

import argparse
import time

import numpy as np
import rgbmesh


def torus(n=32, m=32, big=1.0, small=0.35):
    i, j = np.meshgrid(np.arange(n), np.arange(m), indexing="ij")
    u, v = 2 * np.pi * i.ravel() / n, 2 * np.pi * j.ravel() / m
    points = np.c_[(big + small * np.cos(v)) * np.cos(u), (big + small * np.cos(v)) * np.sin(u), small * np.sin(v)]
    a, b = i.ravel(), j.ravel()
    index = lambda p, q: (p % n) * m + (q % m)
    triangles = np.r_[np.c_[index(a, b), index(a + 1, b), index(a + 1, b + 1)],
                      np.c_[index(a, b), index(a + 1, b + 1), index(a, b + 1)]]
    return points, triangles


ARRAYS = ["vertex_levels", "triangle_levels", "triangle_colors", "parents", "triangles", "insertion_points",
          "control_points", "limit_positions", "state"]


def seconds(f):
    start = time.perf_counter()
    f()
    return time.perf_counter() - start


def run(refine):
    mesh = rgbmesh.Mesh.from_arrays(*torus())
    reference = seconds(lambda: refine(mesh))
    first = {name: seconds(getattr(mesh, name)) for name in ARRAYS}
    again = {name: seconds(getattr(mesh, name)) for name in ARRAYS}
    return mesh.num_vertices, reference, first, again


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    references = {
        "uniform level 5": lambda m: m.refine_uniform(5),
        # A tolerance of the torus's flat triangles against the Loop surface, chosen to give
        # about as many vertices as the uniform mesh (more where the torus curves most).
        "adaptive (geometric tolerance)": lambda m: m.refine(tolerance=5.0e-6),
    }
    for title, refine in references.items():
        runs = [run(refine) for _ in range(args.repeat)]
        vertices = runs[0][0]
        reference = min(r[1] for r in runs)
        print("%s: %s vertices, refinement %.3f s (best of %d)" % (title, format(vertices, ","), reference, args.repeat))
        print("  %-18s %10s %8s %10s %8s" % ("array", "first s", "ratio", "again s", "ratio"))
        total_first = total_again = 0.0
        for name in ARRAYS:
            f = min(r[2][name] for r in runs)
            a = min(r[3][name] for r in runs)
            total_first += f
            total_again += a
            print("  %-18s %10.4f %7.1f%% %10.4f %7.1f%%" % (name, f, 100 * f / reference, a, 100 * a / reference))
        print("  %-18s %10.4f %7.1f%% %10.4f %7.1f%%" % ("all", total_first, 100 * total_first / reference,
                                                        total_again, 100 * total_again / reference))


if __name__ == "__main__":
    main()
