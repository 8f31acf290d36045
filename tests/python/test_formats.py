"""3MF input (issue 43): files of our own written with the standard library's zipfile, and the
3MF platforms that Cura ships, read by the tool and compared with an independent reading of
their XML (zipfile and ElementTree, transforms applied as the 3MF core specification says)."""

import math
import os
import subprocess
import zipfile
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from helpers import public, tool

CORE = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"
CONTENT_TYPES = (
    '<?xml version="1.0" encoding="UTF-8"?>\n'
    '<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
    '<Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
    '<Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>')
RELS = (
    '<?xml version="1.0" encoding="UTF-8"?>\n'
    '<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
    '<Relationship Target="/3D/3dmodel.model" Id="rel0" '
    'Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>')


def octahedron():
    points = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    triangles = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    return points, triangles


def mesh_xml(points, triangles):
    vertices = "".join('<vertex x="%r" y="%r" z="%r"/>' % tuple(map(float, p)) for p in points)
    faces = "".join('<triangle v1="%d" v2="%d" v3="%d"/>' % t for t in triangles)
    return "<mesh><vertices>%s</vertices><triangles>%s</triangles></mesh>" % (vertices, faces)


def write_3mf(path, resources, items, unit="millimeter"):
    """resources: XML of the objects; items: (objectid, transform or None)."""
    build = "".join('<item objectid="%d"%s/>' % (i, ' transform="%s"' % t if t else "") for i, t in items)
    model = ('<?xml version="1.0" encoding="UTF-8"?>\n<model unit="%s" xml:lang="en-US" xmlns="%s">'
             "<resources>%s</resources><build>%s</build></model>" % (unit, CORE, resources, build))
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("[Content_Types].xml", CONTENT_TYPES)
        z.writestr("_rels/.rels", RELS)
        z.writestr("3D/3dmodel.model", model)
    return path


def transform_text(m):
    """A 3 x 4 matrix (x' = A x + t) as 3MF writes it: column-major rows of the 4 x 3 matrix."""
    a = np.asarray(m, float)
    return " ".join("%r" % v for v in [a[0, 0], a[1, 0], a[2, 0], a[0, 1], a[1, 1], a[2, 1],
                                       a[0, 2], a[1, 2], a[2, 2], a[0, 3], a[1, 3], a[2, 3]])


def rotation(axis, angle, translation):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    r = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k
    return np.hstack([r, np.asarray(translation, float)[:, None]])


# ---- the independent reading ------------------------------------------------------------

def parse_transform(text):
    if not text:
        return np.hstack([np.eye(3), np.zeros((3, 1))])
    v = [float(x) for x in text.split()]
    m = np.array(v).reshape(4, 3)  # rows: images of x, y, z, then the translation
    return np.hstack([m[:3].T, m[3][:, None]])


def compose(outer, inner):
    return np.hstack([outer[:, :3] @ inner[:, :3], (outer[:, :3] @ inner[:, 3] + outer[:, 3])[:, None]])


def reference_triangles(path):
    """Every build item's triangles as 3 x 3 arrays of transformed corners."""
    with zipfile.ZipFile(path) as z:
        name = [n for n in z.namelist() if n.endswith(".model")][0]
        root = ET.fromstring(z.read(name))
    ns = "{%s}" % CORE
    objects = {o.get("id"): o for o in root.iter(ns + "object")}
    out = []

    def add(obj, m):
        mesh = obj.find(ns + "mesh")
        if mesh is not None:
            if obj.get("type", "model") not in ("model", "solidsupport"):
                return
            pts = np.array([[float(v.get(c)) for c in "xyz"] for v in mesh.iter(ns + "vertex")])
            pts = pts @ m[:, :3].T + m[:, 3]
            # A mirroring transform turns the triangles inside out: their order is reversed.
            order = ("v1", "v3", "v2") if np.linalg.det(m[:, :3]) < 0 else ("v1", "v2", "v3")
            for t in mesh.iter(ns + "triangle"):
                out.append(pts[[int(t.get(k)) for k in order]])
        for c in obj.iter(ns + "component"):
            add(objects[c.get("objectid")], compose(m, parse_transform(c.get("transform"))))

    for item in root.iter(ns + "item"):
        add(objects[item.get("objectid")], parse_transform(item.get("transform")))
    return np.array(out)


def read_obj(path):
    points, triangles = [], []
    with open(path) as f:
        for line in f:
            w = line.split()
            if w and w[0] == "v":
                points.append([float(x) for x in w[1:4]])
            elif w and w[0] == "f":
                triangles.append([int(x.split("/")[0]) - 1 for x in w[1:4]])
    points = np.array(points)
    return points[np.array(triangles)]


def summary(triangles):
    """What must agree: the count, the area, the area-weighted centre, the bounding box and the
    enclosed volume (which changes sign when the triangles turn inside out)."""
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    areas = np.linalg.norm(np.cross(b - a, c - a), axis=1) / 2
    centre = ((a + b + c) / 3 * areas[:, None]).sum(axis=0) / areas.sum()
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6
    flat = triangles.reshape(-1, 3)
    return len(triangles), areas.sum(), centre, flat.min(axis=0), flat.max(axis=0), volume


def expect_same(got, want, scale):
    assert got[0] == want[0]
    assert got[1] == pytest.approx(want[1], rel=1e-5)
    for k in (2, 3, 4):
        np.testing.assert_allclose(got[k], want[k], atol=1e-5 * scale)
    assert got[5] == pytest.approx(want[5], rel=1e-5, abs=1e-5 * scale ** 3)


def converted(source, tmp_path, *flags):
    out = str(tmp_path / "out.obj")
    r = tool("convert", *flags, source, out)
    return read_obj(out), r.stderr


# ---- the tests ------------------------------------------------------------------------------

def test_objects_components_and_transforms_of_our_own(tmp_path):
    points, triangles = octahedron()
    turn = rotation([1, 2, 3], 0.7, [10, -4, 2])
    mirror = np.array([[-2, 0, 0, 5], [0, 1, 0, 0], [0, 0, 1, 0]], float)  # mirrors x and stretches
    inner = rotation([0, 0, 1], 0.3, [0, 0, 7])
    resources = ('<object id="1" type="model">%s</object>' % mesh_xml(points, triangles) +
                 '<object id="2" type="model"><components><component objectid="1" transform="%s"/>'
                 '<component objectid="1"/></components></object>' % transform_text(inner))
    cases = {
        "one object": [(1, None)],
        "two items, one turned": [(1, None), (1, transform_text(turn))],
        "components inside a turned item": [(2, transform_text(turn))],
        "a mirroring transform": [(1, transform_text(mirror))],
    }
    for name, items in cases.items():
        f = write_3mf(str(tmp_path / "part.3mf"), resources, items)
        got, notes = converted(f, tmp_path)
        want = reference_triangles(f)
        expect_same(summary(got), summary(want), 10)
        # Outwards: the enclosed volume is positive, also where a transform mirrors.
        assert summary(got)[5] > 0, name
        assert "3MF: " in notes and "millimetres" in notes, notes
    assert "mirrored by their transforms" in notes


def test_units_supports_and_files_that_are_not_3mf(tmp_path):
    points, triangles = octahedron()
    mesh = mesh_xml(points, triangles)
    f = write_3mf(str(tmp_path / "inch.3mf"), '<object id="1" type="model">%s</object>' % mesh, [(1, None)], "inch")
    assert "coordinates in inches as the file has them" in tool("info", f).stderr
    # A support object is not the part: left out, and with nothing else the file has no mesh.
    resources = '<object id="1" type="model">%s</object><object id="2" type="support">%s</object>' % (mesh, mesh)
    f = write_3mf(str(tmp_path / "support.3mf"), resources, [(1, None), (2, None)])
    got, notes = converted(f, tmp_path)
    assert len(got) == 8 and "1 support or other objects left out" in notes
    refused = []
    refused.append(write_3mf(str(tmp_path / "only_support.3mf"), resources, [(2, None)]))
    refused.append(write_3mf(str(tmp_path / "empty_build.3mf"), resources, []))
    whole = open(refused[0], "rb").read()
    with open(tmp_path / "truncated.3mf", "wb") as out:
        out.write(whole[: len(whole) // 2])
    refused.append(str(tmp_path / "truncated.3mf"))
    with open(tmp_path / "text.3mf", "w") as out:
        out.write("solid not a zip\n")
    refused.append(str(tmp_path / "text.3mf"))
    with zipfile.ZipFile(tmp_path / "no_model.3mf", "w") as z:
        z.writestr("[Content_Types].xml", CONTENT_TYPES)
    refused.append(str(tmp_path / "no_model.3mf"))
    # Cura's cr-x.3mf has triangles that repeat a vertex, which 3MF forbids: lib3mf refuses it.
    refused.append(public("cura/cr-x.3mf"))
    for f in refused:
        r = subprocess.run([os.environ["RGBMESH_CLI"], "info", f], capture_output=True, text=True)
        assert r.returncode == 2, (f, r.stderr)
        assert r.stderr.count("\n") == 1 and r.stderr.startswith("rgbmesh: error: " + f), r.stderr
    assert "Invalid Model Coordinate Indices (lib3mf refuses it; export the part as STL, OBJ or PLY instead)" in r.stderr


def test_every_subcommand_reads_3mf(tmp_path):
    points, triangles = octahedron()
    f = write_3mf(str(tmp_path / "octahedron.3mf"), '<object id="1" type="model">%s</object>' % mesh_xml(points, triangles),
                  [(1, None)])
    tool("info", f)
    tool("convert", f, str(tmp_path / "o.vtp"))
    tool("refine", f, str(tmp_path / "r.vtp"), "--uniform", "2")
    tool("adapt", "--mesh", f, "--cycles", "2", "--out", str(tmp_path / "adapt"))
    tool("fit", "--target", f, "--out", str(tmp_path / "fit"))


@pytest.mark.parametrize("name", ["rigid3d_mucit2_platform.3mf", "ideagen3D_sapphire_plus.3mf", "weedo_x40.3mf",
                                  "blv_mgn_cube_300_platform.3mf", "101hero-platform.3mf"])
def test_cura_platforms_as_their_xml_says(tmp_path, name):
    # Cura's printer platforms: components, item transforms, up to 167,000 vertices.
    f = public("cura/" + name)
    got, _ = converted(f, tmp_path)
    want = reference_triangles(f)
    scale = np.abs(want).max()
    expect_same(summary(got), summary(want), scale)
