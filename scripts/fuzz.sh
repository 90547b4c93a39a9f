#!/usr/bin/env bash
# A developer check, not part of the test command: the libFuzzer targets of fuzz/ (docs/fuzzing.md),
# built with clang, AddressSanitizer and UndefinedBehaviorSanitizer, each run for SECONDS
# (default 600) in one process over a copy of its committed corpus (fuzz/corpus/<name>) with its
# dictionary. New inputs stay in the copy; a finding is written to BUILD_DIR/findings/ and stops
# the script with libFuzzer's report. Into ./build-fuzz.
#
#   bash scripts/fuzz.sh [SECONDS] [TARGET...]     # TARGET: fuzz_material_file, fuzz_cli (default both)
#
# Minimize a finding before committing it as a regression input (fuzz/corpus/<name>/):
#   build-fuzz/fuzz/<target> -minimize_crash=1 -runs=100000 build-fuzz/findings/crash-...
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-600}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_material_file fuzz_cli)
build=${BUILD_DIR:-build-fuzz}
bash scripts/setup.sh
# RelWithDebInfo: optimized, with line numbers in the reports. SECCHI_DISABLE_LANES: the portable
# path (as scripts/clang_tests.sh's first build); the targets parse input, nothing runs in lanes.
CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSECCHI_WERROR=ON \
    -DSECCHI_BUILD_FUZZERS=ON -DSECCHI_BUILD_TESTS=OFF -DSECCHI_BUILD_APPS=OFF -DSECCHI_BUILD_PYTHON=OFF \
    -DCMAKE_CXX_FLAGS=-DSECCHI_DISABLE_LANES >/dev/null
cmake --build "$build" --parallel 2 --target "${targets[@]}"
mkdir -p "$build/findings"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for target in "${targets[@]}"; do
  name=${target#fuzz_}
  cp -r "fuzz/corpus/$name" "$work/$name"
  mkdir -p "$work/tmp"
  echo "== $target: $seconds s over fuzz/corpus/$name"
  # One process (no -jobs, no -fork); -timeout: an input taking over 10 s is a hang.
  TMPDIR="$work/tmp" "$build/fuzz/$target" "$work/$name" -dict="fuzz/$name.dict" -max_total_time="$seconds" \
      -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$build/findings/$target-" 2>&1 |
    tee "$build/$target.log" | grep -E '^#[0-9]+.*(INITED|DONE)|^stat::|ERROR|SUMMARY|Test unit written' || true
  grep -q 'Test unit written' "$build/$target.log" && { echo "$target: finding (see $build/$target.log)"; exit 1; }
  echo "$target: $(ls "$work/$name" | wc -l) inputs in the corpus after the run, no finding"
done
