#!/usr/bin/env bash
# The limit surface of CAD parts against the parts, without and with --sharp-angle (issue 42):
# fetches 29 CAD parts from Debian's packages (apt-get download, no installation) and prints
# build/bin/rgbmesh_sharp_distances' markdown table (docs/sharp-features.md, "CAD parts,
# measured"). Not part of the test command: it takes a few minutes.
#
# Usage: bench/cad_sharp_survey.sh [BUILD_DIR] [ANGLE]     (defaults: build, 30)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
angle=${2:-30}
tool=$build/bin/rgbmesh_sharp_distances
[ -x "$tool" ] || { echo "cad_sharp_survey.sh: no $tool (build with -DRGBMESH_BUILD_BENCH=ON)" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
parts=$tmp/parts
mkdir -p "$parts"
fetch() {  # PACKAGE: downloads and unpacks it into $tmp/PACKAGE
  (cd "$tmp" && apt-get download "$1" >/dev/null 2>&1) || { echo "cad_sharp_survey.sh: cannot download $1" >&2; exit 1; }
  mkdir -p "$tmp/$1"
  dpkg-deb -x "$tmp/$1"_*.deb "$tmp/$1"
}
fetch libcgal-demo
tar -xzf "$tmp/libcgal-demo/usr/share/doc/libcgal-dev/data.tar.gz" -C "$tmp"
for f in beam cheese cross cube-meshed cylinder dragknob handle itemb joint oblong part pinion pipe spool tripod \
  turbine u; do
  cp "$tmp/data/meshes/$f.off" "$parts/cgal_$f.off"
done
fetch netgen-doc
cp "$tmp"/netgen-doc/usr/share/doc/netgen/examples/{hinge,part1}.stl "$parts/"
fetch admesh
cp "$tmp/admesh/usr/share/doc/admesh/examples/block.stl" "$parts/"
fetch freecad-common
cp "$tmp/freecad-common/usr/share/freecad/Mod/OpenSCAD/OpenSCADTest/data/Cube.stl" "$parts/freecad_Cube.stl"
fetch cura
for f in BIQU_BX_PLATE.stl deltacomb_dc20.stl lulzbot_taz_pro_bed.stl tinyboy_fabrikator15.stl ultimaker2_platform.obj \
  ultimaker3_platform.obj; do
  cp "$tmp/cura/usr/share/cura/resources/meshes/$f" "$parts/cura_$f"
done
fetch prusa-slicer
cp "$tmp/prusa-slicer/usr/share/PrusaSlicer/profiles/Anycubic/AK_Bed.stl" "$parts/prusa_AK_Bed.stl"
cp "$tmp/prusa-slicer/usr/share/PrusaSlicer/profiles/Creality/cr10_bed.stl" "$parts/prusa_cr10_bed.stl"
"$tool" --angle "$angle" "$parts"/*
