#!/usr/bin/env bash
# A developer check, not part of the test command: every unit test built with AddressSanitizer
# and UndefinedBehaviorSanitizer (GCC), including the -march=native builds of the SIMD code
# paths (the VOI scan kernels' slack writes, LaneTracer's chunk slots, the lane kernels), run
# under them. Any out-of-bounds access, use after free, leak, signed overflow, misaligned or
# out-of-range conversion stops the test with a report. (The test command runs a subset under
# clang's sanitizers, and the threaded test cases under ThreadSanitizer: scripts/clang_tests.sh.)
#
#   bash scripts/sanitize.sh [BUILD_DIR=build-sanitize] [ctest arguments...]
#
# Built with -ffp-contract=off. The instrumentation changes where GCC fuses a multiply and an
# add into one FMA, and it changes it differently in the scalar and the SIMD form of one
# formula (exp_table and lanes::exp, the direction rotation, HG's inverse CDF): the tests
# that hold the two forms to the same bits or to 1e-15 then fail by an ulp, as they would
# for any compiler that fuses the two forms differently (the library promises those
# identities where the compiler fuses both alike, e.g. GCC's -O2 and -O3). Without fused
# multiply-adds both forms round every operation, and the tests check the rest.
#
# Slow: the sanitized build takes about 40 minutes on 2 cores and the tests about 10 times
# their usual time. The examples, benchmarks and conformance runner are not built, nor is the
# Python module (an instrumented module loads only into an instrumented interpreter).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-sanitize}
shift || true
bash scripts/setup.sh
flags="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -ffp-contract=off"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSECCHI_BUILD_APPS=OFF -DSECCHI_BUILD_PYTHON=OFF \
    -DSECCHI_WERROR=ON \
    -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined"
cmake --build "$build" -j "$(nproc)"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir "$build" --output-on-failure --parallel "$(nproc)" "$@"
