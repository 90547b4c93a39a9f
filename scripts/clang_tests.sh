#!/usr/bin/env bash
# secchi under clang (Debian's clang 14) beside GCC, with sanitizers, part of the test command.
# Three builds, clang++ with warnings as errors:
#
#  1. AddressSanitizer + UndefinedBehaviorSanitizer, with libstdc++'s assertions
#     (_GLIBCXX_ASSERTIONS: indices checked against a container's size, not only its memory),
#     into build-asan, in the portable form that a standard library without
#     <experimental/simd> gets (SECCHI_DISABLE_LANES: one photon at a time, no LaneTracer, the
#     estimators' scalar loops), so that this path is built and tested too: the unit tests
#     below, which cover every layer (core, optics, scene, sources, transport, map and its
#     stores, estimate, io and its image files). Any out-of-bounds access, use after free or
#     return, leak, signed overflow, misaligned access, out-of-range conversion or bad
#     container index stops the test with a report.
#  2. The same sanitizers with the lanes (clang's own build of libstdc++'s <experimental/simd>,
#     SSE2 vectors here), into build-asan-lanes: tests/test_lane_tracer.cpp.
#  3. ThreadSanitizer with the lanes, into build-tsan: the test cases tagged [threads] in the
#     tests of the threaded code (test_stores: concurrent queries of every store;
#     test_transport: parallel_for, and the first pass's blocks, chunk pool and block-ordered
#     map on 2 threads; test_lane_tracer: LaneTracer's blocks on 2 threads; test_estimate: the
#     second pass's rays on 2 threads; test_images: rendered rows on 2 threads). Any data race
#     stops the test.
#
# The subset, and -O1, keep the step to about 5 minutes on 2 cores (the test command's budget
# is 30 minutes). The unit tests left out take long under the sanitizers (the statistical
# checks of test_estimate, test_exact_references, test_radiance_consistency, test_stratified
# and the spectral tests trace 10^5-10^6 photons: minutes each) or to compile, and run the
# code covered here. The [threads] cases are the threaded ones with 10^4 photons or fewer,
# unchanged; the statistical cases on 2 threads run the same loops with more photons.
# scripts/sanitize.sh (GCC, every unit test, the -march=native SIMD paths, about 40 minutes)
# is the full check.
#
#   bash scripts/clang_tests.sh [all]   # all: every unit test under ASan/UBSan (about 10 minutes)
#
# Build directories: $ASAN_BUILD (default build-asan), $ASAN_LANES_BUILD (build-asan-lanes) and
# $TSAN_BUILD (build-tsan).
set -euo pipefail
cd "$(dirname "$0")/.."
asan_build=${ASAN_BUILD:-build-asan}
asan_lanes_build=${ASAN_LANES_BUILD:-build-asan-lanes}
tsan_build=${TSAN_BUILD:-build-tsan}
asan_tests=(test_core test_event_physics test_phase test_transport test_radiance test_names
            test_scene test_sources test_record test_chord_table test_material_file test_images test_stores
            test_iop_absorption test_iop_scattering test_concentration test_refractive_index test_color
            test_periodic_ray test_problem3_profile test_bottom test_geometry test_embree_mesh test_height_field
            test_backscatter_bias test_upward_importance)
tsan_tests=(test_stores test_transport test_lane_tracer test_estimate test_images)
jobs=$(nproc)
step() { echo "clang_tests: $1 ($SECONDS s)"; }  # the seconds since the start, for the log

configure() {  # build dir, -fsanitize=..., further compiler flags
  CXX=clang++ cmake -S . -B "$1" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -gline-tables-only" \
      -DSECCHI_WERROR=ON -DSECCHI_BUILD_APPS=OFF -DSECCHI_BUILD_PYTHON=OFF -DSECCHI_TEST_NATIVE=OFF \
      -DCMAKE_CXX_FLAGS="$2 $3 -fno-omit-frame-pointer" -DCMAKE_EXE_LINKER_FLAGS="$2" >/dev/null
}

# 1. ASan + UBSan.
step "ASan+UBSan build"
asan_flags="-fno-sanitize-recover=all -D_GLIBCXX_ASSERTIONS"
configure "$asan_build" "-fsanitize=address,undefined" "$asan_flags -DSECCHI_DISABLE_LANES"
export ASAN_OPTIONS=detect_leaks=1:detect_stack_use_after_return=1:check_initialization_order=1:strict_init_order=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
if [ "${1:-}" = all ]; then
  cmake --build "$asan_build" --parallel "$jobs"
  step "ASan+UBSan tests"
  ctest --test-dir "$asan_build" --output-on-failure --parallel "$jobs" -R '^test_'
else
  cmake --build "$asan_build" --parallel "$jobs" --target "${asan_tests[@]}"
  step "ASan+UBSan tests"
  regex="^($(IFS='|'; echo "${asan_tests[*]}"))\$"
  ctest --test-dir "$asan_build" --output-on-failure --parallel "$jobs" -R "$regex"
fi

# 2. ASan + UBSan with the lanes.
step "ASan+UBSan build with the lanes"
configure "$asan_lanes_build" "-fsanitize=address,undefined" "$asan_flags"
cmake --build "$asan_lanes_build" --parallel "$jobs" --target test_lane_tracer
step "ASan+UBSan lane tests"
"$asan_lanes_build/tests/test_lane_tracer"

# 3. TSan: the [threads] test cases.
step "TSan build"
configure "$tsan_build" "-fsanitize=thread" ""
cmake --build "$tsan_build" --parallel "$jobs" --target "${tsan_tests[@]}"
step "TSan tests"
export TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1
for t in "${tsan_tests[@]}"; do
  echo "TSan: $t [threads]"
  "$tsan_build/tests/$t" "[threads]"
done
step "done"
