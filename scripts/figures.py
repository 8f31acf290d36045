#!/usr/bin/env python3
"""Draws the figures of the README and docs/ from real runs (standard library only).

  scripts/figures.py convergence UNIFORM.json ADAPTIVE.json OUT.svg
      error against unknowns, log-log, from two `rgbmesh adapt --report` files
  scripts/figures.py mesh CYCLE.vtp OUT.svg [VX VY VZ]
      the triangles of a VTP file written by rgbmesh, seen from direction V (orthographic),
      colored by the cell array `level` (or shaded by the light, if all levels are equal)

The VTP reader handles what rgbmesh writes with --compression zlib: appended raw data,
zlib-compressed, UInt32 or UInt64 headers (the standard library has no LZ4).
"""

import json
import math
import re
import struct
import sys
import zlib

TYPES = {"UInt8": "B", "Int32": "i", "Int64": "q", "UInt32": "I", "UInt64": "Q", "Float32": "f", "Float64": "d"}


def read_vtp(path):
    raw = open(path, "rb").read()
    start = raw.index(b'<AppendedData encoding="raw">')
    data = raw[raw.index(b"_", start) + 1:]
    header = raw[:start].decode("utf-8", "replace")
    if "vtkZLibDataCompressor" not in header:
        raise SystemExit(f"{path}: expected zlib-compressed appended data (rgbmesh --compression zlib)")
    word = "Q" if 'header_type="UInt64"' in header else "I"
    size = struct.calcsize(word)
    arrays, section = {}, "Other"
    for line in header.splitlines():
        for tag in ("PointData", "CellData", "Points", "Polys"):
            if f"<{tag}" in line:
                section = tag
        m = re.search(r'<DataArray type="(\w+)" Name="([^"]+)".*?offset="\s*(\d+)', line)
        if not m:
            continue
        kind, name, offset = m.group(1), m.group(2), int(m.group(3))
        nblocks, _, _ = struct.unpack_from(f"<3{word}", data, offset)
        sizes = struct.unpack_from(f"<{nblocks}{word}", data, offset + 3 * size)
        pos, out = offset + 3 * size + size * nblocks, b""
        for s in sizes:
            out += zlib.decompress(data[pos:pos + s])
            pos += s
        fmt = TYPES[kind]
        arrays[(section, name)] = struct.unpack(f"<{len(out) // struct.calcsize(fmt)}{fmt}", out)
    return arrays


def convergence(uniform_json, adaptive_json, out):
    runs = [(json.load(open(uniform_json)), "#1f77b4", "uniform"), (json.load(open(adaptive_json)), "#d62728", "adaptive")]
    width, height, left, bottom, top, right = 700, 440, 70, 50, 20, 200
    pts = [(c["dofs"], c[k]) for r, _, _ in runs for c in r["cycles"] for k in ("error_h1", "error_l2") if k in c]
    xmin, xmax = min(p[0] for p in pts), max(p[0] for p in pts)
    ymin, ymax = min(p[1] for p in pts), max(p[1] for p in pts)
    lx0, lx1 = math.floor(math.log10(xmin)), math.ceil(math.log10(xmax))
    ly0, ly1 = math.floor(math.log10(ymin)), math.ceil(math.log10(ymax))

    def xy(n, e):
        x = left + (math.log10(n) - lx0) / (lx1 - lx0) * (width - left - right)
        y = height - bottom - (math.log10(e) - ly0) / (ly1 - ly0) * (height - bottom - top)
        return x, y

    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="sans-serif" font-size="12">',
           f'<rect width="{width}" height="{height}" fill="white"/>']
    for d in range(lx0, lx1 + 1):
        x, _ = xy(10 ** d, 10 ** ly0)
        svg.append(f'<line x1="{x:.1f}" y1="{top}" x2="{x:.1f}" y2="{height - bottom}" stroke="#ddd"/>')
        svg.append(f'<text x="{x:.1f}" y="{height - bottom + 16}" text-anchor="middle">1e{d}</text>')
    for d in range(ly0, ly1 + 1):
        _, y = xy(10 ** lx0, 10 ** d)
        svg.append(f'<line x1="{left}" y1="{y:.1f}" x2="{width - right}" y2="{y:.1f}" stroke="#ddd"/>')
        svg.append(f'<text x="{left - 6}" y="{y + 4:.1f}" text-anchor="end">1e{d}</text>')
    svg.append(f'<text x="{(left + width - right) / 2}" y="{height - 12}" text-anchor="middle">unknowns (vertices)</text>')
    legend_y = top + 10
    for run, color, label in runs:
        for key, dash in (("error_h1", ""), ("error_l2", ' stroke-dasharray="5,3"')):
            cyc = [c for c in run["cycles"] if key in c]
            if not cyc:
                continue
            path = " ".join(f"{x:.1f},{y:.1f}" for x, y in (xy(c["dofs"], c[key]) for c in cyc))
            svg.append(f'<polyline points="{path}" fill="none" stroke="{color}" stroke-width="2"{dash}/>')
            for c in cyc:
                x, y = xy(c["dofs"], c[key])
                svg.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="2.5" fill="{color}"/>')
            name = "H1 seminorm" if key == "error_h1" else "L2"
            svg.append(f'<line x1="{width - right + 10}" y1="{legend_y}" x2="{width - right + 35}" y2="{legend_y}" stroke="{color}" stroke-width="2"{dash}/>')
            svg.append(f'<text x="{width - right + 40}" y="{legend_y + 4}">{label}, {name}</text>')
            legend_y += 18
    svg.append("</svg>")
    open(out, "w").write("\n".join(svg) + "\n")


def mesh_picture(vtp, out, view=(1.0, 0.8, 1.2)):
    a = read_vtp(vtp)
    p = a[("Points", "Points")]
    conn = a[("Polys", "connectivity")]
    levels = a[("CellData", "level")]
    vn = math.sqrt(sum(c * c for c in view))
    v = [c / vn for c in view]
    # An orthonormal frame with v as the viewing direction.
    up = (0.0, 0.0, 1.0) if abs(v[2]) < 0.9 else (0.0, 1.0, 0.0)
    ex = (up[1] * v[2] - up[2] * v[1], up[2] * v[0] - up[0] * v[2], up[0] * v[1] - up[1] * v[0])
    en = math.sqrt(sum(c * c for c in ex))
    ex = tuple(c / en for c in ex)
    ey = (v[1] * ex[2] - v[2] * ex[1], v[2] * ex[0] - v[0] * ex[2], v[0] * ex[1] - v[1] * ex[0])
    pts = [(p[3 * i], p[3 * i + 1], p[3 * i + 2]) for i in range(len(p) // 3)]
    proj = [(sum(q[k] * ex[k] for k in range(3)), sum(q[k] * ey[k] for k in range(3)), sum(q[k] * v[k] for k in range(3))) for q in pts]
    xs, ys = [q[0] for q in proj], [q[1] for q in proj]
    size = 600
    scale = 0.9 * size / max(max(xs) - min(xs), max(ys) - min(ys))
    cx, cy = (max(xs) + min(xs)) / 2, (max(ys) + min(ys)) / 2
    lmax = max(levels) or 1
    tris = []
    for t in range(len(conn) // 3):
        i, j, k = conn[3 * t], conn[3 * t + 1], conn[3 * t + 2]
        (x0, y0, z0), (x1, y1, z1), (x2, y2, z2) = proj[i], proj[j], proj[k]
        cross_z = (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0)
        if cross_z <= 0:
            continue  # facing away
        # The cosine between the triangle's normal and the direction to the viewer.
        a3, b3, c3 = pts[i], pts[j], pts[k]
        n3 = [(b3[1] - a3[1]) * (c3[2] - a3[2]) - (b3[2] - a3[2]) * (c3[1] - a3[1]),
              (b3[2] - a3[2]) * (c3[0] - a3[0]) - (b3[0] - a3[0]) * (c3[2] - a3[2]),
              (b3[0] - a3[0]) * (c3[1] - a3[1]) - (b3[1] - a3[1]) * (c3[0] - a3[0])]
        nn = math.sqrt(sum(q * q for q in n3)) or 1.0
        light = [v[m] + 0.6 * ex[m] + 0.5 * ey[m] for m in range(3)]  # from the upper left of the viewer
        ln = math.sqrt(sum(q * q for q in light))
        shade = abs(sum(n3[m] * light[m] for m in range(3))) / (nn * ln)
        tris.append(((z0 + z1 + z2) / 3, (x0, y0, x1, y1, x2, y2), levels[t], shade))
    tris.sort()
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{size + 130}" height="{size}" font-family="sans-serif" font-size="12">',
           f'<rect width="{size + 130}" height="{size}" fill="white"/>']

    def color(level):
        s = level / lmax  # blue (coarse) to yellow (fine)
        r, g, b = int(40 + 215 * s), int(60 + 170 * s), int(160 - 120 * s)
        return f"rgb({r},{g},{b})"

    shaded = max(levels) == min(levels)
    for _, c, level, shade in tris:
        pts2 = " ".join(f"{size / 2 + (c[2 * m] - cx) * scale:.1f},{size / 2 - (c[2 * m + 1] - cy) * scale:.1f}" for m in range(3))
        if shaded:  # one level: grey shading by the angle to the viewer, thin edges
            grey = int(70 + 170 * shade)
            svg.append(f'<polygon points="{pts2}" fill="rgb({grey},{grey},{grey + 10})" stroke="rgb({grey},{grey},{grey + 10})" stroke-width="0.4"/>')
        else:
            svg.append(f'<polygon points="{pts2}" fill="{color(level)}" stroke="#222" stroke-width="0.3"/>')
    for level in range(0 if not shaded else lmax + 1, lmax + 1):
        y = 30 + 22 * level
        svg.append(f'<rect x="{size + 20}" y="{y - 12}" width="16" height="16" fill="{color(level)}" stroke="#222" stroke-width="0.5"/>')
        svg.append(f'<text x="{size + 42}" y="{y + 1}">level {level}</text>')
    svg.append("</svg>")
    open(out, "w").write("\n".join(svg) + "\n")


if __name__ == "__main__":
    if len(sys.argv) >= 5 and sys.argv[1] == "convergence":
        convergence(sys.argv[2], sys.argv[3], sys.argv[4])
    elif len(sys.argv) in (4, 7) and sys.argv[1] == "mesh":
        mesh_picture(sys.argv[2], sys.argv[3], tuple(map(float, sys.argv[4:7])) if len(sys.argv) == 7 else (1.0, 0.8, 1.2))
    else:
        raise SystemExit(__doc__)
