#!/usr/bin/env bash
# Rebuilds, from scratch, the two tool-result caches the suite looks up:
#   tests/data/cosim-cache  Icarus, Verilator and engine verdicts, and the passes of the
#                           testbench, lint and sweep checks (src/cosim/cache.rs);
#   tests/data/yosys-cache  Yosys synthesis results (src/synth.rs, SINEDEC_SYNTH_CACHE).
# It runs every test with both caches pointed at empty directories, so that they end up
# holding exactly the runs the suite makes. Run it after an RTL change and commit both
# directories; CI then runs the tools only for the designs that changed.
# (Place-and-route results are in tests/data/ecp5-cache: scripts/ecp5_cache.sh.)
set -euo pipefail
cd "$(dirname "$0")/.."
cosim="$PWD/tests/data/cosim-cache"
synth="$PWD/tests/data/yosys-cache"
rm -rf "$cosim" "$synth"
mkdir -p "$cosim" "$synth"
SINEDEC_COSIM_CACHE="$cosim" SINEDEC_SYNTH_CACHE="$synth" ./scripts/test.sh "$@"
echo "$(ls "$cosim" | wc -l) entries in $cosim, $(ls "$synth" | wc -l) in $synth"
