#!/usr/bin/env bash
# How fast each core of this machine runs rgbmesh's own work, relative to the fastest: the same
# short adaptive run (the default sphere-peak, CYCLES cycles) started on every core at
# once, each pinned to its core. Distributed runs are as fast as their slowest process, and
# mpirun binds rank r to core r (a one-process run to core 0), so a ratio between runs on 1 and
# 2 processes means little where the cores differ: on the 2-core development machine, on
# 2026-12-07, core 1 took 1.2-1.7 times core 0's time for the same work for stretches of about
# an hour, and the same time in between (the virtual machine's doing: it reports no steal time).
# Usage: bench/core_speeds.sh [BUILD_DIR] [ROUNDS] [CYCLES]   (one line per core and round)
set -euo pipefail
build=${1:-build}
rounds=${2:-1}
cycles=${3:-20}  # (about 2.5 s: 12 cycles took 0.3 s, too short to time)
tool="$build/bin/rgbmesh"
[ -x "$tool" ] || { echo "core_speeds.sh: $tool not found (build first)" >&2; exit 2; }
command -v taskset > /dev/null || { echo "core_speeds.sh: taskset (util-linux) not found" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cores=$(nproc)
for ((round = 1; round <= rounds; ++round)); do
  pids=()
  for ((core = 0; core < cores; ++core)); do
    taskset -c "$core" /usr/bin/time -f "%e" -o "$work/t$core" \
      "$tool" adapt --cycles "$cycles" --out "$work/run$core" > /dev/null 2>&1 &
    pids+=($!)
  done
  for pid in "${pids[@]}"; do wait "$pid"; done
  fastest=$(cat "$work"/t* | sort -g | head -1)
  for ((core = 0; core < cores; ++core)); do
    t=$(cat "$work/t$core")
    /usr/bin/python3 -c "import sys; print('round %s core %s: %.2f s, %.2f times the fastest' % (sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[3]) / float(sys.argv[4])))" \
      "$round" "$core" "$t" "$fastest"
  done
done
