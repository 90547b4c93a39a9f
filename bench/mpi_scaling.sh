#!/usr/bin/env bash
# Wall times of slab_mpi under mpirun -n 1, 2 and 4 (one thread per rank), and the cost of the
# shards: slab's Lu time with 1 and with S maps on one process (docs/distributed.md checks its
# scaling model against these). Prints BENCHMARKS.md-ready markdown.
# usage: bash bench/mpi_scaling.sh [BUILD_DIR=build] [PHOTONS=2000000] [ROUNDS=3]
# Runs as root need OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 (set here).
set -euo pipefail
build=${1:-build} photons=${2:-2000000} rounds=${3:-3}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
args="--phase petzold --albedo 0.9 --depths 1,5,10 --photons $photons --map-photons $photons --batches 32 --shards 4 --seed 1 --store voi --ray-grid 30 --threads 1 --importance-cosine 0"
out=$(mktemp -d)
now() { date +%s.%N; }
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(date -u +%Y-%m-%d)"
echo "command: bash bench/mpi_scaling.sh $build $photons $rounds"
echo "problem: slab_mpi $args"
echo
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "mpirun start-up and shut-down alone (slab_mpi --photons 64 --map-photons 64 --depths 1, median of $rounds):"
for n in 1 2 4; do
  times=()
  for ((r = 0; r < rounds; ++r)); do
    t0=$(now)
    mpirun --oversubscribe -n $n "$build/examples/slab_mpi" --photons 64 --map-photons 64 --depths 1 --shards 4 --ray-grid 1 >/dev/null
    times+=("$(echo "$(now) - $t0" | bc -l)")
  done
  printf -- '- %d ranks: %.2f s\n' "$n" "$(printf '%s\n' "${times[@]}" | median)"
done
echo
echo "| ranks | wall s (median of $rounds) [min-max] | speed-up vs 1 rank | efficiency | rank 0: first pass / map build / Lu s (last run) |"
echo "|---|---|---|---|---|"
t1=""
for n in 1 2 4; do
  times=()
  for ((r = 0; r < rounds; ++r)); do
    t0=$(now)
    mpirun --oversubscribe -n $n "$build/examples/slab_mpi" $args --json "$out/mpi_$n.json" >"$out/mpi_$n.txt"
    times+=("$(echo "$(now) - $t0" | bc -l)")
  done
  parts=$(grep '^first pass' "$out/mpi_$n.txt" | sed -E 's/first pass ([0-9.]+) s, map build ([0-9.]+) s, Lu ([0-9.]+) s/\1 \/ \2 \/ \3/')
  med=$(printf '%s\n' "${times[@]}" | median)
  lo=$(printf '%s\n' "${times[@]}" | sort -g | head -1) hi=$(printf '%s\n' "${times[@]}" | sort -g | tail -1)
  [ -z "$t1" ] && t1=$med
  printf '| %d | %.2f [%.2f-%.2f] | %.2f | %.2f | %s |\n' "$n" "$med" "$lo" "$hi" "$(echo "$t1 / $med" | bc -l)" \
    "$(echo "$t1 / $med / $n" | bc -l)" "$parts"
done
for n in 2 4; do
  cmp <(grep -v '"seconds"' "$out/mpi_1.json") <(grep -v '"seconds"' "$out/mpi_$n.json") >/dev/null ||
    echo "WARNING: -n $n JSON differs from -n 1"
done

echo
echo "Lu time on one process (slab, 1 thread), one map vs 4 shards (median of $rounds):"
echo
echo "| shards | first pass s | map build s | Lu s |"
echo "|---|---|---|---|"
declare -A lu
for s in 1 4; do
  tr=() bu=() co=()
  for ((r = 0; r < rounds; ++r)); do
    line=$("$build/examples/slab" ${args/--shards 4/--shards $s} | grep '^first pass')
    read -r a b c < <(echo "$line" | sed -E 's/first pass ([0-9.]+) s, map build ([0-9.]+) s, Lu ([0-9.]+) s/\1 \2 \3/')
    tr+=("$a") bu+=("$b") co+=("$c")
  done
  lu[$s]=$(printf '%s\n' "${co[@]}" | median)
  printf '| %d | %s | %s | %s |\n' "$s" "$(printf '%s\n' "${tr[@]}" | median)" "$(printf '%s\n' "${bu[@]}" | median)" "${lu[$s]}"
done
printf '\nLu time ratio, 4 shards / 1 map: %.2f\n' "$(echo "${lu[4]} / ${lu[1]}" | bc -l)"
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
rm -rf "$out"
