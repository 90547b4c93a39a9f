#!/usr/bin/env bash
# Configures and builds secchi (Release, warnings as errors) into ./build.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSECCHI_WERROR=ON >/dev/null
cmake --build build --parallel "$(nproc)"
