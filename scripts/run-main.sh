#!/usr/bin/env bash
# Builds rgbmesh (Release) and runs the main job on its embedded default problem.
# Extra arguments are passed to `rgbmesh`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh main
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DRGBMESH_BUILD_TESTS=OFF -DRGBMESH_BUILD_BENCH=OFF
cmake --build build --target rgbmesh_cli
build/bin/rgbmesh "$@"
