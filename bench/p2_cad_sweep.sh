#!/usr/bin/env bash
# Adaptive P1 and P2 on CAD-like meshes (issue 23): `rgbmesh adapt` with the default Gaussian
# problem and --max-dofs 30000 on each mesh, one markdown row per mesh and order: the cycles
# run, the last cycle's unknowns, why the run stopped, how often the estimate rose from one
# cycle to the next, the smallest growth of the unknowns from one cycle to the next after the
# first three (a stalled run adds a few triangles per cycle: 1.00), and the log-log slope of the
# estimate against the unknowns (least squares over the cycles after the first three; an
# adaptive P2 run that works falls at about -1, P1 at about -1/2), and the slope between the fifth
# last cycle and the last (the asymptotic rate). A mesh whose first mesh already has more
# unknowns than --max-dofs is refused by the tool (exit 2): its row says so.
# Not part of the test command: a sweep takes half an hour.
#
# Usage: bench/p2_cad_sweep.sh MESH_DIR [BUILD_DIR] [ORDERS] [MESH ...]
#   MESH_DIR  where the meshes are (CGAL's data/meshes: scripts/fetch-test-data.sh fetches a
#             few of them, the libcgal-demo package has all)
#   BUILD_DIR default build (the tool is BUILD_DIR/bin/rgbmesh; RGBMESH=path overrides)
#   ORDERS    default "2 1"; "loop" runs Loop-basis elements (--element loop)
#   MESH ...  file names in MESH_DIR (default: the CAD-like list below); a mesh that does not
#             load (not a manifold surface) gets a row saying why
# MAX_DOFS and CYCLES (environment) change --max-dofs (30000) and --cycles (20).
set -euo pipefail
[ $# -ge 1 ] || { sed -n '2,17p' "$0"; exit 2; }
dir=$1
build=${2:-build}
orders=${3:-"2 1"}
shift $(( $# < 3 ? $# : 3 ))
tool=${RGBMESH:-$build/bin/rgbmesh}
[ -x "$tool" ] || { echo "p2_cad_sweep.sh: no tool at $tool (build it first)" >&2; exit 2; }
meshes=("$@")
[ ${#meshes[@]} -gt 0 ] || meshes=(boeing.off pinion.off fandisk.off rotor.off couplingdown.off mech-holes-shark.off
  spool.off joint.off part.off turbine.off cheese.off anchor.off cross.off beam.off helmet.off dragknob.off
  anchor_dense.off rotor_small.off pinion_small.off blade.off b9_mesh.off ALSTOM_TEST4.off cube-meshed.off
  cylinder.off cylinder_locally_refined.off pipe.off itemb.off handle.off oblong.off tripod.off u.off
  fandisk_large.off mushroom.off)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

echo "| mesh | order | cycles | final unknowns | stopped | rises | min growth | slope (cycles 3..) | slope (last 5) |"
echo "| --- | ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: |"
for m in "${meshes[@]}"; do
  for order in $orders; do
    out="$work/run"
    code=0
    element=(--order "$order")
    [ "$order" = loop ] && element=(--element loop)
    nice -n 10 "$tool" adapt --mesh "$dir/$m" --triangulate "${element[@]}" --max-dofs "${MAX_DOFS:-30000}" \
      --cycles "${CYCLES:-20}" --out "$out" > "$work/stdout" 2> "$work/stderr" || code=$?
    if [ "$code" -ne 0 ]; then
      why=$(grep -m1 -i "error" "$work/stderr" | sed 's/^rgbmesh: error: //; s/;.*//; s/|/\\|/g')
      echo "| $m | $order | 0 | – | exit $code: $why | – | – | – | – |"
      continue
    fi
    python3 - "$out/report.json" "$m" "$order" <<'PY'
import json, math, sys
report = json.load(open(sys.argv[1]))
cycles = report["cycles"]
n = [c["dofs"] for c in cycles]
e = [c["estimate"] for c in cycles]
rises = sum(1 for a, b in zip(e, e[1:]) if b > a)
growth = [b / a for a, b in zip(n[3:], n[4:])]
least = "%.2f" % min(growth) if growth else "–"
fit = [(math.log(x), math.log(y)) for x, y in zip(n[3:], e[3:]) if y > 0]
slope = "–"
if len(fit) >= 2 and max(x for x, _ in fit) > min(x for x, _ in fit):
    mx = sum(x for x, _ in fit) / len(fit)
    my = sum(y for _, y in fit) / len(fit)
    slope = "%.2f" % (sum((x - mx) * (y - my) for x, y in fit) / sum((x - mx) ** 2 for x, _ in fit))
# The last five cycles alone: the asymptotic rate, once the first cycles' local features (the
# source's peak, straightened elements) are resolved.
last = "–"
if len(n) >= 8 and n[-1] > n[-5] and e[-5] > 0 and e[-1] > 0:
    last = "%.2f" % (math.log(e[-1] / e[-5]) / math.log(n[-1] / n[-5]))
print("| %s | %s | %d | %d | %s | %d | %s | %s | %s |" % (sys.argv[2], sys.argv[3], len(cycles), n[-1], report["stopped"], rises,
                                                         least, slope, last))
PY
  done
done
