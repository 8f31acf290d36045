#!/usr/bin/env python3
"""Valid seeds in the variants that `rgbmesh convert` does not write, derived from a mesh it
wrote as OFF: legacy VTK (ASCII before and from version 5, binary, an unstructured grid), ASCII
PLY with normals, ASCII STL, and the point clouds .xyz and .pwn. The fuzzers start from valid
files of every variant the readers know, so that mutations reach past the first error.

    python3 fuzz/derive_seeds.py MESH.off OUT_DIR
"""

import math
import os
import struct
import sys


def read_off(path):
    words = open(path).read().split()
    assert words[0] == "OFF", path
    nv, nf = int(words[1]), int(words[2])
    at = 4
    points = [tuple(float(w) for w in words[at + 3 * i:at + 3 * i + 3]) for i in range(nv)]
    at += 3 * nv
    faces = []
    for _ in range(nf):
        n = int(words[at])
        faces.append(tuple(int(w) for w in words[at + 1:at + 1 + n]))
        at += 1 + n
    return points, faces


def vertex_normals(points, faces):
    normals = [[0.0, 0.0, 0.0] for _ in points]
    for f in faces:
        a, b, c = (points[i] for i in f[:3])
        u = [b[k] - a[k] for k in range(3)]
        v = [c[k] - a[k] for k in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        for i in f:
            for k in range(3):
                normals[i][k] += n[k]
    out = []
    for n in normals:
        length = math.sqrt(sum(c * c for c in n)) or 1.0
        out.append(tuple(c / length for c in n) if length else (0.0, 0.0, 1.0))
    return out


def text(values):
    return " ".join(repr(float(v)) for v in values)


def main(off_path, out):
    points, faces = read_off(off_path)
    normals = vertex_normals(points, faces)
    name = os.path.splitext(os.path.basename(off_path))[0]
    nv, nf = len(points), len(faces)
    conn = sum(len(f) for f in faces)

    def write(suffix, data):
        with open(os.path.join(out, name + suffix), "wb") as f:
            f.write(data.encode() if isinstance(data, str) else data)

    pts = "\n".join(text(p) for p in points) + "\n"
    classic = "".join("%d %s\n" % (len(f), " ".join(map(str, f))) for f in faces)
    write("-v3.vtk", "# vtk DataFile Version 3.0\n%s\nASCII\nDATASET POLYDATA\nPOINTS %d double\n%s"
          "POLYGONS %d %d\n%s" % (name, nv, pts, nf, nf + conn, classic))
    offsets = [0]
    for f in faces:
        offsets.append(offsets[-1] + len(f))
    write("-v51.vtk", "# vtk DataFile Version 5.1\n%s\nASCII\nDATASET POLYDATA\nPOINTS %d float\n%s"
          "POLYGONS %d %d\nOFFSETS vtktypeint64\n%s\nCONNECTIVITY vtktypeint64\n%s\n"
          "POINT_DATA %d\nNORMALS Normals float\n%s"
          % (name, nv, pts, nf + 1, conn, " ".join(map(str, offsets)),
             " ".join(str(i) for f in faces for i in f), nv, "\n".join(text(n) for n in normals) + "\n"))
    binary = (b"# vtk DataFile Version 5.1\n%s\nBINARY\nDATASET POLYDATA\nPOINTS %d double\n"
              % (name.encode(), nv))
    binary += b"".join(struct.pack(">3d", *p) for p in points)
    binary += b"\nPOLYGONS %d %d\nOFFSETS vtktypeint64\n" % (nf + 1, conn)
    binary += struct.pack(">%dq" % len(offsets), *offsets)
    binary += b"\nCONNECTIVITY vtktypeint64\n"
    binary += b"".join(struct.pack(">%dq" % len(f), *f) for f in faces) + b"\n"
    write("-binary.vtk", binary)
    write("-grid.vtk", "# vtk DataFile Version 3.0\n%s\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS %d double\n%s"
          "CELLS %d %d\n%sCELL_TYPES %d\n%s\n" % (name, nv, pts, nf, nf + conn, classic, nf,
                                                  "\n".join("5" if len(f) == 3 else "7" for f in faces)))
    write("-ascii.ply", "ply\nformat ascii 1.0\ncomment derived from %s\nelement vertex %d\nproperty double x\n"
          "property double y\nproperty double z\nproperty float nx\nproperty float ny\nproperty float nz\n"
          "element face %d\nproperty list uchar int vertex_indices\nend_header\n%s%s"
          % (os.path.basename(off_path), nv, nf,
             "".join("%s %s\n" % (text(p), text(n)) for p, n in zip(points, normals)), classic))
    facets = []  # single precision, as STL has it: 9 digits read back exactly
    for f in faces:
        for t in range(1, len(f) - 1):
            facets.append("  facet normal 0 0 1\n    outer loop\n%s    endloop\n  endfacet\n"
                          % "".join("      vertex %s\n" % " ".join("%.9g" % c for c in points[i])
                                    for i in (f[0], f[t], f[t + 1])))
    write("-ascii.stl", "solid %s\n%sendsolid %s\n" % (name, "".join(facets), name))
    write(".xyz", pts)
    write(".pwn", "".join("%s %s\n" % (text(p), text(n)) for p, n in zip(points, normals)))


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
