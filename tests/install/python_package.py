"""The Python package rgbmesh where a user installs it (tests/install/CMakeLists.txt):

  python_package.py installed SITE_DIR FORBIDDEN_DIR
      the package as `cmake --install` put it into SITE_DIR (Install.Tree's prefix), imported
      with PYTHONPATH=SITE_DIR and nothing else of the environment
  python_package.py pip SOURCE_DIR WORK_DIR VERSION
      docs/install.md's route: a new virtual environment with the system's site packages, then
      `pip install --no-build-isolation --no-index SOURCE_DIR` (setup.py builds with CMake from
      scratch into WORK_DIR/build, which is deleted before the import), imported in a clean
      environment; exit code 77 (skipped) where python3-venv is not installed
  python_package.py check ROOT FORBIDDEN_DIR [VERSION]
      run by the two above inside the interpreter under test

Run with the interpreter the package is built for (Debian's /usr/bin/python3).
"""

import itertools
import os
import shutil
import subprocess
import sys
import time

SKIPPED = 77


def fail(message):
    print("FAILED: " + message, flush=True)
    sys.exit(1)


def is_under(path, directory):
    path, directory = os.path.realpath(path), os.path.realpath(directory)
    return path == directory or path.startswith(directory + os.sep)


def icosahedron():
    """The 12 vertices (0, ±1, ±φ) and their cyclic permutations; the triangles are the triples of
    mutually adjacent vertices (edge length 2), each turned to face outwards."""
    phi = (1 + 5 ** 0.5) / 2
    points = []
    for a, b in itertools.product((-1.0, 1.0), (-phi, phi)):
        points += [(0.0, a, b), (a, b, 0.0), (b, 0.0, a)]

    def sub(p, q):
        return [p[i] - q[i] for i in range(3)]

    def adjacent(i, j):
        return abs(sum(c * c for c in sub(points[i], points[j])) - 4.0) < 1e-9

    triangles = []
    for i, j, k in itertools.combinations(range(12), 3):
        if adjacent(i, j) and adjacent(j, k) and adjacent(i, k):
            u, v = sub(points[j], points[i]), sub(points[k], points[i])
            normal = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
            outward = sum(normal[c] * (points[i][c] + points[j][c] + points[k][c]) for c in range(3)) > 0
            triangles.append((i, j, k) if outward else (i, k, j))
    return points, triangles


def check(root, forbidden, version=None):
    """Inside the interpreter under test: the package is the one under ROOT, loads nothing from
    FORBIDDEN_DIR (the build tree) outside ROOT, and refines."""
    import numpy as np
    import rgbmesh

    for module in (rgbmesh, rgbmesh._rgbmesh):
        if not is_under(module.__file__, root):
            fail(f"{module.__name__} imported from {module.__file__}, not from under {root}")
    # Every file mapped into this process (the extension and the shared libraries it loaded).
    with open("/proc/self/maps", encoding="utf-8") as maps:
        for line in maps:
            fields = line.split(maxsplit=5)
            path = fields[5].strip() if len(fields) == 6 else ""
            if path.startswith(os.sep) and is_under(path, forbidden) and not is_under(path, root):
                fail(f"the installed package loaded {path} from the build tree {forbidden}")
    if version is not None:
        from importlib import metadata

        installed = metadata.version("rgbmesh")
        if installed != version:
            fail(f"installed rgbmesh {installed}, the CMake project is {version}")

    points, triangles = icosahedron()
    mesh = rgbmesh.Mesh.from_arrays(np.array(points, dtype=np.float64), np.array(triangles, dtype=np.int64))
    mesh.refine_uniform(2)
    problems = mesh.validate()
    if (mesh.num_vertices, mesh.num_triangles) != (162, 320) or problems != "":
        fail(f"icosahedron refined twice: {mesh.num_vertices} vertices, {mesh.num_triangles} triangles, "
             f"validate(): {problems!r} (expected 162, 320, '')")
    print(f"rgbmesh from {os.path.dirname(rgbmesh.__file__)}: 162 vertices, 320 triangles, valid", flush=True)


def clean_environment(**extra):
    # What a user's shell would surely have; nothing of the test's own environment (PYTHONPATH,
    # a virtual environment, LD_LIBRARY_PATH) that could make the import work by accident.
    environment = {"PATH": "/usr/local/bin:/usr/bin:/bin", "LANG": "C.UTF-8"}
    if "HOME" in os.environ:
        environment["HOME"] = os.environ["HOME"]
    environment.update(extra)
    return environment


def run_check(python, flags, root, forbidden, environment, cwd, version=None):
    command = [python] + flags + [os.path.abspath(__file__), "check", root, forbidden]
    if version is not None:
        command.append(version)
    result = subprocess.run(command, env=environment, cwd=cwd)
    if result.returncode != 0:
        fail(f"the import check failed ({result.returncode}): {' '.join(command)}")


def installed(site, forbidden):
    if not os.path.isfile(os.path.join(site, "rgbmesh", "__init__.py")):
        fail(f"cmake --install put no package rgbmesh into {site}")
    extensions = [n for n in os.listdir(os.path.join(site, "rgbmesh")) if n.startswith("_rgbmesh.")]
    if len(extensions) != 1:
        fail(f"expected one extension _rgbmesh.* in {site}/rgbmesh, found {extensions}")
    # -s: no user site packages; the working directory is outside the build tree and the sources.
    run_check(sys.executable, ["-s"], site, forbidden, clean_environment(PYTHONPATH=site), cwd=site)


def pip(source, work, version):
    for module in ("venv", "ensurepip"):
        probe = subprocess.run([sys.executable, "-c", f"import {module}"], capture_output=True)
        if probe.returncode != 0:
            print(f"skipped: {sys.executable} has no {module} (Debian: apt-get install python3-venv python3-pip)")
            sys.exit(SKIPPED)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    env_dir = os.path.join(work, "env")
    build = os.path.join(work, "build")
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", env_dir], check=True)
    env_pip, env_python = os.path.join(env_dir, "bin", "pip"), os.path.join(env_dir, "bin", "python")
    if not os.path.isfile(env_pip):
        fail(f"python3 -m venv made no {env_pip}")

    # The user's command, with the build directory moved into the test's folder (from scratch:
    # the folder was just emptied) and the output kept in a log.
    command = [env_pip, "install", "--no-build-isolation", "--no-index", "--disable-pip-version-check", "-v", source]
    environment = {k: v for k, v in os.environ.items()
                   if not k.startswith(("PYTHON", "PIP_", "VIRTUAL_ENV", "RGBMESH_"))}
    environment["RGBMESH_BUILD_DIR"] = build
    log = os.path.join(work, "pip.log")
    print("running: " + " ".join(command) + f" (RGBMESH_BUILD_DIR={build}, log {log})", flush=True)
    start = time.monotonic()
    with open(log, "w", encoding="utf-8") as out:
        result = subprocess.run(command, env=environment, cwd=work, stdout=out, stderr=subprocess.STDOUT)
    seconds = time.monotonic() - start
    if result.returncode != 0:
        with open(log, encoding="utf-8", errors="replace") as f:
            print("".join(f.readlines()[-60:]))
        fail(f"pip install failed ({result.returncode}) after {seconds:.0f} s; whole log: {log}")
    print(f"pip install: {seconds:.0f} s (configure and build from scratch)", flush=True)
    if not os.path.isfile(os.path.join(build, "CMakeCache.txt")):
        fail(f"pip did not build in RGBMESH_BUILD_DIR={build}")

    # Nothing of the build may be needed any more.
    shutil.rmtree(build)
    # -I: no PYTHONPATH, no user site packages, no script directory; only the venv's and the
    # system's site packages.
    run_check(env_python, ["-I"], env_dir, build, clean_environment(), cwd=work, version=version)

    # The wheel's record is complete: uninstalling leaves no file of the package behind.
    subprocess.run([env_pip, "uninstall", "-y", "--disable-pip-version-check", "rgbmesh"],
                   env=clean_environment(), cwd=work, check=True, stdout=subprocess.DEVNULL)
    site = subprocess.run([env_python, "-I", "-c", "import sysconfig; print(sysconfig.get_path('platlib'))"],
                          env=clean_environment(), check=True, capture_output=True, text=True).stdout.strip()
    left = os.path.join(site, "rgbmesh")
    if os.path.exists(left):
        fail(f"pip uninstall left {left}: {os.listdir(left)}")


def main(argv):
    if len(argv) >= 4 and argv[1] == "check":
        check(argv[2], argv[3], argv[4] if len(argv) > 4 else None)
    elif len(argv) == 4 and argv[1] == "installed":
        installed(os.path.abspath(argv[2]), os.path.abspath(argv[3]))
    elif len(argv) == 5 and argv[1] == "pip":
        pip(os.path.abspath(argv[2]), os.path.abspath(argv[3]), argv[4])
    else:
        print(__doc__, file=sys.stderr)
        sys.exit(2)


if __name__ == "__main__":
    main(sys.argv)
