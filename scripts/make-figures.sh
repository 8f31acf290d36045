#!/usr/bin/env bash
# Regenerates the figures of the README and docs/ from real runs of the command-line tool:
#   docs/convergence.svg   H1 and L2 errors against unknowns, adaptive and uniform (sphere-peak)
#   docs/adapted-mesh.svg  the last adaptive mesh, colored by level
#   docs/fit-before.svg, docs/fit-after.svg  the bunny fit: limit surfaces of the base before and after
#   docs/cad-smooth.svg, docs/cad-sharp.svg  a CAD part's limit surface without and with --sharp-angle 30
#   docs/thb-functions.svg  the truncated hierarchical Loop basis's functions around the peak (example 09)
# Needs python3 (standard library only) and a built tool (scripts/run-main.sh); the files are
# written with zlib, which the standard library reads.
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
build/bin/rgbmesh --compression zlib adapt --problem sphere-peak --strategy uniform --cycles 8 --max-dofs 200000 \
  --out "$tmp/uniform" --report "$tmp/uniform.json" >/dev/null
build/bin/rgbmesh --compression zlib adapt --problem sphere-peak --strategy adaptive --cycles 40 --max-dofs 100000 \
  --out "$tmp/adaptive" --report "$tmp/adaptive.json" >/dev/null
mkdir -p docs
python3 scripts/figures.py convergence "$tmp/uniform.json" "$tmp/adaptive.json" docs/convergence.svg
# A mesh of a few thousand triangles draws well: the adaptive cycle closest to 3,000 unknowns.
cycle=$(python3 -c "
import json; c = json.load(open('$tmp/adaptive.json'))['cycles']
print(min(c, key=lambda r: abs(r['dofs'] - 3000))['cycle'])")
python3 scripts/figures.py mesh "$tmp/adaptive/cycle_$(printf %03d "$cycle").vtp" docs/adapted-mesh.svg 0.48 0.6 0.64
echo "wrote docs/convergence.svg and docs/adapted-mesh.svg"
# Fitting: the bunny from a 500-face base, limit surfaces before and after (level 2).
build/bin/rgbmesh --compression zlib fit --target data/bunny.obj --base-faces 500 --levels 2 --out "$tmp/fit" >/dev/null
python3 scripts/figures.py mesh "$tmp/fit/initial_limit_surface.vtp" docs/fit-before.svg 0 0 -1
python3 scripts/figures.py mesh "$tmp/fit/limit_surface.vtp" docs/fit-after.svg 0 0 -1
echo "wrote docs/fit-before.svg and docs/fit-after.svg"
# Sharp features: Netgen's part1.stl (scripts/fetch-test-data.sh), its limit surface at level 2.
part=build/public-data/netgen/part1.stl
build/bin/rgbmesh --compression zlib refine "$part" "$tmp/smooth.vtp" --uniform 2 --limit 2>/dev/null
build/bin/rgbmesh --compression zlib refine "$part" "$tmp/sharp.vtp" --uniform 2 --limit --sharp-angle 30 2>/dev/null
python3 scripts/figures.py mesh "$tmp/smooth.vtp" docs/cad-smooth.svg 1 0.8 1.2
python3 scripts/figures.py mesh "$tmp/sharp.vtp" docs/cad-sharp.svg 1 0.8 1.2
echo "wrote docs/cad-smooth.svg and docs/cad-sharp.svg"
# The truncated hierarchical Loop basis: its functions at about 1,000 unknowns, by level.
build/bin/example_09_smooth_adaptive --basis thb --max-dofs 1000 --svg docs/thb-functions.svg >/dev/null
echo "wrote docs/thb-functions.svg"
