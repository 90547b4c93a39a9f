#!/usr/bin/env bash
# The main job: Mobley et al. 1993 canonical problems 1a, 1b, 2a, 2b, 3, 4, 5 and 6 with each photon
# store (the k-d tree with spheres, the VOI octree and the VOI grid with the cylinder), at the
# default (full) photon budgets, every problem once more traced in float lanes (VOI grid,
# conformance_voi-grid_lanes-float.json), and problem 3 once more from its material file
# (examples/materials/canonical_problem3.mat). Writes conformance_kdtree.json,
# conformance_voi.json, conformance_voi-grid.json, conformance_3_material.json, the problem-2a
# photon-map image photon_map_2a.exr and problem 3's IOP profile iop_profile_3_material.csv into
# ./build/conformance-results, and there the conformance report (scripts/conformance_report.py):
# conformance_report.md, a table per problem, and conformance_<problem>.svg, a figure per
# problem, with the Kirk checks of --problem all in their own table. Exit status 1 if any
# scored entry fails.
#
# The seed study (scripts/seed_study.py: each entry's scatter over 8 seeds against its batch
# standard error) runs 8 times as long as this job's store runs, so it is not part of this job;
# run it apart, for each store, e.g.
#   python3 scripts/seed_study.py --store voi --seeds 8 --threads "$(nproc)"
# (into build/seed-study/); the seed_study_*.json found there are added to the report the next
# time this job runs, or at once with
#   python3 scripts/conformance_report.py build/conformance-results --seed-study build/seed-study/seed_study_voi.json
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
out=build/conformance-results
mkdir -p "$out"
status=0
for store in kdtree voi voi-grid; do
  build/conformance/canonical --problem all --store "$store" --seed 1 --threads "$(nproc)" \
    --json "$out/conformance_$store.json" --exr "$out/photon_map_2a.exr" || status=1
done
# Every problem once more with photons in float lanes (LaneTracer<..., float>), in the VOI grid.
build/conformance/canonical --problem 1a,1b,2a,2b,3,4,5,6 --tracer lanes-float --store voi-grid --seed 1 \
  --threads "$(nproc)" --json "$out/conformance_voi-grid_lanes-float.json" \
  --exr "$out/photon_map_2a_lanes-float.exr" || status=1
build/conformance/canonical --problem 3 --material examples/materials/canonical_problem3.mat --store voi \
  --seed 1 --threads "$(nproc)" --json "$out/conformance_3_material.json" --profile-csv "$out/iop_profile_3_material.csv" \
  || status=1
seed_studies=()
for study in build/seed-study/seed_study_*.json; do
  if [[ -e "$study" ]]; then seed_studies+=(--seed-study "$study"); fi
done
python3 scripts/conformance_report.py --out "$out" ${seed_studies[@]+"${seed_studies[@]}"} \
  "$out/conformance_kdtree.json" "$out/conformance_voi.json" "$out/conformance_voi-grid.json" \
  "$out/conformance_voi-grid_lanes-float.json" "$out/conformance_3_material.json"
exit $status
