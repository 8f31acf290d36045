#!/usr/bin/env bash
# Fuzzes the readers with libFuzzer (fuzz/README.md).
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]
#
# SECONDS (default 1800) is the total fuzzing time, shared equally by the targets (default: all
# of them; `scripts/fuzz.sh 0 list` lists them). Installs clang 14 and libFuzzer when missing,
# configures and builds build-fuzz/ with clang (-DRGBMESH_FUZZ=ON), writes the seeds, then runs
# one target at a time, in one process (one core). Prints per target the executions, the
# coverage (cov: edges, ft: features) and the findings; exits 1 when there are findings.
#
# Under build-fuzz/, never in the repository:
#   seeds/EXT/        valid files (data/bunny.obj and an octahedron converted by `rgbmesh
#                     convert`, variants derived from them by fuzz/derive_seeds.py, the public
#                     data of build/public-data) and the malformed corpus of tests/corpus/files
#   corpus/TARGET/    the fuzzer's own corpus, growing from run to run
#   findings/TARGET/  crash-*, timeout-*, oom-*, leak-* inputs, and each one minimised (*.min)
#   logs/TARGET.log   libFuzzer's output, appended
#
# Environment: RGBMESH_CLI (the rgbmesh tool for the seeds; default: build-fuzz/bin/rgbmesh,
# else build/bin/rgbmesh, else it is built in build-fuzz), FUZZ_BUILD_JOBS (default 2),
# FUZZ_MINIMIZE_SECONDS (default 60 per finding), FUZZ_MINIMIZE_COUNT (default 3 per target),
# FUZZ_MAX_LEN (default 262144 bytes).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
build=$root/build-fuzz

all_targets=(fuzz_off fuzz_obj fuzz_ply fuzz_stl fuzz_vtk fuzz_xyz fuzz_xml fuzz_vtp fuzz_vtu fuzz_pieces fuzz_3mf
             fuzz_mesh_off fuzz_mesh_obj fuzz_mesh_ply fuzz_mesh_stl fuzz_mesh_vtk fuzz_mesh_vtp fuzz_mesh_vtu
             fuzz_mesh_3mf)

# The input extensions of a target's seeds, and its dictionary.
extensions_of() {
  case $1 in
    fuzz_xyz) echo "xyz pwn" ;;
    fuzz_xml) echo "vtp vtu" ;;
    fuzz_pieces) echo "pieces" ;;
    *) echo "${1##*_}" ;;
  esac
}
dictionary_of() {
  case $1 in
    fuzz_xml | fuzz_pieces | *vtp | *vtu) echo xml ;;
    *) echo "${1##*_}" ;;
  esac
}

total=1800
if [ $# -gt 0 ] && [[ $1 =~ ^[0-9]+$ ]]; then
  total=$1
  shift
fi
if [ "${1:-}" = list ]; then
  printf '%s\n' "${all_targets[@]}"
  exit 0
fi
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all_targets[@]}")
for t in "${targets[@]}"; do
  [[ " ${all_targets[*]} " == *" $t "* ]] || { echo "fuzz.sh: unknown target '$t' (scripts/fuzz.sh 0 list)" >&2; exit 2; }
done
max_len=${FUZZ_MAX_LEN:-262144}
minimize_seconds=${FUZZ_MINIMIZE_SECONDS:-60}
max_minimized=${FUZZ_MINIMIZE_COUNT:-3}

# --- what is needed ---------------------------------------------------------------------------
scripts/install-deps.sh main
missing=()
for p in clang-14 libfuzzer-14-dev libclang-rt-14-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "fuzz.sh: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo=sudo
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# --- build ------------------------------------------------------------------------------------
mkdir -p "$build"
cmake -S . -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DRGBMESH_FUZZ=ON -DRGBMESH_BUILD_TESTS=OFF -DRGBMESH_BUILD_BENCH=OFF > "$build/configure.log" 2>&1 ||
  { cat "$build/configure.log"; exit 1; }
cmake --build "$build" -j "${FUZZ_BUILD_JOBS:-2}" --target "${targets[@]}"

# --- seeds ------------------------------------------------------------------------------------
cli=${RGBMESH_CLI:-}
if [ -z "$cli" ]; then
  if [ -x "$build/bin/rgbmesh" ]; then cli=$build/bin/rgbmesh
  elif [ -x "$root/build/bin/rgbmesh" ]; then cli=$root/build/bin/rgbmesh
  else
    cmake --build "$build" -j "${FUZZ_BUILD_JOBS:-2}" --target rgbmesh_cli
    cli=$build/bin/rgbmesh
  fi
fi
seeds=$build/seeds
rm -rf "$seeds"
mkdir -p "$seeds/valid"
# A small mesh next to the bunny: small valid inputs give fast runs and mutations that hit the
# structure.
cat > "$seeds/valid/octahedron.obj" <<'EOF'
v 1 0 0
v -1 0 0
v 0 1 0
v 0 -1 0
v 0 0 1
v 0 0 -1
f 1 3 5
f 3 2 5
f 2 4 5
f 4 1 5
f 3 1 6
f 2 3 6
f 4 2 6
f 1 4 6
EOF
for mesh in "$root/data/bunny.obj" "$seeds/valid/octahedron.obj"; do
  name=$(basename "$mesh" .obj)
  for ext in obj off ply stl vtp vtu; do
    "$cli" convert "$mesh" "$seeds/valid/$name-tool.$ext" > /dev/null
  done
  if command -v python3 > /dev/null; then
    python3 fuzz/derive_seeds.py "$seeds/valid/$name-tool.off" "$seeds/valid"
  else
    echo "fuzz.sh: no python3: no legacy VTK, ASCII PLY/STL, .xyz and .pwn seeds derived" >&2
  fi
done
# Saved RGB states with inserted vertices, forced splits and all three colours (read_rgb_mesh):
# the octahedron refined uniformly, and inside a ball.
for ext in vtp vtu; do
  "$cli" refine "$seeds/valid/octahedron.obj" "$seeds/valid/octahedron-uniform2.$ext" --uniform 2 > /dev/null
  "$cli" refine "$seeds/valid/octahedron.obj" "$seeds/valid/octahedron-ball.$ext" --ball 1,0,0,0.5,4 > /dev/null
done
# Pieces of a distributed run with their states (read_rgb_pieces), where mpirun is there.
# 3MF seeds stored without compression, so that mutations reach the XML.
python3 - "$seeds/valid" <<'PY' || echo "fuzz.sh: no python3: no 3MF seeds of our own" >&2
import sys, zipfile
out = sys.argv[1]
core = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"
types = ('<?xml version="1.0" encoding="UTF-8"?><Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
         '<Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
         '<Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>')
rels = ('<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
        '<Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>')
pts = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
tris = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
mesh = ("<mesh><vertices>" + "".join('<vertex x="%g" y="%g" z="%g"/>' % p for p in pts) + "</vertices><triangles>" +
        "".join('<triangle v1="%d" v2="%d" v3="%d"/>' % t for t in tris) + "</triangles></mesh>")
for name, build in [("octahedron", '<item objectid="1"/>'),
                    ("components", '<item objectid="2" transform="0 1 0 -1 0 0 0 0 1 5 0 0"/>')]:
    model = ('<?xml version="1.0" encoding="UTF-8"?><model unit="millimeter" xmlns="%s"><resources>'
             '<object id="1" type="model">%s</object><object id="2" type="model"><components>'
             '<component objectid="1" transform="-1 0 0 0 1 0 0 0 1 0 0 2"/><component objectid="1"/></components></object>'
             '</resources><build>%s</build></model>' % (core, mesh, build))
    with zipfile.ZipFile("%s/%s.3mf" % (out, name), "w", zipfile.ZIP_STORED) as z:
        z.writestr("[Content_Types].xml", types)
        z.writestr("_rels/.rels", rels)
        z.writestr("3D/3dmodel.model", model)
PY
mkdir -p "$seeds/pieces"
if command -v mpirun > /dev/null; then
  OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np 2 "$cli" adapt --cycles 3 \
    --coarsen 0.5 --out "$seeds/run" > /dev/null 2>&1 && cp "$seeds/run"/cycle_00[0-2]_r[01].vtp "$seeds/pieces/"
  rm -rf "$seeds/run"
fi
for ext in obj off ply stl vtk vtp vtu xyz pwn 3mf; do
  mkdir -p "$seeds/$ext"
  for f in "$seeds/valid"/*."$ext" "$root/build/public-data"/*."$ext" "$root/build/public-data"/*/*."$ext" \
           "$root/tests/corpus/files"/*."$ext"; do
    # Larger files would be cut to max_len by libFuzzer: a truncated file, not a valid one.
    [ -f "$f" ] && [ "$(stat -c %s "$f")" -le "$max_len" ] && cp "$f" "$seeds/$ext/"
  done
done

# --- fuzzing ----------------------------------------------------------------------------------
# Scratch files of runs that crashed (the others remove theirs): rgbmesh-fuzz-PID.EXT.
remove_stale_scratch_files() {
  local f pid
  for f in /dev/shm/rgbmesh-fuzz-* "${TMPDIR:-/tmp}"/rgbmesh-fuzz-* /tmp/rgbmesh-fuzz-*; do
    [ -e "$f" ] || continue
    pid=${f##*rgbmesh-fuzz-}
    pid=${pid%%.*}
    [[ $pid =~ ^[0-9]+$ ]] && ! kill -0 "$pid" 2> /dev/null && rm -f "$f"
  done
  return 0
}

# Leaks of the libraries outside rgbmesh (fuzz/lsan.supp says which and why) are not findings.
export LSAN_OPTIONS="suppressions=$root/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

share=$((total / ${#targets[@]}))
[ "$share" -ge 10 ] || share=10
summary=()
findings_total=0
for t in "${targets[@]}"; do
  bin=$build/bin/$t
  corpus=$build/corpus/$t
  found=$build/findings/$t
  log=$build/logs/$t.log
  mkdir -p "$corpus" "$found" "$build/logs" "$build/seeds/$t"
  for ext in $(extensions_of "$t"); do cp "$seeds/$ext"/* "$build/seeds/$t/" 2> /dev/null || true; done
  echo "== $t: ${share}s (log: $log)"
  execs=0 cov=0 ft=0 new_findings=()
  start=$(date +%s)
  deadline=$((start + share))
  # A finding ends libFuzzer's run: it is started again for the rest of the target's share,
  # at most 5 times.
  for attempt in 1 2 3 4 5; do
    left=$((deadline - $(date +%s)))
    [ "$left" -ge 5 ] || break
    before=$(ls "$found")
    offset=$(stat -c %s "$log" 2> /dev/null || echo 0)
    rc=0
    "$bin" -max_total_time="$left" -timeout=10 -rss_limit_mb=2048 -max_len="$max_len" -print_final_stats=1 \
      -dict="$root/fuzz/dict/$(dictionary_of "$t").dict" -artifact_prefix="$found/" \
      "$corpus" "$build/seeds/$t" >> "$log" 2>&1 || rc=$?
    run=$(tail -c +"$((offset + 1))" "$log")
    n=$(grep -o 'stat::number_of_executed_units: [0-9]*' <<< "$run" | tail -1 | grep -o '[0-9]*$' || true)
    [ -n "$n" ] || n=$(grep -o '^#[0-9]*' <<< "$run" | tail -1 | tr -d '#' || true)
    execs=$((execs + ${n:-0}))
    c=$(grep -o 'cov: [0-9]*' <<< "$run" | tail -1 | grep -o '[0-9]*$' || true)
    f=$(grep -o 'ft: [0-9]*' <<< "$run" | tail -1 | grep -o '[0-9]*$' || true)
    [ -z "$c" ] || cov=$c
    [ -z "$f" ] || ft=$f
    remove_stale_scratch_files
    [ "$rc" -ne 0 ] || break
    what=$(grep -m1 -E 'SUMMARY: |rgbmesh fuzz finding|ERROR: libFuzzer|terminate called|runtime error' <<< "$run" || true)
    for a in $(comm -13 <(echo "$before") <(ls "$found")); do
      case $a in crash-* | timeout-* | oom-* | leak-* | slow-unit-*) ;; *) continue ;; esac
      new_findings+=("$found/$a: ${what:-exit code $rc}")
    done
    [ ${#new_findings[@]} -gt 0 ] || new_findings+=("(no input saved) exit code $rc: ${what:-see $log}")
  done
  # libFuzzer's minimisation runs step after step while the input shrinks (-max_total_time is
  # per step), so `timeout` bounds it; what it reached so far is in FILE.min. The first few
  # findings only: the others are mostly the same bug again.
  minimized=0
  for entry in "${new_findings[@]}"; do
    file=${entry%%: *}
    [ -f "$file" ] && [ "$minimized" -lt "$max_minimized" ] || continue
    minimized=$((minimized + 1))
    echo "   minimising $(basename "$file") (${minimize_seconds}s)"
    timeout -k 5 "$minimize_seconds" "$bin" -minimize_crash=1 -max_total_time=$(((minimize_seconds + 3) / 4)) \
      -timeout=10 -rss_limit_mb=2048 -exact_artifact_path="$file.min" "$file" >> "$log" 2>&1 || true
    remove_stale_scratch_files
  done
  corpus_size=$(find "$corpus" -type f | wc -l)
  summary+=("$(printf '%-15s %6ss %12s %8s %8s %8s %9s' "$t" "$(($(date +%s) - start))" "$execs" "$cov" "$ft" \
    "$corpus_size" "${#new_findings[@]}")")
  for entry in "${new_findings[@]}"; do summary+=("    finding: $entry"); done
  findings_total=$((findings_total + ${#new_findings[@]}))
done

echo
printf '%-15s %7s %12s %8s %8s %8s %9s\n' target time executions cov ft corpus findings
printf '%s\n' "${summary[@]}"
echo "findings: $findings_total (inputs and minimised inputs in $build/findings/)"
[ "$findings_total" -eq 0 ]
