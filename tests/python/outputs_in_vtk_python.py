#!/usr/bin/python3
"""The tool's VTK XML outputs as a ParaView user's script sees them: read through VTK's own
Python (Debian's python3-vtk9, the same readers ParaView uses), every compression, a refined
mesh with all three colours, and an adaptive run's .pvd series.

    outputs_in_vtk_python.py RGBMESH DATA_DIR WORK_DIR

Exit 0 when every check holds; the first failed check is printed and the exit code is 1;
77 (skipped) where VTK's Python is not installed.
"""

import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ElementTree

try:
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLUnstructuredGridReader
except ImportError as error:  # ctest reports exit code 77 as skipped
    print("skipped: VTK's Python is not installed (Debian: apt-get install python3-vtk9): " + str(error))
    sys.exit(77)


def check(condition, what):
    if not condition:
        print("FAILED: " + what)
        sys.exit(1)


def run(*args):
    result = subprocess.run([str(a) for a in args], capture_output=True, text=True)
    check(result.returncode == 0, " ".join(map(str, args)) + " exited with " + str(result.returncode) + ": " + result.stderr)
    return result.stdout


def read(path):
    reader = vtkXMLUnstructuredGridReader() if path.endswith(".vtu") else vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    data = reader.GetOutput()
    check(data is not None and data.GetNumberOfPoints() > 0, path + ": VTK read no points")
    return data


def arrays(data):
    """Every array of the data set as numpy, keyed by where it is and its name."""
    out = {"points": vtk_to_numpy(data.GetPoints().GetData())}
    for where, fields in (("point", data.GetPointData()), ("cell", data.GetCellData()), ("field", data.GetFieldData())):
        for i in range(fields.GetNumberOfArrays()):
            array = fields.GetArray(i)
            out[where + " " + array.GetName()] = vtk_to_numpy(array)
    cells = data.GetPolys() if data.IsA("vtkPolyData") else data.GetCells()
    out["connectivity"] = vtk_to_numpy(cells.GetConnectivityArray())
    out["offsets"] = vtk_to_numpy(cells.GetOffsetsArray())
    return out


def main():
    tool, data_dir, work = sys.argv[1], sys.argv[2], sys.argv[3]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    bunny = os.path.join(data_dir, "bunny.obj")

    # A mesh of several levels and all three colours, large enough for arrays of many blocks.
    files = {}
    for compression in ("lz4", "zlib", "none"):
        for ext in (".vtp", ".vtu"):
            path = os.path.join(work, "m-" + compression + ext)
            run(tool, "--compression", compression, "refine", bunny, path, "--uniform", "1", "--ball", "0,0,1,0.3,3")
            files[compression + ext] = path
    info = json.loads(run(tool, "info", "--json", files["lz4.vtp"]))

    reference = arrays(read(files["lz4.vtp"]))
    n, m = info["vertices"], info["triangles"]
    check(reference["points"].shape == (n, 3), "points: %s for %d vertices" % (reference["points"].shape, n))
    check(reference["connectivity"].shape == (3 * m,), "connectivity of %d triangles" % m)
    check(3 * m * 4 > 4 * 32768, "the connectivity spans several compressed blocks")
    check(np.array_equal(reference["offsets"], np.arange(0, 3 * m + 1, 3)), "offsets 0, 3, 6, ...")
    check(reference["connectivity"].min() == 0 and reference["connectivity"].max() == n - 1, "point indices in range")
    check(reference["point level"].dtype == np.uint8 and reference["point level"].max() == info["max_level"],
          "point levels up to the mesh's maximum level")
    levels = {int(k): v for k, v in info["vertices_per_level"].items()}
    check(all(np.count_nonzero(reference["point level"] == k) == v for k, v in levels.items()),
          "point levels as info counts them")
    colors = np.bincount(reference["cell color"], minlength=3)
    expected = [sum(t[c] for t in info["triangles_per_level"].values()) for c in ("green", "red", "blue")]
    check(list(colors) == expected, "colours %s, info says %s" % (list(colors), expected))
    check(np.array_equal(reference["points"], reference["point control_point"]), "the points are the control points")
    gap = np.linalg.norm(reference["point limit"] - reference["points"], axis=1).max()
    check(0 < gap < 0.02 * info["bbox_diagonal"], "limit positions near the control points (%.3g)" % gap)
    check(reference["field rgb_state_version"].tolist() == [1], "RGB state version 1")
    check(np.count_nonzero(reference["point rgb_base_vertex"] >= 0) == levels[0], "one base index per base vertex")

    # Every compression and both formats hold the same values, bit for bit.
    for key, path in files.items():
        other = arrays(read(path))
        check(sorted(other) == sorted(reference), key + ": arrays " + str(sorted(other)))
        for name, values in reference.items():
            check(np.array_equal(other[name].view(np.uint8), values.view(np.uint8)) or
                  (name in ("connectivity", "offsets") and np.array_equal(other[name], values)),
                  key + ": " + name + " differs")

    # An adaptive run: the .pvd lists every cycle; each has the solution and indicator arrays.
    out = os.path.join(work, "adapt")
    run(tool, "adapt", "--cycles", "4", "--out", out)
    series = ElementTree.parse(os.path.join(out, "solution.pvd")).getroot().findall("./Collection/DataSet")
    check(len(series) == 4, "%d data sets in the .pvd" % len(series))
    previous = 0
    for entry in series:
        data = read(os.path.join(out, entry.get("file")))
        values = arrays(data)
        for name in ("point solution", "point exact_solution", "cell error_indicator", "cell level", "point rgb_parents"):
            check(name in values, entry.get("file") + ": no " + name)
        check(values["point solution"].shape == (data.GetNumberOfPoints(),), entry.get("file") + ": solution size")
        check(np.all(np.isfinite(values["point solution"])), entry.get("file") + ": finite solution")
        check(data.GetNumberOfCells() > previous, entry.get("file") + ": the mesh grows cycle by cycle")
        previous = data.GetNumberOfCells()
    # Quadratic elements: the .pvd lists the P2 files, six-node quadratic triangles with the
    # solution at every node (vertices and edges: the report's unknowns).
    out = os.path.join(work, "adapt-p2")
    run(tool, "adapt", "--order", "2", "--cycles", "3", "--out", out)
    report = json.load(open(os.path.join(out, "report.json")))
    series = ElementTree.parse(os.path.join(out, "solution.pvd")).getroot().findall("./Collection/DataSet")
    check([e.get("file") for e in series] == ["cycle_%03d_p2.vtu" % c for c in range(3)], "the .pvd lists the P2 files")
    errors = []
    for entry, cycle in zip(series, report["cycles"]):
        data = read(os.path.join(out, entry.get("file")))
        check(data.GetNumberOfPoints() == cycle["dofs"], entry.get("file") + ": one point per unknown")
        check(data.GetNumberOfCells() == cycle["triangles"], entry.get("file") + ": one cell per triangle")
        check(all(data.GetCellType(k) == 22 for k in range(data.GetNumberOfCells())), "VTK_QUADRATIC_TRIANGLE cells")
        values = arrays(data)
        check(np.all(np.isfinite(values["point solution"])), entry.get("file") + ": finite solution")
        check(np.allclose(values["point exact_solution"] - values["point solution"], values["point error"]),
              entry.get("file") + ": error = exact - solution at every node")
        errors.append(np.abs(values["point error"]).max())
    check(errors[-1] < errors[0], "the nodal error falls cycle by cycle: %s" % errors)
    print("ok: %d files read through VTK's Python" % (len(files) + 2 * len(series)))


if __name__ == "__main__":
    main()
