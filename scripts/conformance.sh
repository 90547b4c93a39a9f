#!/usr/bin/env bash
# The main job: Mobley et al. 1993 canonical problems 1a, 1b, 2a, 2b with both photon stores,
# at the default (full) photon budgets. Writes conformance_kdtree.json, conformance_voi.json,
# the problem-2a photon-map image photon_map_2a.exr and a markdown table of both stores
# (conformance.md) into ./build/conformance-results. Exit status 1 if any scored entry fails.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
out=build/conformance-results
mkdir -p "$out"
status=0
for store in kdtree voi; do
  build/conformance/canonical --problem all --store "$store" --seed 1 --threads "$(nproc)" \
    --json "$out/conformance_$store.json" --exr "$out/photon_map_2a.exr" || status=1
done
python3 scripts/conformance_table.py "$out/conformance_kdtree.json" "$out/conformance_voi.json" > "$out/conformance.md"
echo "table of both stores: $out/conformance.md"
exit $status
