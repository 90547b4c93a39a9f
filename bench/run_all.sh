#!/usr/bin/env bash
# Runs every benchmark and writes BENCHMARKS.md-ready markdown.
#   bash bench/run_all.sh [BUILD_DIR] [OUT_DIR] [--quick]
# BUILD_DIR (default build) is a configured Release build; its `benchmarks` target is built
# first (the benchmarks are not in the default build). OUT_DIR (default BUILD_DIR/bench-results) receives results.md (the tables, with
# machine, date and commands), secchi_bench.json, scaling.csv and scaling.svg (the log-log
# plot, drawn by bench/plot_scaling.py with python3's standard library).
# Benchmarks are never part of the test command; on the 2-core machine the full run takes
# about 4-6 minutes (--quick: about 1).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="${1:-build}"
out="${2:-$build/bench-results}"
quick=""
for a in "$@"; do [[ "$a" == "--quick" ]] && quick="--quick"; done
cmake --build "$build" --target benchmarks --parallel "$(nproc)"
mkdir -p "$out"
md="$out/results.md"
cpu="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
# A virtual machine may name only the vendor ("AMD EPYC"): family and model tell the generation
# (AMD family 25: model 0-15 Zen 3, 16-31 and 96-127 Zen 4), and the SIMD flags which kernels run.
family="$(grep -m1 '^cpu family' /proc/cpuinfo | cut -d: -f2 | tr -d ' ')"
model="$(grep -m1 '^model[[:space:]]*:' /proc/cpuinfo | cut -d: -f2 | tr -d ' ')"
simd="$(grep -m1 '^flags' /proc/cpuinfo | tr ' ' '\n' | grep -E '^(avx2|fma|avx512f|avx512vl)$' | tr '\n' ' ' | sed 's/ $//')"

run() {  # run CMD...: echo the command into the markdown, then append its tables
    echo "Command: \`$*\`" >>"$md"
    echo >>"$md"
    local t0=$SECONDS
    "$@" --md "$out/part.md" >/dev/null
    cat "$out/part.md" >>"$md"
    echo "($((SECONDS - t0)) s)" >>"$md"
    echo >>"$md"
}

{
    echo "## Search structures and collection ($(date -u +%Y-%m-%d))"
    echo
    echo "Machine: \`nproc\` = $(nproc), CPU \"$cpu\" (/proc/cpuinfo: family $family, model $model; ${simd:-no AVX2}), $(uname -sr), compiler $(c++ --version | head -1)."
    native="$(grep -s '^SECCHI_BENCH_NATIVE:' "$build/CMakeCache.txt" | cut -d= -f2 || true)"
    echo "Benchmarks built with SECCHI_BENCH_NATIVE=${native:-ON} (ON: -march=native where accepted)."
    echo "Run with \`bash bench/run_all.sh $*\`. Timings are medians of repeated runs with the spread [min-max];"
    echo "the machine is shared, so compare figures within one table (ratios), not across runs."
    echo
} >"$md"

run "$build/bench/search_bench" --suite collect $quick
run "$build/bench/search_bench" --suite uniform $quick
run "$build/bench/search_bench" --suite tune $quick
run "$build/bench/search_bench" --suite build $quick
run "$build/bench/search_bench" --suite spectral $quick
echo "### Propagation against bare random walks" >>"$md"
echo >>"$md"
run "$build/bench/walk_bench" $quick
echo "### Phase samplers" >>"$md"
echo >>"$md"
run "$build/bench/phase_bench" ${quick:+--rounds 3}
echo "Command: \`$build/bench/search_bench --suite scaling $quick --csv $out/scaling.csv\`" >>"$md"
echo >>"$md"
"$build/bench/search_bench" --suite scaling $quick --csv "$out/scaling.csv" --md "$out/part.md" >/dev/null
cat "$out/part.md" >>"$md"
python3 "$here/plot_scaling.py" "$out/scaling.csv" "$out/scaling.svg"
echo "Plot: \`scaling.svg\` (bench/plot_scaling.py $out/scaling.csv)." >>"$md"
echo >>"$md"

echo "### Headline figures" >>"$md"
echo >>"$md"
echo "Command: \`$build/bench/secchi_bench $quick --json $out/secchi_bench.json\`" >>"$md"
echo >>"$md"
"$build/bench/secchi_bench" $quick --json "$out/secchi_bench.json" >/dev/null
{
    echo "| figure | value |"
    echo "|---|---|"
    python3 -c "import json,sys; [print(f'| {k} | {v:.4g} |') for k, v in json.load(open(sys.argv[1])).items()]" "$out/secchi_bench.json"
    echo
} >>"$md"
rm -f "$out/part.md"
echo "wrote $md, $out/scaling.svg"
