#!/usr/bin/env bash
# Runs the whole sinedec test suite. Installs Yosys, Icarus Verilog and Verilator with
# apt-get when they are missing (the co-simulation and synthesis tests need them and fail,
# never skip, without them), then runs every Rust test.
set -euo pipefail
cd "$(dirname "$0")/.."

need=()
command -v yosys >/dev/null 2>&1 || need+=(yosys)
command -v iverilog >/dev/null 2>&1 || need+=(iverilog)
command -v verilator >/dev/null 2>&1 || need+=(verilator)
if [ ${#need[@]} -gt 0 ]; then
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  echo "installing ${need[*]} with apt-get"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${need[@]}" >/dev/null
fi
yosys -V
iverilog -V 2>&1 | sed -n 1p || true
verilator --version

cargo test --all-targets "$@"
