#!/bin/sh
# The progress display (io/progress.hpp): shown on a terminal (a pseudo-terminal from
# util-linux's script), silent on a pipe and with --quiet, and the outputs the same with and
# without it. usage: progress.sh SLAB SPECTRAL_CASE1 MATERIAL_FILE
set -e
slab=$1 spectral=$2 material=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
# A slab run of several seconds (about 6 s on a 2-core Zen 4; the display starts after 2 s).
run="$slab --photons 2000000 --map-photons 20000 --depths 1 --store voi --threads 2"
script -qec "$run --json tty.json" /dev/null > tty.txt
grep -q 'slab: loop 1, .*ETA' tty.txt || { echo "no progress on a terminal"; cat tty.txt; exit 1; }
script -qec "$run --quiet --json quiet.json" /dev/null > quiet.txt
if grep -q 'ETA' quiet.txt; then echo "progress despite --quiet"; exit 1; fi
$run --json pipe.json > pipe.txt 2> pipe_err.txt
if [ -s pipe_err.txt ]; then echo "stderr on a pipe:"; cat pipe_err.txt; exit 1; fi
for f in tty quiet pipe; do grep -v '"seconds"' $f.json > $f.cmp; done
cmp tty.cmp pipe.cmp
cmp quiet.cmp pipe.cmp
# The display forced from the start: byte-identical CSV and table.
bands="--material $material --wavelengths 450:650:100 --depths 0:5:5 --photons 20000"
SECCHI_PROGRESS=always $spectral $bands --csv forced.csv > forced.txt 2> forced_err.txt
grep -q 'ETA' forced_err.txt || { echo "SECCHI_PROGRESS=always shows nothing"; exit 1; }
$spectral $bands --csv plain.csv > plain.txt 2> plain_err.txt
test ! -s plain_err.txt
cmp forced.csv plain.csv
cmp forced.txt plain.txt
echo "progress: shown on a terminal, silent on a pipe and with --quiet; same outputs"
