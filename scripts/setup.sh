#!/usr/bin/env bash
# Installs secchi's build dependencies from Debian packages (idempotent: installs only what
# is missing). GLM, Catch2 2.13, OpenEXR 3.1, nanoflann 1.4, plus the compilers (GCC, clang with its
# sanitizer and libFuzzer runtimes, libclang-rt-14-dev: scripts/clang_tests.sh, scripts/fuzz.sh) and
# CMake; and for the Python module (python/) pybind11, the Debian interpreter's headers, numpy and pytest.
# OpenMPI (libopenmpi-dev, openmpi-bin) for runs spread over processes (slab_mpi, docs/distributed.md);
# Embree 3 (libembree-dev) for triangle meshes in the water (scene/embree_mesh.hpp).
set -euo pipefail
packages=(g++ clang libclang-rt-14-dev cmake ninja-build libglm-dev catch2 libopenexr-dev libnanoflann-dev
          pybind11-dev python3-dev python3-numpy python3-pytest libopenmpi-dev openmpi-bin libembree-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all dependencies present"
  exit 0
fi
echo "setup: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
