#!/usr/bin/env bash
# The adaptive loop on 1, 2 and 4 MPI processes (issue 13), in one script so that the figures
# compare: for the last cycle of each run, its time and the shares of building the finite-element
# mesh, partitioning its triangles, assembly + solve, estimate, errors and the rest (adaptation,
# output); the solver's iterations; the largest peak memory of a process; and the bytes the
# processes sent during the cycle (the report's bytes_sent: every message PETSc, hypre and
# rgbmesh hand to MPI, counted through its profiling interface), per process on average and the
# most by one.
# Usage: bench/mpi_cycles.sh [BUILD_DIR] [adapt options...]   (default: --strategy uniform --max-dofs 700000)
set -euo pipefail
build=${1:-build}
shift || true
args=("$@")
[ ${#args[@]} -gt 0 ] || args=(--strategy uniform --max-dofs 700000)
tool="$build/bin/rgbmesh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
printf "%3s %9s %7s %6s %6s %6s %6s %6s %6s %4s %10s %12s %12s\n" P unknowns cycle_s mesh parts solve estim errors rest \
  its "peak_MB/pr" "sent_MB/pr" "sent_MB_max"
for p in 1 2 4; do
  out="$work/p$p"
  mpirun --oversubscribe -np "$p" \
    sh -c '/usr/bin/time -f "%M" -o "$0.$OMPI_COMM_WORLD_RANK" "$@"' "$work/rss$p" \
    "$tool" adapt "${args[@]}" --solver amg --out "$out" > /dev/null 2>&1
  peak=$(cat "$work"/rss$p.* | sort -n | tail -1)
  /usr/bin/python3 - "$out/report.json" "$p" "$peak" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))["cycles"][-1]
s = c["seconds"]
keys = ("mesh_seconds", "partition_seconds", "solve_seconds", "estimate_seconds", "error_seconds")
parts = [c.get(k, 0.0) for k in keys]
p = int(sys.argv[2])
print("%3s %9d %7.2f %5.0f%% %5.0f%% %5.0f%% %5.0f%% %5.0f%% %5.0f%% %4d %10.0f %12.2f %12.2f" % (
    p, c["dofs"], s, *(100 * x / s for x in parts), 100 * (s - sum(parts)) / s, c["solver_iterations"],
    int(sys.argv[3]) / 1024, c.get("bytes_sent", 0) / p / 1e6, c.get("bytes_sent_largest", 0) / 1e6))
PY
done
