#!/usr/bin/python3
"""A band of fine triangles that sweeps over the Stanford bunny, driven from numpy.

The indicator is the user's own: the distance of each vertex's limit position to a plane that
moves from the bunny's feet to its ears. Triangles with a corner within the band are refined,
one level per pass, up to --max-level; vertices farther than twice the band's half-width are
removed again. RGB subdivision keeps the mesh conforming after every single operation, and the
surface is always the bunny's Loop limit surface.

    PYTHONPATH=build/python examples/python/moving_band.py [--steps 8] [--max-level 4] [--out DIR]

Each step writes DIR/step_NNN.vtp (with the RGB state and the indicator), DIR/band.pvd lists
them for ParaView; with PyVista installed, --show opens the last step, --screenshot FILE saves it.
"""

import argparse
import os
import time

import numpy as np
import rgbmesh

HERE = os.path.dirname(os.path.abspath(__file__))
BUNNY = os.path.join(HERE, "..", "..", "data", "bunny.obj")


def distance_to_plane(points, normal, offset):
    return points @ normal - offset


def adapt_to_band(mesh, normal, offset, width, max_level):
    """Refines the triangles that touch the band |n·x - s| < width, one level per pass, and
    coarsens where the vertices are farther than 2 width, until a pass changes nothing."""
    passes = 0
    while True:
        d = np.abs(distance_to_plane(mesh.limit_positions(), normal, offset))
        near = (d[mesh.triangles()] < width).any(axis=1)
        # Vertices are removed where their value is below coarsen_below: width / d < 1/2 is
        # farther than 2 width from the plane.
        r = mesh.adapt_to(triangle_values=near.astype(float), refine_above=0.5,
                          vertex_values=width / np.maximum(d, 1e-300), coarsen_below=0.5, max_level=max_level)
        passes += 1
        if r["splits"] == 0 and r["removals"] == 0:
            return passes


def write_series(out, files):
    with open(os.path.join(out, "band.pvd"), "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n')
        for step, name in enumerate(files):
            f.write('    <DataSet timestep="%d" file="%s"/>\n' % (step, name))
        f.write("  </Collection>\n</VTKFile>\n")


def main():
    parser = argparse.ArgumentParser(description="A band of fine triangles sweeping over the bunny.")
    parser.add_argument("--steps", type=int, default=8, help="positions of the plane (default 8)")
    parser.add_argument("--max-level", type=int, default=4, help="finest level in the band (default 4)")
    parser.add_argument("--width", type=float, default=0.02, help="half-width of the band, as a fraction of the height")
    parser.add_argument("--out", default="out/python_band", help="output folder (default out/python_band)")
    parser.add_argument("--show", action="store_true", help="show the last step with PyVista")
    parser.add_argument("--screenshot", help="save the last step as a PNG with PyVista")
    args = parser.parse_args()
    if args.steps < 2 or not 1 <= args.max_level <= 8 or not 0 < args.width < 0.5:
        parser.error("--steps >= 2, --max-level in [1, 8] and --width in (0, 0.5) are needed")

    mesh = rgbmesh.read(BUNNY)
    base_points = mesh.control_points()
    limit = mesh.limit_positions()
    normal = np.array([0.0, 1.0, 0.0])  # the bunny's up
    low, high = (limit @ normal).min(), (limit @ normal).max()
    width = args.width * (high - low)
    os.makedirs(args.out, exist_ok=True)
    print("bunny: %d vertices, %d triangles; band of half-width %.4g, finest level %d"
          % (mesh.num_vertices, mesh.num_triangles, width, args.max_level))
    print("step   plane  vertices  triangles  in band  passes  seconds")
    files = []
    for step in range(args.steps):
        offset = low + (high - low) * step / (args.steps - 1)
        start = time.perf_counter()
        passes = adapt_to_band(mesh, normal, offset, width, args.max_level)
        seconds = time.perf_counter() - start
        assert mesh.validate() == ""
        d = distance_to_plane(mesh.limit_positions(), normal, offset)
        in_band = int((np.abs(d[mesh.triangles()]) < width).any(axis=1).sum())
        print("%4d  %6.3f  %8d  %9d  %7d  %6d  %7.2f"
              % (step, offset, mesh.num_vertices, mesh.num_triangles, in_band, passes, seconds))
        name = "step_%03d.vtp" % step
        mesh.write(os.path.join(args.out, name), limit=True)
        files.append(name)
    write_series(args.out, files)
    # Coarsening every inserted vertex gives back the base mesh exactly.
    mesh_at_end = mesh.num_vertices
    mesh.refine_uniform(0)
    print("coarsened from %d vertices back to the base: %d vertices, control points %s"
          % (mesh_at_end, mesh.num_vertices, "identical" if np.array_equal(mesh.control_points(), base_points)
             else "DIFFERENT"))
    print("wrote %s/band.pvd (open it in ParaView, color by the cell array 'level')" % args.out)

    if args.show or args.screenshot:
        last = rgbmesh.read(os.path.join(args.out, files[-1]))
        try:
            view = last.to_pyvista(points="limit")
        except ImportError as e:
            print("no PyVista (%s): open the .pvd in ParaView instead" % e)
            return
        view.cell_data["level"] = last.triangle_levels()
        view.plot(scalars="level", show_edges=True, off_screen=bool(args.screenshot), screenshot=args.screenshot)


if __name__ == "__main__":
    main()
