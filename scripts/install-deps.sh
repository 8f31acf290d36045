#!/usr/bin/env bash
# Installs the Debian 12 packages rgbmesh needs, when missing (apt-get, as root or via sudo).
#   scripts/install-deps.sh main   what the library and the CLI need
#   scripts/install-deps.sh test   the above plus the test and benchmark dependencies
# python3-setuptools and python3-wheel are main: `pip install --no-build-isolation .` builds the
# Python package with them (pip fetches nothing). python3-venv is test (Install.PythonPip makes a
# venv, which brings its own pip), with python3-pip, the system's pip of docs/install.md's --user
# route: neither is needed to build, and a user installs the one of the route taken.
set -euo pipefail

main_packages=(cmake ninja-build g++ pkg-config libvtk9-dev lib3mf-dev libeigen3-dev libsuitesparse-dev libopenblas0-pthread libceres-dev libcli11-dev libcgal-dev libpetsc-real-dev libmetis-dev openmpi-bin python3-dev python3-numpy pybind11-dev python3-setuptools python3-wheel)
test_packages=(libgtest-dev libgmock-dev libbenchmark-dev libosd-dev doxygen python3-vtk9 python3-pytest python3-venv python3-pip)

packages=("${main_packages[@]}")
if [ "${1:-main}" = "test" ]; then packages+=("${test_packages[@]}"); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "rgbmesh: installing missing Debian packages: ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
