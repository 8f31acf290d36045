#!/usr/bin/env bash
# Fetches the public meshes and point clouds that the tests use and that this repository does
# not hold: a selection of CGAL's data set (closed scans, meshes with many holes, high genus,
# CAD-like parts, point clouds), taken from Debian 12's libcgal-demo package with
# `apt-get download` (no installation, no root needed once the package lists exist).
#   scripts/fetch-test-data.sh [DEST]     (default: build/public-data)
set -euo pipefail
cd "$(dirname "$0")/.."
dest=${1:-build/public-data}
[ -f "$dest/.complete" ] && exit 0

files=(
  data/meshes/cow.off                     # closed scan, 5,804 triangles, genus 0
  data/meshes/elephant.off                # closed, genus 0
  data/meshes/elephant-with-holes.off     # 106 boundary loops, genus 3
  data/meshes/mech-holes-shark.off        # CAD-like part with holes
  data/meshes/fandisk.off                 # CAD-like part, sharp features
  data/meshes/rotor.off                   # CAD-like, genus 1
  data/meshes/anchor.off                  # genus 4
  data/meshes/couplingdown.off            # CAD-like, genus 9
  data/meshes/knot1.off                   # torus knot, genus 1
  data/meshes/blade.off                   # open, 2 boundary loops
  data/meshes/3torus.off                  # quads, genus 3
  data/points_3/kitten.xyz                # point cloud, 5,210 points (with normals)
  data/points_3/sphere_20k.xyz            # point cloud, 21,000 points
  data/points_3/hippo1.ply                # point cloud, 6,104 points, binary PLY
  data/points_3/oni.pwn                   # point cloud, 1,435 points with normals
  data/points_3/blobby.xyz                # point cloud, 3,288 points
  data/points_3/before_upsample.xyz       # open creased sheet, 850 points with normals
  data/points_3/fin90_with_PCA_normals.xyz  # folded CAD part, 757 points, principal-direction normals
  data/points_3/points.xyz                # 49 points: too few for a surface
)

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
if ! (cd "$tmp" && apt-get download libcgal-demo >/dev/null 2>&1); then
  echo "rgbmesh: updating the package lists to download libcgal-demo"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  (cd "$tmp" && apt-get download libcgal-demo >/dev/null)
fi
dpkg-deb --fsys-tarfile "$tmp"/libcgal-demo_*.deb | tar -x -C "$tmp" ./usr/share/doc/libcgal-dev/data.tar.gz
mkdir -p "$dest"
tar -xzf "$tmp/usr/share/doc/libcgal-dev/data.tar.gz" -C "$tmp" "${files[@]}"
for f in "${files[@]}"; do cp "$tmp/$f" "$dest/"; done
cat > "$dest/README" <<'TXT'
Public test data fetched by scripts/fetch-test-data.sh from Debian's libcgal-demo package
(CGAL's data set, data/meshes and data/points_3). Not part of rgbmesh; not committed.
TXT
touch "$dest/.complete"
echo "rgbmesh: test data in $dest"
