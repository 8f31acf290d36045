#!/usr/bin/env bash
# The adaptive loop on 1, 2 and 4 MPI processes (issue 13), in one script so that the figures
# compare. For the last cycle of each run: its time (without writing the files) and the shares
# of building the finite-element mesh, partitioning its triangles (and numbering the unknowns),
# the distributed mesh's exchanges (parts decided, views migrated, interface splits handed
# over), assembly, solve, estimate, errors and adaptation (the rest: marking, refinement,
# solution transfer), and writing the
# files as a share of the same time; the solver's iterations; the largest peak memory of a
# process; and the bytes the processes sent during the cycle (the report's bytes_sent: every
# message PETSc, hypre and rgbmesh hand to MPI, counted through its profiling interface), per
# process on average and the most by one. Each process of a run shares the machine's cores.
# Usage: bench/mpi_cycles.sh [BUILD_DIR] [adapt options...]   (default: --strategy uniform --max-dofs 700000)
# Environment: PROCESSES (default "1 2 4"), REPEATS (default 1: each repeat runs every count
# again, so that alternating runs give the spread of a noisy machine). The cores' relative
# speeds (bench/core_speeds.sh) are printed before and after: a run on several processes is as
# fast as its slowest core, and on the development machine the second core was at times
# 1.2-1.7 times slower than the first for an hour, then equal again.
set -euo pipefail
build=${1:-build}
shift || true
args=("$@")
[ ${#args[@]} -gt 0 ] || args=(--strategy uniform --max-dofs 700000)
tool="$build/bin/rgbmesh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
printf "%3s %9s %7s %5s %5s %5s %5s %5s %5s %5s %5s %6s %4s %10s %11s %11s\n" P unknowns cycle_s mesh parts exch assem \
  solve estim errs adapt output its "peak_MB/pr" "sent_MB/pr" "sent_MB_max"
speeds() { "$(dirname "$0")/core_speeds.sh" "$build" 1 20 | sed 's/^round 1 /# /'; }
speeds
for ((repeat = 0; repeat < ${REPEATS:-1}; ++repeat)); do
for p in ${PROCESSES:-1 2 4}; do
  out="$work/p$p"
  rm -rf "$out"
  # (One process unbound: mpirun binds a lone process to one core, where a user's serial run,
  # started without mpirun, has every core for its threaded loops.)
  bind=()
  [ "$p" -gt 1 ] || bind=(--bind-to none)
  mpirun --oversubscribe "${bind[@]}" -np "$p" \
    sh -c '/usr/bin/time -f "%M" -o "$0.$OMPI_COMM_WORLD_RANK" "$@"' "$work/rss$p" \
    "$tool" adapt "${args[@]}" --solver amg --out "$out" > /dev/null 2>&1
  peak=$(cat "$work"/rss$p.* | sort -n | tail -1)
  /usr/bin/python3 - "$out/report.json" "$p" "$peak" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))["cycles"][-1]
s = c["seconds"]
assembly = c.get("assembly_seconds", 0.0)
parts = [c.get("mesh_seconds", 0.0), c.get("partition_seconds", 0.0), c.get("exchange_seconds", 0.0), assembly,
         c["solve_seconds"] - assembly,
         c.get("estimate_seconds", 0.0), c.get("error_seconds", 0.0)]
p = int(sys.argv[2])
shares = [100 * x / s for x in parts] + [100 * (s - sum(parts)) / s, 100 * c.get("output_seconds", 0.0) / s]
print("%3s %9d %7.2f" % (p, c["dofs"], s) + "".join(" %4.0f%%" % x for x in shares[:-1]) + " %5.0f%%" % shares[-1] +
      " %4d %10.0f %11.2f %11.2f" % (c["solver_iterations"], int(sys.argv[3]) / 1024, c.get("bytes_sent", 0) / p / 1e6,
                                     c.get("bytes_sent_largest", 0) / 1e6))
PY
done
done
speeds
