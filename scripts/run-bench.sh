#!/usr/bin/env bash
# Builds rgbmesh (Release) and regenerates the tables of docs/performance.md. The first line it
# prints is the stamp those tables carry: the date, the commit (with -dirty when tracked files
# differ from it) and the machine (cores, CPU model, memory).
# Then: the Google Benchmark cases (insertions/s, removals/s, the time ratio to OpenSubdiv
# measured in the same process), the command-line tool's --stats on the Stanford bunny refined
# to uniform level 5 (1.9 million vertices: peak memory per vertex) and coarsened back, the
# finite-element benchmark (assembly and solve, 10^4 to 10^6 unknowns, each solver; the
# adaptive cycle), the fit, --repair against reading (bench_repair), the Python package's
# arrays against refining (bench/python_overhead.py), and the output formats on 1.9 million vertices (bench_write:
# seconds against PLY, memory); against deal.II where it is installed (bench_vs_dealii); the
# adaptive loop on 1, 2 and 4 MPI processes (mpi_cycles.sh) and the partition among them
# (bench_partition). Arguments are passed to bench_refinement.
# Not run here (see docs/performance.md): bench_rgb_state, the moving peak's mpi_cycles.sh run,
# bench/fit_survey.sh and bench/p2_cad_sweep.sh.
set -euo pipefail
cd "$(dirname "$0")/.."

# The stamp: date, commit, machine.
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
if git rev-parse --git-dir >/dev/null 2>&1 && ! git diff --quiet HEAD -- 2>/dev/null; then
  commit="$commit-dirty"
fi
cpu=$(awk -F': *' '/^model name/ {print $2; exit}' /proc/cpuinfo 2>/dev/null || true)
memory=$(awk '/^MemTotal:/ {printf "%.1f GiB", $2 / 1048576; exit}' /proc/meminfo 2>/dev/null || true)
os=$( (. /etc/os-release && echo "${PRETTY_NAME:-}") 2>/dev/null || true)
echo "stamp: $(date +%Y-%m-%d), commit $commit, $(nproc) cores (${cpu:-unknown CPU}), ${memory:-unknown} memory${os:+, $os}"
scripts/install-deps.sh test
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DRGBMESH_BUILD_TESTS=ON -DRGBMESH_BUILD_BENCH=ON
cmake --build build --target bench_refinement bench_fem bench_fit bench_write rgbmesh_cli
cmake --build build --target bench_repair 2>/dev/null || true  # (without CGAL: no repair)
cmake --build build --target rgbmesh_python 2>/dev/null || true  # (without Python/pybind11: no package)
build/bin/bench_refinement --benchmark_min_time=1 "$@"
build/bin/bench_fem
build/bin/bench_fit
[ -x build/bin/bench_repair ] && build/bin/bench_repair
echo
echo "writing 1.9 million vertices in each output format (seconds against PLY, peak memory):"
build/bin/bench_write 3 3
echo
echo "bunny, uniform level 5:"
build/bin/rgbmesh refine data/bunny.obj - --uniform 5 --stats 2>/dev/null | tail -n 1
echo "bunny, uniform level 5, then back to the base mesh:"
build/bin/rgbmesh refine data/bunny.obj - --uniform 5 --coarsen-all --stats 2>/dev/null | tail -n 1
# The Python package's arrays against refining the mesh they describe (10^6 vertices).
if [ -d build/python/rgbmesh ]; then
  echo
  echo "Python arrays of a 10^6-vertex mesh, as fractions of refining it:"
  PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py
fi
# Against deal.II, where it is installed (Debian: libdeal.ii-dev; not installed by this script).
if cmake --build build --target bench_vs_dealii 2>/dev/null; then
  echo
  echo "adaptive sphere-peak against deal.II (Q1/Q2, Kelly, Dörfler 0.5):"
  build/bin/bench_vs_dealii --max-dofs 200000
else
  echo "no deal.II (Debian: libdeal.ii-dev): bench_vs_dealii skipped"
fi
# The adaptive loop on 1, 2 and 4 MPI processes, and its partition against building the FE mesh.
echo
echo "adaptive loop on 1, 2 and 4 processes:"
bench/mpi_cycles.sh build
if cmake --build build --target bench_partition 2>/dev/null; then
  build/bin/bench_partition
fi
