#!/usr/bin/env bash
# What a Loop-element unknown costs against a P2 one (issue 45): adaptive sphere-peak (Dörfler
# 0.5) to --max-dofs 60000 with P2, Loop in the details basis and Loop in the truncated
# hierarchical basis, in one script, the runs alternated REPEATS times (this machine's speed
# drifts by 20% over minutes; compare within a round). Per run: cycles, last unknowns, last H1
# error, µs per unknown (the cycles' seconds over the sum of their unknowns, as the issue
# measures), that against the same round's P2, and the seconds until the run's H1 error first
# reached P2's last one (the cost of an accuracy rather than of an unknown).
# Not part of the test command: a round takes about a minute.
#
# Usage: bench/loop_cost.sh [BUILD_DIR]   (REPEATS=2, MAX_DOFS=60000; RGBMESH=path overrides
#        the tool, BASE=path adds the same runs of another build of the tool, e.g. the last
#        release, as a reference in the same rounds)
set -euo pipefail
build=${1:-build}
tool=${RGBMESH:-$build/bin/rgbmesh}
[ -x "$tool" ] || { echo "loop_cost.sh: no tool at $tool (build it first)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
tools=("$tool")
[ -n "${BASE:-}" ] && tools+=("$BASE")

echo "| round | tool | run | cycles | last unknowns | last H1 | µs per unknown | against P2 | seconds to P2's last H1 |"
echo "| ---: | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |"
for round in $(seq 1 "${REPEATS:-2}"); do
  for t in "${tools[@]}"; do
    for run in p2 details thb; do
      element=(--element p2)
      [ "$run" = details ] && element=(--element loop --loop-basis details)
      [ "$run" = thb ] && element=(--element loop --loop-basis thb)
      rm -rf "$work/$run"
      "$t" adapt "${element[@]}" --max-dofs "${MAX_DOFS:-60000}" --cycles 60 --out "$work/$run" > /dev/null
    done
    python3 - "$work" "$round" "$t" <<'PY'
import json, sys
work, round_, tool = sys.argv[1:4]
runs = {r: json.load(open(f"{work}/{r}/report.json"))["cycles"] for r in ("p2", "details", "thb")}
def per_unknown(c):
    return 1e6 * sum(x["seconds"] for x in c) / sum(x["dofs"] for x in c)
p2 = per_unknown(runs["p2"])
target = runs["p2"][-1]["error_h1"]
for name, c in runs.items():
    spent, reached = 0.0, None
    for x in c:
        spent += x["seconds"]
        if x["error_h1"] <= target:
            reached = spent
            break
    print(f"| {round_} | {tool} | {name} | {len(c)} | {c[-1]['dofs']:,} | {c[-1]['error_h1']:.2e} | "
          f"{per_unknown(c):.1f} | {per_unknown(c) / p2:.2f} | {reached:.2f} |")
PY
  done
done
