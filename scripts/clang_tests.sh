#!/usr/bin/env bash
# secchi under clang (Debian's clang 14) beside GCC, part of the test command: the library's
# unit tests that cover every layer (core, optics, scene, transport, map, estimate, io), built
# with clang++ and warnings as errors, in the portable form that a standard library without
# <experimental/simd> gets (SECCHI_DISABLE_LANES: one photon at a time, no LaneTracer), so that
# this path is built and tested too. Into ./build-clang.
#
#   bash scripts/clang_tests.sh [all]     # all: every unit test (about three times as long)
set -euo pipefail
cd "$(dirname "$0")/.."
tests=(test_core test_event_physics test_phase test_transport test_radiance test_names)
CXX=clang++ cmake -S . -B build-clang -G Ninja -DCMAKE_BUILD_TYPE=Release -DSECCHI_WERROR=ON \
    -DSECCHI_BUILD_APPS=OFF -DSECCHI_TEST_NATIVE=OFF -DCMAKE_CXX_FLAGS=-DSECCHI_DISABLE_LANES >/dev/null
if [ "${1:-}" = all ]; then
  cmake --build build-clang --parallel "$(nproc)"
  ctest --test-dir build-clang --output-on-failure --parallel "$(nproc)" -R '^test_'
else
  cmake --build build-clang --parallel "$(nproc)" --target "${tests[@]}"
  regex="^($(IFS='|'; echo "${tests[*]}"))\$"
  ctest --test-dir build-clang --output-on-failure --parallel "$(nproc)" -R "$regex"
fi
