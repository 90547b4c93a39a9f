#!/usr/bin/env bash
# Renders the README's preview images into docs/images/ with the example programs (build them
# first: bash scripts/build.sh): the underwater camera's views and radiance distribution
# (examples/underwater_camera.cpp) and the host ray tracer with secchi's water
# (examples/embed/host_tracer.cpp), and the Case-1 spectral run's Rrs(lambda) and Ed(lambda, z)
# (examples/spectral_case1.cpp, drawn by scripts/plot_spectral.py), and the 3-D scenes
# (examples/littoral_scenes.cpp). PNG and SVG previews only: the OpenEXR files they come with are
# removed (the programs write them wherever they run). About 10 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
out=docs/images
mkdir -p "$out"
build/examples/underwater_camera --map-photons 1000000 --size 200 --spp 2 --out "$out/camera_"
build/examples/embed_host --map-photons 1000000 --size 160 --out "$out/embed"
build/examples/littoral_scenes --photons 2000000 --size 200 --spp 2 --out "$out/scene_"
build/examples/spectral_case1 --photons 100000 --csv build/spectral_case1.csv
python3 scripts/plot_spectral.py build/spectral_case1.csv "$out/spectral_case1.svg"
rm -f "$out"/*.exr
ls -l "$out"
