#!/usr/bin/env bash
# Runs `rgbmesh fit` with its defaults on many targets and prints a markdown table of the
# outcomes: exit code, the two distance directions (relative to the diagonal), the base, the
# time and the peak memory. Not part of the test command (minutes to tens of minutes).
#   bench/fit_survey.sh RGBMESH LIST [OUT]
# LIST: one target per line, "path [extra options]"; blank lines and # comments are skipped.
# Every run is bounded: 600 s and 8 GB of address space.
set -uo pipefail
tool=$1; list=$2; out=${3:-/tmp/fit-survey}
mkdir -p "$out"
echo "| target | kind | exit | targets→surface rms / max | surface→target rms / max | base | seconds | peak MB | outcome |"
echo "|---|---|---|---|---|---|---|---|---|"
while read -r path extra; do
  [ -z "$path" ] && continue
  case "$path" in \#*) continue;; esac
  name=$(basename "$path")
  dir="$out/$name"; mkdir -p "$dir"
  start=$(date +%s.%N)
  ( ulimit -v 8000000; /usr/bin/time -f "%M" -o "$dir/time.txt" timeout 600 \
      "$tool" fit --target "$path" $extra --out "$dir/run" --report "$dir/report.json" >"$dir/stdout.txt" 2>"$dir/stderr.txt" )
  code=$?
  seconds=$(echo "$(date +%s.%N) - $start" | bc)
  peak=$(( $(tail -1 "$dir/time.txt" 2>/dev/null || echo 0) / 1024 ))
  python3 - "$dir" "$name" "$code" "$seconds" "$peak" <<'PY'
import json, sys, os
d, name, code, seconds, peak = sys.argv[1:]
report = os.path.join(d, "report.json")
err = open(os.path.join(d, "stderr.txt")).read().strip().splitlines()
last = next((l for l in reversed(err) if "error" in l), "")
if os.path.exists(report) and int(code) in (0, 2) and os.path.getmtime(report) >= os.path.getmtime(os.path.join(d, "time.txt")) - 700:
    r = json.load(open(report))
    f, b = r["targets_to_surface"], r["surface_to_target"]
    base = r["base"]
    btxt = f'{base["source"]}{"/" + base["reconstruction"] if "reconstruction" in base else ""} {base["faces"]}f g{base["genus"]} b{base["boundary_loops"]}'
    out = "accepted" if r["status"] == "accepted" else "rejected: " + r["reason"][:90]
    print(f'| {name} | {r["target"]["kind"]} | {code} | {100*f["rms_relative"]:.3f}% / {100*f["max_relative"]:.2f}% | {100*b["rms_relative"]:.3f}% / {100*b["max_relative"]:.2f}% | {btxt} | {float(seconds):.1f} | {peak} | {out} |')
else:
    print(f'| {name} | | {code} | | | | {float(seconds):.1f} | {peak} | {last.replace("rgbmesh: error: ", "refused: ")[:140]} |')
PY
  rm -f "$dir/report.json" 2>/dev/null
done < "$list"
