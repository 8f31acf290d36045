#!/usr/bin/env bash
# Builds rgbmesh with its tests and benchmarks (Release) and runs the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh test
scripts/fetch-test-data.sh build/public-data
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DRGBMESH_BUILD_TESTS=ON -DRGBMESH_BUILD_BENCH=ON
cmake --build build
ctest --test-dir build --output-on-failure -j "$(nproc)"
