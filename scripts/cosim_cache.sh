#!/usr/bin/env bash
# Rebuilds tests/data/cosim-cache, the Icarus and Verilator verdicts the suite's
# co-simulations look up (src/cosim/cache.rs), from scratch: runs every test with the cache
# pointed at an empty directory, so that it ends up holding exactly the runs the suite makes.
# Run it after an RTL change and commit the directory; CI then simulates only what changed.
set -euo pipefail
cd "$(dirname "$0")/.."
dir="$PWD/tests/data/cosim-cache"
rm -rf "$dir"
mkdir -p "$dir"
SINEDEC_COSIM_CACHE="$dir" ./scripts/test.sh "$@"
echo "$(ls "$dir" | wc -l) entries in $dir"
