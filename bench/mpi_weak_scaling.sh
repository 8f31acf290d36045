#!/usr/bin/env bash
# Weak scaling of the distributed moving peak (issue 44.4): the same problem on 1, 2, 4, 8 and
# 16 MPI processes with the work per process held about constant, so that what grows with the
# processes shows. The knob is the peak's target error (--target-error), chosen per P so that
# the steady steps have about 15,000 unknowns per process: the steps' size does not follow
# E^-2 (two adaptations per step lag the peak, and the floor and the wake of intermediate levels
# set a least size), so the targets were found by serial runs of the same command (2026-12-06:
# 0.25 -> 15,400 unknowns, 0.14 -> 33,000, 0.07 -> 59,000, 0.042 -> 119,000, 0.026 -> 245,000),
# and the script prints the per-process unknowns it got. The floor (--min-level 4, 5,120 cells)
# is the same for every P, as a run's floor would be; every process holds it, a replicated
# floor that does not fall with P. The start settles at the target on a static peak first (1.3
# million unknowns for 0.026), so the peak memory is the settling's.
#
# Per P, over the second half of the steps (from step 4 of 8: step 0 carries the settling start,
# and the next steps coarsen it away): the unknowns of the last step in all and per process; the
# coarsening rounds per adaptation (the report's coarsening_rounds per step over its
# cycles_per_step adaptations, 2: each round exchanges the processes' removals and makes the
# ghost layers exact again), on average and in the step with the most; the distributed mesh's
# all-to-all exchanges per step (each one a message to and from every process); the bytes sent
# per process per step, on average and the most by one process in a step (bytes_sent,
# bytes_sent_largest: every message PETSc, hypre and rgbmesh hand to MPI, counted through its
# profiling interface); the peak memory of the largest process (/usr/bin/time per rank, the
# whole run's, so the settling start's), and rank 0's resident memory in those steps (the
# report's resident_mb); the seconds per step, as information only (on a machine with fewer
# cores than processes they are no scaling measurement); and the most AMG iterations of a step's
# solve.
# The whole script takes about 20 minutes on the 2-core development machine (P = 16: 11).
# Usage: bench/mpi_weak_scaling.sh [BUILD_DIR] [P:TARGET ...]   (default: 1:0.25 2:0.14 4:0.07 8:0.042 16:0.026)
# Environment: STEPS (default 8), FLOOR (the --min-level, default 4), REPORTS (a folder to keep each
# run's report.json in, as pP.json, for the per-step timings the table leaves out).
set -euo pipefail
build=${1:-build}
shift || true
runs=("$@")
[ ${#runs[@]} -gt 0 ] || runs=(1:0.25 2:0.14 4:0.07 8:0.042 16:0.026)
tool="$build/bin/rgbmesh"
steps=${STEPS:-8}
floor=${FLOOR:-4}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
echo "moving peak, --min-level $floor --steps $steps"
printf "%3s %6s %9s %8s %8s %8s %9s %10s %10s %9s %7s %8s %4s\n" P target unknowns "per_proc" "rounds" "rnd_max" \
  "exchanges" "sent_MB/pr" "sent_MB_mx" "peak_MB" "r0_MB" "step_s" "its"
for run in "${runs[@]}"; do
  p=${run%%:*}
  target=${run#*:}
  out="$work/p$p"
  # Each process's share of the machine's memory, as distribution.md advises.
  mpirun --oversubscribe -np "$p" \
    sh -c '/usr/bin/time -f "%M" -o "$0.$OMPI_COMM_WORLD_RANK" "$@"' "$work/rss$p" \
    "$tool" --memory-limit "$((80 / p))%" adapt --problem moving-peak --min-level "$floor" --steps "$steps" \
    --target-error "$target" --max-dofs 100000000 --solver amg --out "$out" > "$work/log$p" 2>&1 ||
    { echo "P=$p failed:"; tail -5 "$work/log$p"; continue; }
  peak=$(cat "$work"/rss$p.* | sort -n | tail -1)
  [ -z "${REPORTS:-}" ] || { mkdir -p "$REPORTS" && cp "$out/report.json" "$REPORTS/p$p.json"; }
  /usr/bin/python3 - "$out/report.json" "$p" "$peak" "$target" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
p, peak = int(sys.argv[2]), int(sys.argv[3])
per = max(1, report.get("cycles_per_step", 1))
cycles = report["cycles"]
steps = cycles[max(2, (len(cycles) - 1) // 2):] or cycles
last = cycles[-1]
rounds = [c.get("coarsening_rounds", 0) / per for c in steps]
print("%3d %6s %9d %8d %8.2f %8.1f %9.1f %10.2f %10.2f %9.0f %7.0f %8.2f %4d" % (
    p, sys.argv[4], last["dofs"], last["dofs"] / p, sum(rounds) / len(rounds), max(rounds),
    sum(c.get("exchanges", 0) for c in steps) / len(steps),
    sum(c.get("bytes_sent", 0) for c in steps) / len(steps) / p / 1e6,
    max(c.get("bytes_sent_largest", 0) for c in steps) / 1e6, peak / 1024,
    max(c.get("resident_mb", 0) for c in steps),
    sum(c["seconds"] for c in steps) / len(steps), max(c.get("solver_iterations", 0) for c in steps)))
PY
done
