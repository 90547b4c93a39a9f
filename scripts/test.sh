#!/usr/bin/env bash
# The test command: installs dependencies, builds, and runs every test (unit tests and the
# quick conformance checks), then unit tests of every layer under clang with AddressSanitizer
# and UndefinedBehaviorSanitizer, and the threaded ones under ThreadSanitizer (clang_tests.sh).
# The slow, tight conformance run is scripts/conformance.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --test-dir build --output-on-failure --parallel "$(nproc)"
bash scripts/clang_tests.sh
