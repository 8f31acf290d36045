#!/usr/bin/env bash
# Fetches the public meshes and point clouds that the tests use and that this repository does
# not hold, taken from Debian 12's packages with `apt-get download` (no installation, no root
# needed once the package lists exist):
#   - a selection of CGAL's data set (closed scans, meshes with many holes, high genus, CAD-like
#     parts, point clouds), from libcgal-demo, into DEST;
#   - meshes as tools export them, with the defects that --repair handles (issue 23): OpenSCAD's
#     STL exports (openscad-testing-data) into DEST/openscad, geomview's OFF models (geomview)
#     into DEST/geomview, assimp's test models (assimp-testmodels) into DEST/assimp;
#   - CAD parts as meshers' examples ship them: Netgen's hinge and part1 (netgen-doc) into
#     DEST/netgen (the pictures of docs/sharp-features.md);
#   - 3MF files as a slicer ships them: Cura's printer platforms (cura) into DEST/cura;
#   - OpenSubdiv's Loop regression shapes with crease and corner tags (issue 42), which Debian
#     ships only inside the test program bfr_evaluate (opensubdiv-tools): each is cut out of it
#     by its SHA-256 into DEST/opensubdiv/NAME.obj.
#   scripts/fetch-test-data.sh [DEST]     (default: build/public-data)
# DEST/.complete holds the version of this selection: a folder fetched by an older version is
# fetched again.
set -euo pipefail
cd "$(dirname "$0")/.."
dest=${1:-build/public-data}
version=7
[ -f "$dest/.complete" ] && [ "$(cat "$dest/.complete")" = "$version" ] && exit 0

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
  data/meshes/pig.stl                     # 17 patches meeting at 421 non-manifold vertices
  data/points_3/kitten.xyz                # point cloud, 5,210 points (with normals)
  data/points_3/sphere_20k.xyz            # point cloud, 21,000 points
  data/points_3/hippo1.ply                # point cloud, 6,104 points, binary PLY
  data/points_3/hippo2.ply                # one-sided scan, 4,387 points, a lobe held by one vertex (issue 43)
  data/points_3/oni.pwn                   # point cloud, 1,435 points with normals
  data/points_3/blobby.xyz                # point cloud, 3,288 points
  data/points_3/before_upsample.xyz       # open creased sheet, 850 points with normals
  data/points_3/fin90_with_PCA_normals.xyz  # folded CAD part, 757 points, principal-direction normals
  data/points_3/points.xyz                # 49 points: too few for a surface
  data/meshes/mpi.off                     # polygons of up to 10 corners, concave, corners in line (issue 43)
  data/meshes/P.off                       # a letter P of hexagons, two concave
  data/meshes/corner_poly.off             # concave hexagons
  data/meshes/double-torus-3-holes.off    # 201 polygons of up to 7 corners, 16 concave
)
# Meshes as tools export them, by package (extract below says where they go).
openscad_files=(
  stl/adns2610_dev_circuit_inv.stl        # a circuit board's outline, genus 14, zero-area triangles
  scad/bugs/issue1580-zero-area-triangle.stl
  scad/bugs/issue1580-back-to-back.stl    # a back-to-back pair of zero-area triangles
  scad/bugs/issue1580-back-to-back2.stl
  scad/bugs/issue945e.stl                 # coordinates of 1e-16 where 0 is meant: slivers
  scad/misc/bad-stl-pcbvicebar.stl        # files that once broke OpenSCAD's import; valid
  scad/misc/bad-stl-tardis.stl
  scad/misc/bad-stl-wing.stl
  scad/3D/features/import.stl
)
geomview_files=(
  tref.off                                # a trefoil tube: 320 quads with 1,280 vertices at 328 positions
  cam.off                                 # two triangles meeting at one vertex
  br2.off                                 # polygons whose fan-split gives zero-area triangles
)
assimp_files=(
  STL/sphereWithHole.stl                  # non-manifold vertices
  STL/3DSMaxExport.STL                    # non-manifold edges
  STL/Spider_binary.stl                   # zero-area triangles, parts
  PLY/cube_uv.ply                         # a cube with 24 vertices at 8 positions
  PLY/points.ply                          # 4 points, no faces
  OBJ/point_cloud.obj                     # 3 points, no faces
  OFF/Wuson.off                           # duplicate positions, non-manifold vertices
)
cura_files=(
  rigid3d_mucit2_platform.3mf             # 3MF: two components in a transformed build item
  ideagen3D_sapphire_plus.3mf             # 3MF: a component, an item transform
  weedo_x40.3mf                           # 3MF: 167,004 vertices, an item transform, lib3mf warnings
  blv_mgn_cube_300_platform.3mf           # 3MF: an item transform
  101hero-platform.3mf                    # 3MF: plain
  cr-x.3mf                                # 3MF: triangles that repeat a vertex, which lib3mf refuses
)

# OpenSubdiv's shapes (OBJ text with 't crease', 't corner', 't creasemethod' tags), by the
# SHA-256 of their text as OpenSubdiv 3.5.0 and 3.6.0 hold it.
opensubdiv_shapes=(
  loop_cube_creases0=852dfe68d40d6e8d0f5ec3d7c013e17bbfaa3efcd09cae2a0907c659674a6077
  loop_cube_creases1=b9b49bd9892e44e5d47c7947394fc551e99be0d9bde0484751234beb668786d3
  loop_cubes_infsharp=fd1c30ced98ef917e6b5a3217e624eb2c27bf2ac23f8b7e402022144a119f2b5
  loop_cubes_semisharp=ae3f1ca3d5dbdec7efef7c0f6985149e59f3874d64c0878b925968d5ff15fc3b
  loop_chaikin0=df556cb57df4ddc112ddef19ad8de4abd3862fe316defa633b6dbb1011b42f40
  loop_chaikin1=a7543d0e4aad022ac83a96c94123accc99c68f08e1687e244817df90becfeb4b
  loop_icos_infsharp=389eb1b4799839f668361ed244bc4980e3e17d22e6aaf602923bc17ff6837445
  loop_icos_semisharp=784f10b41b82825582bb7af12c9238d7a0872e18e01ef4eb0c79dd81279077b3
)

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
updated=no
# Downloads package $1 into $tmp (updating the package lists once if it is not found).
download() {
  if ! (cd "$tmp" && apt-get download "$1" >/dev/null 2>&1); then
    if [ "$updated" = no ]; then
      echo "rgbmesh: updating the package lists to download $1"
      sudo=""
      if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
      $sudo apt-get update -qq
      updated=yes
    fi
    (cd "$tmp" && apt-get download "$1" >/dev/null)
  fi
}
# Extracts files of package $1 found under its folder $2 into DEST/$3:
#   extract PACKAGE FOLDER TO FILE...
extract() {
  local package=$1 from=$2 to=$3
  shift 3
  download "$package"
  local paths=()
  for f in "$@"; do paths+=("./$from/$f"); done
  dpkg-deb --fsys-tarfile "$tmp/$package"_*.deb | tar -x -C "$tmp" "${paths[@]}"
  mkdir -p "$dest/$to"
  for f in "$@"; do cp "$tmp/$from/$f" "$dest/$to/"; done
}

mkdir -p "$dest"
download libcgal-demo
dpkg-deb --fsys-tarfile "$tmp"/libcgal-demo_*.deb | tar -x -C "$tmp" ./usr/share/doc/libcgal-dev/data.tar.gz
tar -xzf "$tmp/usr/share/doc/libcgal-dev/data.tar.gz" -C "$tmp" "${files[@]}"
for f in "${files[@]}"; do cp "$tmp/$f" "$dest/"; done
extract openscad-testing-data usr/share/openscad/testdata openscad "${openscad_files[@]}"
extract geomview usr/share/geomview/geom geomview "${geomview_files[@]}"
extract assimp-testmodels usr/share/assimp/models assimp "${assimp_files[@]}"
extract netgen-doc usr/share/doc/netgen/examples netgen hinge.stl part1.stl
extract cura usr/share/cura/resources/meshes cura "${cura_files[@]}"
download opensubdiv-tools
dpkg-deb --fsys-tarfile "$tmp"/opensubdiv-tools_*.deb | tar -x -C "$tmp" ./usr/bin/bfr_evaluate
mkdir -p "$dest/opensubdiv"
python3 - "$tmp/usr/bin/bfr_evaluate" "$dest/opensubdiv" "${opensubdiv_shapes[@]}" <<'PY'
import hashlib, sys
binary, out, wanted = sys.argv[1], sys.argv[2], dict(a.split("=") for a in sys.argv[3:])
found = {}
for text in open(binary, "rb").read().split(b"\0"):
    digest = hashlib.sha256(text).hexdigest()
    for name, expected in wanted.items():
        if digest == expected:
            found[name] = text
missing = sorted(set(wanted) - set(found))
if missing:
    sys.exit("rgbmesh: OpenSubdiv's shapes not found in bfr_evaluate: " + ", ".join(missing))
for name, text in found.items():
    with open(f"{out}/{name}.obj", "wb") as f:
        f.write(text)
PY

cat > "$dest/README" <<'TXT'
Public test data fetched by scripts/fetch-test-data.sh from Debian's packages: libcgal-demo
(CGAL's data set, data/meshes and data/points_3) here, openscad-testing-data in openscad/,
geomview in geomview/, assimp-testmodels in assimp/, OpenSubdiv's Loop shapes with crease
tags (cut out of opensubdiv-tools' bfr_evaluate) in opensubdiv/, netgen-doc's CAD parts in netgen/. Not part of rgbmesh; not
committed.
TXT
echo "$version" > "$dest/.complete"
echo "rgbmesh: test data in $dest"
