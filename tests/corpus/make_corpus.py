#!/usr/bin/env python3
"""Writes the corpus of malformed input files that test_corpus feeds to `rgbmesh`.

Every file here is damaged in one way: each must give exit code 2 and a single line naming the
file, never a crash, a hang, a large allocation or an output. The files are small; they are
committed in files/ together with this script, which makes exactly the same bytes on every run
(standard library only, fixed seeds).

    python3 tests/corpus/make_corpus.py            # rewrite files/
    python3 tests/corpus/make_corpus.py --check    # exit 1 if files/ differs from what it makes

files/MANIFEST.tsv has one line per file: name, the commands that must fail on it ("info convert
fit", or "info convert" for a file whose damage is in the mesh only, which makes it a valid point
cloud for fit, or "convert" for a valid point cloud, which info describes), and a text the error
line must contain (may be empty).
"""

import base64
import os
import random
import shutil
import struct
import sys
import tempfile
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))

# ---------------------------------------------------------------------------------------------
# A valid octahedron in every format; the cases damage it.

POINTS = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
TRIANGLES = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]


def fmt(x):
    return repr(float(x)) if x != int(x) else str(int(x))


def off_text(points=POINTS, triangles=TRIANGLES, counts=None):
    nv, nf = counts if counts else (len(points), len(triangles))
    lines = ["OFF", "%d %d 0" % (nv, nf)]
    lines += [" ".join(fmt(c) for c in p) for p in points]
    lines += ["3 " + " ".join(str(i) for i in t) for t in triangles]
    return "\n".join(lines) + "\n"


def obj_text(points=POINTS, triangles=TRIANGLES):
    lines = ["v " + " ".join(fmt(c) for c in p) for p in points]
    lines += ["f " + " ".join(str(i + 1) for i in t) for t in triangles]
    return "\n".join(lines) + "\n"


def ply_header(fmt_name, nv, nf, extra_vertex_props=""):
    return ("ply\nformat %s 1.0\nelement vertex %s\nproperty float x\nproperty float y\nproperty float z\n%s"
            "element face %s\nproperty list uchar int vertex_indices\nend_header\n"
            % (fmt_name, nv, extra_vertex_props, nf))


def ply_binary(big_endian=False):
    e = ">" if big_endian else "<"
    body = b"".join(struct.pack(e + "3f", *p) for p in POINTS)
    body += b"".join(struct.pack(e + "B3i", 3, *t) for t in TRIANGLES)
    name = "binary_big_endian" if big_endian else "binary_little_endian"
    return ply_header(name, len(POINTS), len(TRIANGLES)).encode() + body


def ply_ascii():
    body = "".join(" ".join(fmt(c) for c in p) + "\n" for p in POINTS)
    body += "".join("3 %d %d %d\n" % t for t in TRIANGLES)
    return ply_header("ascii", len(POINTS), len(TRIANGLES)) + body


def stl_binary(count=None, triangles=TRIANGLES):
    data = b"binary STL written for the rgbmesh corpus".ljust(80, b" ")
    data += struct.pack("<I", len(triangles) if count is None else count)
    for t in triangles:
        data += struct.pack("<3f", 0, 0, 1)
        for i in t:
            data += struct.pack("<3f", *POINTS[i])
        data += struct.pack("<H", 0)
    return data


def stl_ascii(words=None):
    """ASCII STL; `words` replaces keywords (for misspellings)."""
    w = {"solid": "solid", "facet": "facet", "normal": "normal", "outer": "outer", "loop": "loop",
         "vertex": "vertex", "endloop": "endloop", "endfacet": "endfacet", "endsolid": "endsolid"}
    w.update(words or {})
    lines = ["%s octahedron" % w["solid"]]
    for t in TRIANGLES:
        lines.append("  %s %s 0 0 1" % (w["facet"], w["normal"]))
        lines.append("    %s %s" % (w["outer"], w["loop"]))
        for i in t:
            lines.append("      %s %s" % (w["vertex"], " ".join(fmt(c) for c in POINTS[i])))
        lines.append("    %s" % w["endloop"])
        lines.append("  %s" % w["endfacet"])
    lines.append("%s octahedron" % w["endsolid"])
    return "\n".join(lines) + "\n"


def legacy_ascii():
    pts = " ".join(" ".join(fmt(c) for c in p) for p in POINTS)
    polys = "".join("3 %d %d %d\n" % t for t in TRIANGLES)
    return ("# vtk DataFile Version 3.0\noctahedron\nASCII\nDATASET POLYDATA\nPOINTS %d double\n%s\n"
            "POLYGONS %d %d\n%s" % (len(POINTS), pts, len(TRIANGLES), 4 * len(TRIANGLES), polys))


def legacy_binary():
    pts = b"".join(struct.pack(">3d", *p) for p in POINTS)
    offsets = struct.pack(">%dq" % (len(TRIANGLES) + 1), *[3 * i for i in range(len(TRIANGLES) + 1)])
    conn = b"".join(struct.pack(">3q", *t) for t in TRIANGLES)
    return (b"# vtk DataFile Version 5.1\noctahedron\nBINARY\nDATASET POLYDATA\nPOINTS 6 double\n" + pts +
            b"\nPOLYGONS %d %d\nOFFSETS vtktypeint64\n" % (len(TRIANGLES) + 1, 3 * len(TRIANGLES)) + offsets +
            b"\nCONNECTIVITY vtktypeint64\n" + conn + b"\n")


# ---------------------------------------------------------------------------------------------
# VTK XML, as VTK's writers lay it out: ascii, inline base64 ("binary") or appended (raw or
# base64), uncompressed or zlib-compressed, with a UInt32 or UInt64 size header.

class Array:
    def __init__(self, name, vtype, values, components=1):
        self.name, self.vtype, self.values, self.components = name, vtype, values, components


PACK = {"Float64": "d", "Float32": "f", "Int64": "q", "Int32": "i", "UInt8": "B"}


def array_bytes(a):
    return struct.pack("<%d%s" % (len(a.values), PACK[a.vtype]), *a.values)


def encode_block(raw, mode, header64):
    """The bytes (before base64) of one array: size header and data."""
    w = "<Q" if header64 else "<I"
    if mode == "compressed":
        if not raw:
            return struct.pack(w, 0) + struct.pack(w, 32768) + struct.pack(w, 0), b""
        comp = zlib.compress(raw, 6)
        header = struct.pack(w, 1) + struct.pack(w, 32768) + struct.pack(w, len(raw) % 32768) + struct.pack(w, len(comp))
        return header, comp
    return struct.pack(w, len(raw)) + raw, None


def xml_file(kind, arrays, piece_attrs, encoding="appended-raw", compressed=True, header64=False):
    """arrays: list of (section, Array); section is PointData, CellData, Points, Polys, Cells."""
    root = '<VTKFile type="%s" version="0.1" byte_order="LittleEndian" header_type="%s"%s>\n' % (
        kind, "UInt64" if header64 else "UInt32", ' compressor="vtkZLibDataCompressor"' if compressed else "")
    mode = "compressed" if compressed else "plain"
    appended = b""
    sections = {}
    for section, a in arrays:
        attrs = 'type="%s" Name="%s"' % (a.vtype, a.name)
        if a.components != 1:
            attrs += ' NumberOfComponents="%d"' % a.components
        raw = array_bytes(a)
        if encoding == "ascii":
            body = " ".join(fmt(v) if isinstance(v, float) else str(v) for v in a.values)
            line = '<DataArray %s format="ascii">\n          %s\n        </DataArray>' % (attrs, body)
        else:
            header, data = encode_block(raw, mode, header64)
            if encoding == "binary":
                text = base64.b64encode(header) + (base64.b64encode(data) if data is not None else b"")
                line = '<DataArray %s format="binary">\n          %s\n        </DataArray>' % (attrs, text.decode())
            else:
                if encoding == "appended-base64":
                    chunk = base64.b64encode(header) + (base64.b64encode(data) if data is not None else b"")
                else:
                    chunk = header + (data or b"")
                line = '<DataArray %s format="appended" offset="%d"/>' % (attrs, len(appended))
                appended += chunk
        sections.setdefault(section, []).append(line)
    out = root + "  <%s>\n    <Piece %s>\n" % (kind, " ".join('%s="%s"' % kv for kv in piece_attrs))
    for section in ("PointData", "CellData", "Points", "Verts", "Lines", "Strips", "Polys", "Cells"):
        if section in sections:
            out += "      <%s>\n" % section
            for line in sections[section]:
                out += "        %s\n" % line
            out += "      </%s>\n" % section
    out += "    </Piece>\n  </%s>\n" % kind
    data = out.encode()
    if encoding.startswith("appended"):
        data += b'  <AppendedData encoding="%s">\n   _' % (b"base64" if encoding == "appended-base64" else b"raw")
        data += appended + b"\n  </AppendedData>\n"
    return data + b"</VTKFile>\n"


def octahedron_arrays(kind):
    pts = Array("Points", "Float64", [float(c) for p in POINTS for c in p], 3)
    conn = Array("connectivity", "Int64", [i for t in TRIANGLES for i in t])
    offs = Array("offsets", "Int64", [3 * (i + 1) for i in range(len(TRIANGLES))])
    level = Array("level", "UInt8", [0] * len(POINTS))
    arrays = [("PointData", level), ("Points", pts)]
    if kind == "PolyData":
        arrays += [("Polys", conn), ("Polys", offs)]
        attrs = [("NumberOfPoints", "6"), ("NumberOfVerts", "0"), ("NumberOfLines", "0"),
                 ("NumberOfStrips", "0"), ("NumberOfPolys", "8")]
    else:
        arrays += [("Cells", conn), ("Cells", offs), ("Cells", Array("types", "UInt8", [5] * len(TRIANGLES)))]
        attrs = [("NumberOfPoints", "6"), ("NumberOfCells", "8")]
    return arrays, attrs


def xml(kind, **options):
    arrays, attrs = octahedron_arrays(kind)
    return xml_file(kind, arrays, attrs, **options)


# ---------------------------------------------------------------------------------------------
# The cases

class Corpus:
    def __init__(self):
        self.files = {}  # name -> (bytes, commands, expected)

    def add(self, name, data, expected="", commands="info convert fit"):
        assert name not in self.files, name
        if isinstance(data, str):
            data = data.encode()
        assert data, name + ": use add_empty"
        self.files[name] = (data, commands, expected)

    def add_empty(self, name):
        self.files[name] = (b"", "info convert fit", "the file is empty")


def replace_once(data, old, new):
    if isinstance(data, str):
        assert old in data, old
        return data.replace(old, new, 1)
    assert old in data, old
    return data.replace(old, new, 1)


def appended_start(data):
    return data.index(b"_", data.index(b"<AppendedData")) + 1


def first_offset(data, name):
    """The appended offset of the DataArray named `name`."""
    at = data.index(b'Name="%s"' % name.encode())
    start = data.index(b'offset="', at) + len(b'offset="')
    return int(data[start:data.index(b'"', start)])


def patch_word(data, at, value, size=4):
    data = bytearray(data)
    data[at:at + size] = struct.pack("<I" if size == 4 else "<Q", value)
    return bytes(data)


def garbage(rng, n, text=False):
    if text:
        return "".join(rng.choice("abcdefghijklmnopqrstuvwxyz0123456789 .-+\n/#") for _ in range(n))
    return bytes(rng.randrange(256) for _ in range(n))


def make(c):
    rng = random.Random(20240610)
    bom = "\ufeff"

    # --- every format: empty, garbage, BOM then garbage, NUL bytes ---
    for ext in ("obj", "off", "ply", "stl", "vtk", "vtp", "vtu", "xyz", "pwn"):
        c.add_empty("empty.%s" % ext)
        g = garbage(rng, 300)
        if ext == "stl":  # 300 bytes whose count disagrees with their length
            g = g[:80] + struct.pack("<I", 1000) + g[84:]
        c.add("garbage.%s" % ext, g)
        c.add("bom-garbage.%s" % ext, (bom + garbage(rng, 200, text=True)).encode() + b"\x01\x02")
        c.add("nul.%s" % ext, b"\x00" * 64)

    # --- OBJ ---
    obj = obj_text()
    c.add("obj-letters.obj", "v 1 2 x\n" + obj, "'x' is not a number")
    c.add("obj-two-coordinates.obj", "v 1 2\n" + obj, "expected 3 vertex coordinates")
    c.add("obj-huge-number.obj", "v 1e999 0 0\n" + obj, "is not a number")
    c.add("obj-nan.obj", "v nan 0 0\n" + obj, "finite")
    c.add("obj-inf.obj", obj.replace("v 1 0 0", "v inf 0 0"), "finite")
    c.add("obj-index-zero.obj", obj + "f 0 1 2\n", "vertex index 0 is invalid")
    c.add("obj-index-beyond.obj", obj + "f 1 2 99\n", "vertex index 99 is out of range")
    c.add("obj-relative-beyond.obj", obj + "f -1 -2 -99\n", "points before the first vertex")
    c.add("obj-bad-reference.obj", obj + "f 1/2/3 a 3\n", "is not a vertex reference")
    c.add("obj-huge-index.obj", obj + "f 1 2 99999999999999999999\n", "is not a vertex reference")
    c.add("obj-polyline.obj", obj + "l 1 2\n", "are not surface polygons")
    c.add("obj-curve.obj", obj + "curv 0 1 1 2\n", "free-form geometry")
    c.add("obj-not-a-statement.obj", obj + "123 4 5\n", "is not an OBJ statement")
    c.add("obj-control-bytes.obj", obj + "\x01\x02\x03\n", "is not an OBJ statement")
    c.add("obj-nul-late.obj", obj + "\x00", "contains NUL bytes")
    c.add("obj-bom-bad-index.obj", bom + obj + "f 1 2 7\n", "line 15: vertex index 7 is out of range")
    c.add("obj-two-corner-face.obj", obj + "f 1 2\n", "face 8 has 2 vertices", "info convert")
    c.add("obj-point-element.obj", obj + "p 1\n", "not surface polygons", "info convert")
    # (info reports a file without faces as a point cloud: only convert must fail.)
    c.add("obj-no-faces.obj", obj.split("f ")[0], "", "convert")
    c.add("obj-comments-only.obj", "# nothing\n# at all\n", "")
    c.add("obj-non-manifold.obj", obj + "f 1 3 5\n", "", "info convert")
    # OpenSubdiv's sharpness tags (issue 42): vertices count from 0.
    c.add("obj-tag-counts.obj", obj + "t crease 2/1/0 0 2\n", "declares 3 arguments but has 2")
    c.add("obj-tag-count-text.obj", obj + "t crease two/1/0 0 2 1\n", "is not a tag's argument counts")
    c.add("obj-tag-negative.obj", obj + "t crease 2/1/0 0 2 -1\n", "is not a number of 0 or more")
    c.add("obj-tag-nan.obj", obj + "t corner 1/1/0 0 nan\n", "is not a number of 0 or more")
    c.add("obj-tag-odd-vertices.obj", obj + "t crease 3/1/0 0 2 4 1\n", "pairs of vertices")
    # (Checked where the faces become a mesh: a point cloud does not look at them.)
    c.add("obj-tag-not-an-edge.obj", obj + "t crease 2/1/0 0 1 10\n", "crease tag 0 (0, 1) is not an edge",
          "info convert")
    c.add("obj-tag-vertex-beyond.obj", obj + "t corner 1/1/0 6 10\n", "corner tag 0 names vertex 6", "info convert")
    c.add("obj-tag-method.obj", obj + "t creasemethod 0/0/1 sharp\n", "'normal' or 'chaikin'")
    c.add("obj-tag-hole.obj", obj + "t hole 1/0/0 0\n", "hole tags are not supported")
    c.add("obj-tag-boundary-none.obj", obj + "t interpolateboundary 1/0/0 0\n", "interpolateboundary 0 is not supported")
    for n in (9, 33, 57, 70):  # inside the vertex lines: a line cut short
        text = obj[:n]
        if text.endswith("\n") or text.split("\n")[-1].count(" ") < 3:
            c.add("obj-truncated-%d.obj" % n, text, "", "info convert")
    # A face continued over 80,000 lines: copying the tokens at each continuation took 80 s.
    c.add("obj-continued-lines.obj", "f 1 2 \\\n" + "3\\\n" * 80000 + "\n",
          "vertex index 1 is out of range")

    # --- OFF ---
    off = off_text()
    c.add("off-fewer-faces-declared.off", off_text(counts=(6, 5)), "data after the last of the 5 faces")
    c.add("off-more-faces-declared.off", off_text(counts=(6, 9)), "the file ends after 8 of 9 faces")
    c.add("off-more-vertices-declared.off", off_text(counts=(7, 8)), "the file ends after 7 of 8 faces")
    c.add("off-fewer-vertices-declared.off", off_text(counts=(5, 8)), "")
    c.add("off-negative-count.off", off_text(counts=(-6, 8)), "non-negative integers")
    c.add("off-huge-count.off", off_text(counts=(10 ** 15, 8)), "")
    c.add("off-overflowing-count.off", off_text(counts=(10 ** 25, 8)), "non-negative integers")
    c.add("off-no-counts.off", "OFF\n", "the file ends before the counts")
    c.add("off-bad-header.off", "XOFF\n6 8 0\n", "unsupported OFF variant")
    c.add("off-binary.off", "OFF BINARY\n6 8 0\n", "binary OFF files are not supported")
    c.add("off-letters.off", off.replace("0 0 -1", "0 0 z"), "'z' is not a number")
    c.add("off-nan.off", off.replace("0 0 -1", "0 0 nan"), "finite")
    c.add("off-negative-face-size.off", off.replace("3 0 2 4", "-3 0 2 4"), "is not a vertex count")
    c.add("off-short-face.off", off.replace("3 0 2 4", "4 0 2 4"), "expected 4 vertex indices, found 3")
    c.add("off-bad-index.off", off.replace("3 0 2 4", "3 0 2 x"), "is not a vertex index")
    c.add("off-index-beyond.off", off.replace("3 0 2 4", "3 0 2 6"), "references vertex 6", "info convert")
    c.add("off-negative-index.off", off.replace("3 0 2 4", "3 0 2 -1"), "", "info convert")
    c.add("off-bom-fewer-faces.off", bom + off_text(counts=(6, 7)), "line 16: data after the last of the 7 faces")
    for n in list(range(4, len(off) - 2, 7)):
        c.add("off-truncated-%03d.off" % n, off[:n], "")

    # --- PLY ---
    ply = ply_binary()
    body = len(ply_header("binary_little_endian", 6, 8))
    c.add("ply-huge-vertex-count-with-list.ply",
          ply_header("binary_little_endian", 10 ** 12, 0, "property list uchar int extra\n").encode() + b"\0" * 100,
          "the header announces 1000000000000 items of element 'vertex'")
    c.add("ply-huge-vertex-count.ply", ply_header("binary_little_endian", 10 ** 12, 8).encode() + ply[body:],
          "the file ends inside element 'vertex'")
    c.add("ply-huge-face-count.ply", ply_header("binary_little_endian", 6, 10 ** 12).encode() + ply[body:],
          "the header announces 1000000000000 items of element 'face'")
    c.add("ply-negative-count.ply", ply_header("binary_little_endian", -6, 8).encode() + ply[body:],
          "expected 'element <name> <count>'")
    c.add("ply-no-format.ply", ply.replace(b"format binary_little_endian 1.0\n", b""), "no 'format' line")
    c.add("ply-unknown-format.ply", ply.replace(b"binary_little_endian", b"binary_middle_endian"), "unknown PLY format")
    c.add("ply-no-end-header.ply", ply_header("ascii", 6, 8).replace("end_header\n", ""), "no 'end_header'")
    c.add("ply-no-vertex.ply", "ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n",
          "no 'vertex' element")
    c.add("ply-no-z.ply", ply_header("ascii", 0, 0).replace("property float z\n", ""), "no scalar property 'z'")
    c.add("ply-bad-type.ply", ply_header("ascii", 0, 0).replace("float z", "quaternion z"), "expected 'property")
    c.add("ply-list-of-floats-as-count.ply", ply_header("ascii", 0, 0).replace("list uchar int", "list float int"),
          "expected 'property")
    c.add("ply-property-first.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n", "a property before any element")
    c.add("ply-unexpected-keyword.ply", ply_header("ascii", 0, 0).replace("end_header", "bogus\nend_header"),
          "unexpected 'bogus'")
    c.add("ply-ascii-letters.ply", ply_ascii().replace("0 0 -1\n", "0 0 q\n"), "'q' is not a number")
    c.add("ply-ascii-list-too-long.ply", ply_ascii().replace("3 0 2 4\n", "9 0 2 4\n"), "expected 9 list values")
    c.add("ply-ascii-negative-list.ply", ply_ascii().replace("3 0 2 4\n", "-3 0 2 4\n"), "is not a list length")
    c.add("ply-ascii-truncated.ply", ply_ascii()[:-30], "expected 3 list values, found 0")
    c.add("ply-index-beyond.ply", ply_ascii().replace("3 0 2 4\n", "3 0 2 60\n"), "references vertex 60",
          "info convert")
    c.add("ply-ascii-nan.ply", ply_ascii().replace("0 0 -1\n", "nan 0 -1\n"), "finite")
    le = struct.pack("<B3i", 3, 0, 2, 4)
    c.add("ply-list-length-253.ply", ply.replace(le, struct.pack("<b3i", -3, 0, 2, 4)), "it is truncated")
    int_lists = ply_header("binary_little_endian", 6, 8).replace("list uchar int", "list int int").encode()
    int_lists += b"".join(struct.pack("<3f", *p) for p in POINTS)
    int_lists += struct.pack("<i3i", -3, 0, 2, 4) + b"".join(struct.pack("<4i", 3, *t) for t in TRIANGLES[1:])
    c.add("ply-negative-list-length.ply", int_lists, "item 0 has a negative list length")
    c.add("ply-list-beyond-file.ply", ply.replace(le, struct.pack("<B3i", 250, 0, 2, 4)), "it is truncated")
    for n in sorted(set([0, 3, 10, 60, body - 1, body, body + 1, body + 35, body + 72, body + 73, body + 100, len(ply) - 1])):
        if 0 < n < len(ply):
            c.add("ply-truncated-%03d.ply" % n, ply[:n], "")
    c.add("ply-big-endian-truncated.ply", ply_binary(True)[:-5], "it is truncated")

    # --- STL ---
    stl = stl_binary()
    c.add("stl-count-too-small.stl", stl_binary(count=7), "the binary STL header announces 7 triangles")
    c.add("stl-count-too-large.stl", stl_binary(count=9), "it is truncated")
    c.add("stl-count-huge.stl", stl_binary(count=0xFFFFFFFF), "announces 4294967295 triangles")
    c.add("stl-trailing-bytes.stl", stl + b"\0" * 50, "the count or the file is damaged")
    c.add("stl-short-header.stl", stl[:50], "needs an 84-byte header")
    for n in (84, 85, 100, 134, 133, 200, 333, len(stl) - 1):
        c.add("stl-truncated-%03d.stl" % n, stl[:n], "")
    ascii_stl = stl_ascii()
    for word, wrong in (("facet", "facett"), ("normal", "normel"), ("outer", "outter"), ("loop", "lop"),
                        ("vertex", "vertx"), ("endloop", "endlop"), ("endfacet", "endfaket"),
                        ("endsolid", "endsolyd")):
        c.add("stl-ascii-misspelled-%s.stl" % word, stl_ascii({word: wrong}), "'%s'" % wrong)
    c.add("stl-ascii-letters.stl", ascii_stl.replace("vertex 0 0 -1", "vertex 0 0 x"), "'x' is not a number")
    c.add("stl-ascii-two-coordinates.stl", ascii_stl.replace("vertex 0 0 -1", "vertex 0 0", 1), "")
    c.add("stl-ascii-four-corners.stl", ascii_stl.replace("    endloop", "      vertex 0 0 0\n    endloop", 1),
          "expected 'endloop', found 'vertex'")
    c.add("stl-ascii-nan.stl", ascii_stl.replace("vertex 0 0 -1", "vertex 0 0 nan"), "finite")
    c.add("stl-ascii-text-after-end.stl", ascii_stl + "more text\n", "after 'endsolid'")
    c.add("stl-ascii-nul.stl", ascii_stl[:200] + "\0" + ascii_stl[201:], "")
    c.add("stl-ascii-bom-misspelled.stl", bom + stl_ascii({"outer": "inner"}), "line 3: expected 'outer'")
    for n in (5, 20, 60, 150, 300, 600, len(ascii_stl) - 30, len(ascii_stl) - 15):
        c.add("stl-ascii-truncated-%03d.stl" % n, ascii_stl[:n], "")

    # --- legacy VTK ---
    vtk = legacy_ascii()
    c.add("vtk-not-vtk.vtk", "# vtk DataFile Versio 3.0\n" + vtk.split("\n", 1)[1], "not a legacy VTK file")
    c.add("vtk-no-mode.vtk", vtk.replace("ASCII", "EBCDIC"), "expected ASCII or BINARY")
    c.add("vtk-no-dataset.vtk", vtk.replace("DATASET", "DATASAT"), "expected 'DATASET'")
    c.add("vtk-structured.vtk", vtk.replace("POLYDATA", "STRUCTURED_POINTS"), "holds a STRUCTURED_POINTS data set")
    c.add("vtk-negative-points.vtk", vtk.replace("POINTS 6", "POINTS -6"), "is not a count")
    c.add("vtk-huge-points.vtk", vtk.replace("POINTS 6", "POINTS 6000000000000"), "the file is truncated")
    c.add("vtk-bad-type.vtk", vtk.replace("double", "quaternion"), "unsupported data type 'quaternion'")
    c.add("vtk-letters.vtk", vtk.replace("0 0 -1", "0 0 w"), "'w' is not a number")
    c.add("vtk-short-cell.vtk", vtk.replace("POLYGONS 8 32", "POLYGONS 8 31"), "")
    c.add("vtk-cell-overflow.vtk", vtk.replace("3 0 2 4\n", "300 0 2 4\n"), "does not fit in the 32 values")
    c.add("vtk-huge-cells.vtk", vtk.replace("POLYGONS 8 32", "POLYGONS 8 3200000000000"), "the file is truncated")
    c.add("vtk-lines.vtk", vtk + "LINES 1 3\n2 0 1\n", "is a line, not a surface polygon", "info convert")
    c.add("vtk-unexpected.vtk", vtk + "BANANAS 3\n", "unexpected 'bananas'")
    c.add("vtk-index-beyond.vtk", vtk.replace("3 0 2 4\n", "3 0 2 40\n"), "references vertex 40", "info convert")
    c.add("vtk-nan.vtk", vtk.replace("0 0 -1", "0 0 nan"), "finite")
    c.add("vtk-grid-missing-types.vtk",
          vtk.replace("POLYDATA", "UNSTRUCTURED_GRID").replace("POLYGONS", "CELLS"), "8 cells but 0 cell types",
          "info convert")
    binary_vtk = legacy_binary()
    c.add("vtk-binary-bad-offsets.vtk", binary_vtk.replace(struct.pack(">q", 3), struct.pack(">q", 30), 1),
          "the cell offsets are out of order")
    c.add("vtk-binary-huge-offsets-count.vtk", binary_vtk.replace(b"POLYGONS 9 24", b"POLYGONS 9000000000 24"),
          "the file is truncated")
    for n in (30, 70, 90, 100, 150, 200, 240, len(binary_vtk) - 10):
        c.add("vtk-binary-truncated-%03d.vtk" % n, binary_vtk[:n], "")
    for n in (60, 75, 120):
        c.add("vtk-ascii-truncated-%03d.vtk" % n, vtk[:n], "")

    # --- .xyz / .pwn ---
    xyz = "".join("%s\n" % " ".join(fmt(v) for v in p) for p in POINTS)
    pwn = "".join("%s %s\n" % (" ".join(fmt(v) for v in p), " ".join(fmt(v) for v in p)) for p in POINTS)
    for ext, text in (("xyz", xyz), ("pwn", pwn)):
        c.add("cloud-letters.%s" % ext, text.replace("0 0 -1", "0 0 k"), "'k' is not a number")
        c.add("cloud-nan.%s" % ext, text.replace("0 0 -1", "0 0 nan"), "is not a finite number")
        c.add("cloud-inf.%s" % ext, text.replace("0 0 -1", "0 0 -inf"), "is not a finite number")
        c.add("cloud-huge.%s" % ext, text.replace("0 0 -1", "0 0 1e400"), "is not a number")
        c.add("cloud-four-columns.%s" % ext, "1 2 3 4\n" + text, "expected 3 numbers (x y z) or 6")
        c.add("cloud-mixed-columns.%s" % ext, text + "1 2\n", "like the first point")
        c.add("cloud-comments-only.%s" % ext, "# no points\n\n", "no points")
        c.add("cloud-trailing-garbage.%s" % ext, text.replace("0 0 -1", "0 0 -1x"), "'-1x' is not a number")
        c.add("cloud-comma.%s" % ext, text.replace("0 0 -1", "0,0,-1"), "")
        c.add("cloud-bom-letters.%s" % ext, bom + "a b c\n" + text, ":1: 'a' is not a number")
    c.add("cloud-zero-normals.xyz", "1 2 3 0 0 0\n" * 3 + "x\n", "")

    # --- VTK XML (.vtp and .vtu) ---
    for kind, ext in (("PolyData", "vtp"), ("UnstructuredGrid", "vtu")):
        cells_attr = "NumberOfPolys" if kind == "PolyData" else "NumberOfCells"
        good = xml(kind)
        name = lambda what: "xml-%s.%s" % (what, ext)
        # Counts: negative, not numbers, too large, disagreeing with the data.
        c.add(name("points-minus-one"), replace_once(good, b'NumberOfPoints="6"', b'NumberOfPoints="-1"'),
              'NumberOfPoints="-1" is not a count')
        c.add(name("cells-minus-one"), replace_once(good, b'%s="8"' % cells_attr.encode(), b'%s="-1"' % cells_attr.encode()),
              '%s="-1" is not a count' % cells_attr)
        c.add(name("points-int-min"), replace_once(good, b'NumberOfPoints="6"', b'NumberOfPoints="-2147483648"'),
              "is not a count")
        c.add(name("points-letters"), replace_once(good, b'NumberOfPoints="6"', b'NumberOfPoints="six"'), "is not a count")
        c.add(name("points-exponent"), replace_once(good, b'NumberOfPoints="6"', b'NumberOfPoints="6e0"'), "is not a count")
        c.add(name("points-huge"), replace_once(good, b'NumberOfPoints="6"', b'NumberOfPoints="99999999999999999999"'),
              "is not a count")
        c.add(name("points-large"), replace_once(good, b'NumberOfPoints="6"', b'NumberOfPoints="4000000000"'),
              "the header announces 12000000000")
        c.add(name("points-one-more"), replace_once(good, b'NumberOfPoints="6"', b'NumberOfPoints="7"'),
              "the array holds 18 values, the header announces 21")
        c.add(name("cells-one-more"), replace_once(good, b'%s="8"' % cells_attr.encode(), b'%s="9"' % cells_attr.encode()),
              "the offsets array holds 8 values for 9 cells")
        # Array attributes.
        c.add(name("components-minus-one"), replace_once(good, b'NumberOfComponents="3"', b'NumberOfComponents="-1"'),
              'NumberOfComponents="-1" is not a positive count')
        c.add(name("components-zero"), replace_once(good, b'NumberOfComponents="3"', b'NumberOfComponents="0"'),
              "is not a positive count")
        c.add(name("components-two"), replace_once(good, b'NumberOfComponents="3"', b'NumberOfComponents="2"'),
              "has 2 components instead of 3")
        c.add(name("type-unknown"), replace_once(good, b'type="Float64"', b'type="Float128"'), 'unsupported type="Float128"')
        c.add(name("format-unknown"), replace_once(good, b'format="appended"', b'format="hex"'), 'format="hex"')
        c.add(name("format-missing"), replace_once(good, b' format="appended"', b""), 'format=""')
        c.add(name("offset-negative"), replace_once(good, b'offset="0"', b'offset="-4"'), 'offset="-4" is not an offset')
        c.add(name("offset-beyond"), replace_once(good, b'offset="0"', b'offset="99999"'), "beyond the end of the file")
        c.add(name("offset-missing"), replace_once(good, b' offset="0"', b""), 'offset="" is not an offset')
        c.add(name("offsets-not-integers"), replace_once(good, b'type="Int64" Name="offsets"', b'type="Float64" Name="offsets"'),
              "is not an integer type")
        # File attributes and structure.
        c.add(name("header-type-16"), replace_once(good, b'header_type="UInt32"', b'header_type="UInt16"'),
              'header_type="UInt16"')
        c.add(name("byte-order-middle"), replace_once(good, b'byte_order="LittleEndian"', b'byte_order="MiddleEndian"'),
              "byte_order")
        c.add(name("compressor-unknown"), replace_once(good, b"vtkZLibDataCompressor", b"vtkFooDataCompressor"),
              'unknown compressor="vtkFooDataCompressor"')
        other = "UnstructuredGrid" if kind == "PolyData" else "PolyData"
        c.add(name("wrong-type"), xml(other), "the file holds VTK %s data, not %s" % (other, kind))
        c.add(name("root-not-vtkfile"), good.replace(b"VTKFile", b"VTKFiles"), "the root element is <VTKFiles>")
        c.add(name("no-data-set"), good.replace(b"<%s>" % kind.encode(), b"<Other>", 1).replace(
            b"</%s>" % kind.encode(), b"</Other>", 1), "no <%s> element" % kind)
        c.add(name("no-points-array"), good.replace(b"<Points>", b"<Pointz>").replace(b"</Points>", b"</Pointz>"),
              "has 6 points but no Points array")
        c.add(name("no-offsets"), replace_once(good, b'Name="offsets"', b'Name="offsetz"'), "no offsets array")
        c.add(name("no-connectivity"), replace_once(good, b'Name="connectivity"', b'Name="connectivitz"'),
              "no connectivity array")
        # XML syntax.
        c.add(name("mismatched-end-tag"), replace_once(good, b"</Points>", b"</Pointz>"), "does not match")
        c.add(name("unquoted-attribute"), replace_once(good, b'NumberOfPoints="6"', b"NumberOfPoints=6"),
              "malformed attribute")
        c.add(name("repeated-attribute"), replace_once(good, b'NumberOfPoints="6"', b'NumberOfPoints="6" NumberOfPoints="6"'),
              "repeats the attribute")
        c.add(name("text-before-root"), b"hello " + good, "text outside the XML elements")
        c.add(name("doctype"), b'<!DOCTYPE VTKFile [<!ENTITY x "y">]>\n' + good, "unsupported XML markup")
        c.add(name("appended-in-comment"), b"<!-- <AppendedData -->\n" + good, "inside XML markup")
        c.add(name("deep-nesting"), replace_once(good, b"<Points>", b"<Points>" + b"<a>" * 100 + b"</a>" * 100),
              "nested too deeply")
        c.add(name("no-underscore"), replace_once(good, b"   _", b"   "), "does not start with '_'")
        c.add(name("appended-encoding-hex"), replace_once(good, b'encoding="raw"', b'encoding="hex"'), 'encoding="hex"')
        c.add(name("appended-missing"), good[:good.index(b"  <AppendedData")], "the file ends inside <VTKFile>")
        c.add(name("two-roots"), xml(kind, encoding="ascii", compressed=False) * 2, "more than one root element")
        # Compression headers: blocks, block sizes, compressed sizes.
        start = appended_start(good)
        lvl = start + first_offset(good, "level")
        pts = start + first_offset(good, "Points")
        off = start + first_offset(good, "offsets")
        c.add(name("zero-blocks-partial"), patch_word(good, lvl, 0), "announces 0 blocks with a partial last block")
        c.add(name("zero-blocks-points"), patch_word(good, pts, 0), "0 blocks with a partial last block")
        c.add(name("zero-blocks-no-partial"), patch_word(patch_word(good, pts, 0), pts + 8, 0),
              "the array holds 0 values, the header announces 18")
        c.add(name("many-blocks"), patch_word(good, pts, 0xFFFFFFFF), "announces 4294967295 blocks")
        c.add(name("block-size-zero"), patch_word(good, pts + 4, 0), "blocks of 0 bytes")
        c.add(name("last-block-larger"), patch_word(good, pts + 8, 40000), "with a last one of 40000")
        c.add(name("compressed-size-huge"), patch_word(good, pts + 12, 0x7FFFFFFF), "the compressed size of block 0")
        c.add(name("compressed-size-zero"), patch_word(good, pts + 12, 0), "the compressed size of block 0")
        c.add(name("expansion-lie"), patch_word(patch_word(good, pts + 4, 0x7FFFFFFF), pts + 8, 0),
              "more than the compressor can produce")
        c.add(name("uncompressed-size-mismatch"), patch_word(good, pts + 8, 136), "the array holds 17 values")
        damaged = bytearray(good)
        for k in range(off + 16, off + 24):
            damaged[k] ^= 0x5A
        c.add(name("offsets-block-damaged"), bytes(damaged), "compressed block 0 is damaged")
        c.add(name("truncated-in-header"), good[:pts + 6], "the size header of the binary data is damaged or truncated")
        c.add(name("truncated-in-blocks"), good[:pts + 20], "")
        # 64-bit headers.
        good64 = xml(kind, header64=True)
        start64 = appended_start(good64)
        pts64 = start64 + first_offset(good64, "Points")
        c.add(name("header64-zero-blocks"), patch_word(good64, pts64, 0, 8), "0 blocks with a partial last block")
        c.add(name("header64-many-blocks"), patch_word(good64, pts64, 2 ** 62, 8), "blocks, more than the file holds")
        c.add(name("header64-as-32"), good64.replace(b'header_type="UInt64"', b'header_type="UInt32"'), "")
        # Uncompressed appended raw.
        plain = xml(kind, compressed=False)
        pstart = appended_start(plain)
        ppts = pstart + first_offset(plain, "Points")
        c.add(name("raw-size-huge"), patch_word(plain, ppts, 0xFFFFFFF0), "more than the file holds")
        c.add(name("raw-size-short"), patch_word(plain, ppts, 8 * 17), "the array holds 17 values, the header announces 18")
        c.add(name("raw-size-odd"), patch_word(plain, ppts, 8 * 18 - 3), "not a whole number of Float64 values")
        poff = pstart + first_offset(plain, "offsets")
        c.add(name("raw-offsets-decreasing"), patch_word(patch_word(plain, poff + 4, 9, 4), poff + 8, 0, 4),
              "the cell offsets are corrupt at cell 1")
        c.add(name("raw-offset-huge"), patch_word(plain, poff + 4 + 7 * 8, 10 ** 9, 4), "the cell offsets are corrupt at cell 7")
        # ASCII arrays.
        text = xml(kind, encoding="ascii", compressed=False)
        c.add(name("ascii-too-few"), replace_once(text, b"0 0 -1\n", b"0 0\n"), "the array holds 17 values")
        c.add(name("ascii-too-many"), replace_once(text, b"0 0 -1\n", b"0 0 -1 7\n"), "the array holds 19 values")
        c.add(name("ascii-offsets-letters"), replace_once(text, b"3 6 9", b"3 x 9"), "'x' is not an integer")
        c.add(name("ascii-offsets-decreasing"), replace_once(text, b"3 6 9", b"3 2 9"), "corrupt at cell 1")
        c.add(name("ascii-offset-beyond"), replace_once(text, b"21 24", b"21 2400000000000"), "corrupt at cell 7")
        c.add(name("ascii-offset-negative"), replace_once(text, b"3 6 9", b"-3 6 9"), "corrupt at cell 0")
        c.add(name("ascii-unclosed"), text[:text.index(b"</Points>")], "the file ends inside")
        c.add(name("ascii-index-beyond"), replace_once(text, b"0 2 4", b"0 2 44"), "references vertex 44", "info convert")
        c.add(name("ascii-nan"), replace_once(text, b"0 0 -1\n", b"0 0 nan\n"), "finite")
        # Inline base64.
        inline = xml(kind, encoding="binary", compressed=True)
        at = inline.index(b'format="binary">') + len(b'format="binary">\n          ')
        c.add(name("base64-bad-characters"), inline[:at] + b"!!!!" + inline[at + 4:], "damaged or truncated")
        c.add(name("base64-empty"), replace_once(xml(kind, encoding="binary", compressed=False),
                                                 b'format="binary">', b'format="binary"/><x>'), "")
        b64 = xml(kind, encoding="appended-base64", compressed=True)
        b64start = appended_start(b64)
        c.add(name("appended-base64-truncated"), b64[:b64start + 30], "")
        c.add(name("appended-base64-bad"), b64[:b64start] + b"@@@@" + b64[b64start + 4:], "damaged or truncated")
        # Cells that are no surface, and polyhedra.
        if kind == "UnstructuredGrid":
            c.add(name("polyhedron-faces"), replace_once(text, b"</Cells>",
                  b'  <DataArray type="Int64" Name="faces" format="ascii">0</DataArray>\n      </Cells>'),
                  "polyhedron cells")
            c.add(name("no-types"), replace_once(good, b'Name="types"', b'Name="typez"'), "no types array")
            c.add(name("tetra"), replace_once(text, b"5 5 5 5 5 5 5 5", b"10 5 5 5 5 5 5 5"), "is a tetrahedron",
                  "info convert")
        # Found by fuzzing (fuzz/README.md): two cell arrays of one name made VTK read through a
        # null pointer.
        twice, twice_attrs = octahedron_arrays(kind)
        twice += [("CellData", Array("level", "UInt8", [0] * 8))] * 2
        c.add(name("cell-arrays-same-name"), xml_file(kind, twice, twice_attrs),
              "piece 0 CellData has two arrays named 'level'")
        # Found by fuzzing once the tool's files carried field data (the RGB state): VTK makes an
        # array of every element inside FieldData and reads through a null pointer for any other.
        tag = b"<" + kind.encode() + b">"
        c.add(name("field-data-not-an-array"),
              replace_once(text, tag, tag + b'\n    <FieldData><Datar Name="d7"/></FieldData>'),
              "the field data holds a <Datar> element, where only DataArray elements belong")
        c.add(name("points-not-an-array"), replace_once(text, b"<Points>", b"<Points><Coordinates/>"),
              "piece 0 Points holds a <Coordinates> element, where only DataArray elements belong")
        c.add(name("point-data-not-an-array"), replace_once(text, b"<PointData>", b"<PointData><D/>"),
              "piece 0 PointData holds a <D> element, where only DataArray elements belong")
        # ASCII values that VTK misread (it stops at the first character that does not fit,
        # content when it has enough values) or fails on.
        c.add(name("ascii-comma"), replace_once(text, b"0 0 -1\n", b"0 0 -1,5\n"), "'-1,5' is not a Float64 number")
        c.add(name("ascii-hex"), replace_once(text, b"0 0 -1\n", b"0 0 0x10\n"), "'0x10' is not a Float64 number")
        c.add(name("ascii-infinity"), replace_once(text, b"0 0 -1\n", b"0 0 infinity\n"),
              "'infinity' is not a Float64 number")
        c.add(name("ascii-fraction-index"), replace_once(text, b"0 2 4", b"0 2 4.0"),
              "'4.0' is not an integer in the range of Int64")
        float32 = text.replace(b'type="Float64" Name="Points"', b'type="Float32" Name="Points"')
        c.add(name("ascii-float32-overflow"), replace_once(float32, b"0 0 -1\n", b"0 0 -1e39\n"),
              "'-1e39' is not a Float32 number")
        if kind == "UnstructuredGrid":
            # 261 was read as 5 (a triangle); the types that VTK failed to read (fuzzing) leaked.
            c.add(name("ascii-type-261"), replace_once(text, b"5 5 5 5 5 5 5 5", b"5 5 5 5 5 5 5 261"),
                  "'261' is not an integer in the range of UInt8")
            c.add(name("ascii-types-not-numbers"), replace_once(text, b"5 5 5 5 5 5 5 5", b"5 5 5 5 5 5 /> 5"),
                  "'/>' is not an integer in the range of UInt8")
            types = start + first_offset(good, "types")
            damaged = bytearray(good)
            for k in range(types + 16, types + 24):
                damaged[k] ^= 0x5A
            c.add(name("types-block-damaged"), bytes(damaged), "Cells types: compressed block 0 is damaged")
        else:
            # One tag with 150,000 attributes: comparing each with all before it took 40 s.
            digits = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
            names = []
            for i in range(150000):
                n = "a"
                while True:
                    n += digits[i % 62]
                    i //= 62
                    if i == 0:
                        break
                names.append(n)
            c.add(name("many-attributes"), '<VTKFile type="PolyData" %s aa="">\n</VTKFile>\n'
                  % " ".join('%s=""' % n for n in names), "<VTKFile> repeats the attribute aa")
        for n in (10, 100, 400, 700, start - 20, start + 3, len(good) - 60):
            c.add(name("truncated-%04d" % n), good[:n], "")


def write(directory):
    c = Corpus()
    make(c)
    files = os.path.join(directory, "files")
    if os.path.isdir(files):
        shutil.rmtree(files)
    os.makedirs(files)
    manifest = []
    for name in sorted(c.files):
        data, commands, expected = c.files[name]
        with open(os.path.join(files, name), "wb") as f:
            f.write(data)
        manifest.append("%s\t%s\t%s\n" % (name, commands, expected))
    with open(os.path.join(files, "MANIFEST.tsv"), "w") as f:
        f.write("".join(manifest))
    return c


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--check":
        with tempfile.TemporaryDirectory() as tmp:
            write(tmp)
            made = sorted(os.listdir(os.path.join(tmp, "files")))
            have = sorted(os.listdir(os.path.join(HERE, "files")))
            if made != have:
                print("tests/corpus/files: the file list differs from what make_corpus.py makes")
                return 1
            for name in made:
                with open(os.path.join(tmp, "files", name), "rb") as a, open(os.path.join(HERE, "files", name), "rb") as b:
                    if a.read() != b.read():
                        print("tests/corpus/files/%s differs from what make_corpus.py makes" % name)
                        return 1
        print("tests/corpus/files is what make_corpus.py makes")
        return 0
    c = write(HERE)
    counts = {}
    for name in c.files:
        ext = name.rsplit(".", 1)[1]
        counts[ext] = counts.get(ext, 0) + 1
    print("%d files: %s" % (len(c.files), ", ".join("%s %d" % kv for kv in sorted(counts.items()))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
