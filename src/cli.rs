//! The command line's arguments: clap's derive types, whose doc comments are `--help`
//! (synced with docs/cli.md). Read by `main.rs`.
use clap::{Parser, Subcommand};
use std::path::PathBuf;

#[derive(Parser)]
#[command(
    name = "sinedec",
    version,
    about = "Generates verified Verilog for an FPGA sine/cosine encoder decoder"
)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
}

#[derive(Subcommand)]
pub(crate) enum Command {
    /// Writes Verilog and the parameter report for a configuration.
    ///
    /// Writes `<name>_core.v`, `<name>_core_tb.v` (self-checking testbench),
    /// `<name>_top.v` and, for a sinewave top, `<name>_top_tb.v` (its self-checking
    /// testbench), `<name>_params.md`, `<name>_params.json`, `<name>_inst.v`,
    /// `<name>_sinedec.core` (FuseSoC) and `<name>_lint.vlt` (Verilator `-Wall` waivers
    /// with their reasons).
    ///
    /// With a `[board]` section it adds `<name>_top.ucf`, plus `<name>_board.v`,
    /// `<name>_clock.v` and `<name>_clock_sim.v` when the board's oscillator is not the
    /// system clock (see `[board] clock_hz`); with `preset = "spartan3an-starter-kit"` also
    /// `<name>_top.ut`, BitGen options for `bitgen -f <name>_top.ut`: `-g
    /// UnusedPin:PullUp`. A `[capacitive]` config gets `<name>_top.qsf` and
    /// `<name>_top.sdc` for Quartus.
    ///
    /// A sinewave top without `[board]` gets `<name>_top.sdc` (Quartus TimeQuest, Synopsys)
    /// and `<name>_top.xdc` (Vivado) for a board of your own: `create_clock` on `clk` with
    /// the configured period, and for every other port of `<name>_top` an input or output
    /// delay (`-max` and `-min`) from the I/O budget `check` prints, the ADC data window
    /// with the capture distance as a multicycle, or a `set_false_path` for an input that
    /// enters through a synchronizer (docs/interfaces.md, "I/O constraints of a top without
    /// `[board]`"). Pin locations and I/O standards are left to you.
    ///
    /// Without CONFIG it uses the embedded `configs/spartan3an.toml`. DIR follows the
    /// output-directory rule: sinedec never overwrites or removes a file it did not write.
    /// Same config and command give the same bytes.
    Generate {
        /// Configuration file (TOML); the embedded Spartan-3AN default when omitted.
        config: Option<PathBuf>,
        /// Output directory: created when missing; sinedec replaces only the files its
        /// manifest (.sinedec-manifest) lists and never overwrites another file.
        #[arg(short, long, default_value = "out")]
        output: PathBuf,
        /// Use a non-empty directory sinedec did not write (no manifest): add the files next
        /// to the ones there; an existing file of the same name is still refused.
        #[arg(long)]
        force: bool,
    },
    /// Simulates the board top cycle by cycle against encoder, ADC and amplifier models.
    #[command(allow_negative_numbers = true)]
    ///
    /// Cycle-accurate simulation of `<name>_top` against an encoder model (imperfections,
    /// speed profile `constant:RPM`, `ramp:FROM:TO:S`, `reversal:RPM:AT:OVER`, `creep`) and
    /// the configured ADC's chip model answering its frames (the LTC1407A-1 behind an
    /// LTC6912-1 model on the kit preset; the generic SPI model from `[adc.frame]`). Its
    /// outputs are read by their masters: a BiSS-C master reads frames back to back at 2.5
    /// MHz MA (or the slave's limit) and each frame's CRC, position and turns are checked
    /// against the parallel bus at the slave's latch; with `[ssi]` an SSI master and with
    /// `[spi]` an SPI master (mode 0) read at the same rate (slower where the slave's
    /// synchronizer or the round trip needs it) and their positions and turns are checked
    /// the same way; with `[abz]` a quadrature counter follows the A/B edges against the
    /// position; with `[capture]` 1 us pulses on `capture` at `--capture-hz` (default 20
    /// kHz) and each capture's age and position against the encoder's angle at the pin;
    /// with `[registers]` the loop reads STATUS through AXI4-Lite every 10 us, clearing
    /// what it read, and prints each latched fault with the exact cycle it was raised (the
    /// top's live `flags`) and the polls that found it. `--fault KIND[@FROM[..TO]]`
    /// (repeatable) injects a fault: los, clip, broken-wire, overspeed, qep-b-stuck,
    /// adc-frame, no-index (docs/cli.md says which STATUS bits each raises). With
    /// `[reference] absolute` the encoder's SSI channel (`sim/ssi_encoder.rs`) answers
    /// the absolute start, the summary says what it stored and when the position became
    /// absolute, and the error figures count the referenced samples against the absolute
    /// position. Prints max/RMS error in LSB and arc-seconds, sample rate, latency, flags, ADC
    /// protocol violations, the BiSS-C, SSI, SPI, ABZ and capture checks and simulation
    /// speed, with a progress bar.
    ///
    /// On a `[capacitive]` config it runs `cap_top` against the capacitive encoder and a
    /// 16-bit SPI ADC model and prints the error in mechanical degrees and the per-sample
    /// processing time; the track imperfections (`--offset-sin`, `--offset-cos`,
    /// `--gain-mismatch`, `--phase-error`, `--harmonic2`, `--harmonic3`, `--harmonic5`, their
    /// `-phase` options and `--eccentricity`) do not apply there and are rejected.
    ///
    /// The encoder model (`sim/encoder.rs`) gives both tracks the same waveform, the cos
    /// track a quarter period later: sin(x) + h2 sin(2x + p2) + h3 sin(3x + p3) + h5 sin(5x +
    /// p5), with `--harmonicK` the ratio hk and `--harmonicK-phase` the phase pk in degrees.
    /// A 3rd or 5th harmonic of ratio h moves the decoded angle by about h rad electrical,
    /// four times per signal period; the 2nd once and three times. `--eccentricity` (in
    /// arc-seconds) turns the scale's angle against the shaft's by that much once per turn:
    /// the error is the shaft's, which no per-period correction can remove, and the summary
    /// says so. `--settle S` starts the statistics S seconds into the run (samples that leave
    /// the top earlier are not counted, and the CSV's `warmup` column marks them), for a
    /// correction to converge first.
    ///
    /// The compiled engine runs by default: built from the Verilog of the same rust-hdl top
    /// by Yosys and rustc, cached under `$SINEDEC_ENGINE_CACHE`, else
    /// `$XDG_CACHE_HOME/sinedec/engine`, else `~/.cache/sinedec/engine` (empty or relative
    /// values ignored, as the XDG specification says). A cached library is loaded only when
    /// its bytes match the SHA-256 stored beside it; a damaged entry is rebuilt, and a
    /// cache that cannot be written is said in one stderr line naming its path and variable
    /// while the model is built in a temporary directory.
    ///
    /// Options are checked before the run: speeds finite within ±1,000,000 rpm, ramp and
    /// reversal times > 0, `--amplitude` in (0, 1], `--noise-lsb` 0..=10000, offsets and
    /// `--gain-mismatch` -1..=1, `--phase-error` -45..=45 degrees, `--harmonic2`,
    /// `--harmonic3` and `--harmonic5` -0.5..=0.5, their phases -360..=360 degrees,
    /// `--eccentricity` -3600..=3600 arc-seconds, `--duration` (0, 10] s, `--settle` 0 <= S
    /// < `--duration`, `--capture-hz` (0, 100000] (with `[capture]` only), each `--fault` a
    /// known kind, once, starting within the run and ending after it starts (sinewave path
    /// only). A run with no decoded sample past the settling ones is an error (naming
    /// `--settle` when it is the settle time that leaves none), and on the capacitive path a
    /// `--duration` within the filters' 1.5 ms settling window is refused before the run. A profile faster than the decoder
    /// follows (`check`'s max speed: the unwrap limit, on the capacitive path also the
    /// low-pass corner) runs with a warning on stderr: its error figures measure a lost
    /// track. Negative values may be written in scientific notation (`--offset-sin -1e-1`).
    ///
    /// Without `--csv` no decoded sample is kept (the statistics are gathered as they
    /// come), so memory stays bounded however long the run.
    Simulate(SimulateArgs),
    /// Validates a configuration and prints its derived parameters.
    ///
    /// Says first which board top `generate` writes (`<name>_top.v`, beyond the core and
    /// its testbench: every preset has one; the ADC chip and the enabled outputs are named)
    /// and which chip models `simulate` runs it against, then prints the derived
    /// parameters: widths, guard bits, latency, ADC timing and its I/O budget, sample rate,
    /// resolution, maximum speed at full resolution. Its last line (`resources (top)`)
    /// gives the LUTs, FFs, block RAMs and multipliers of the whole configured top for the
    /// target family (xc3sa or cycloneive) from the Yosys synthesis `sinedec report` cached
    /// for this exact design (in `$SINEDEC_SYNTH_CACHE` or report's default cache
    /// directory), with the Yosys version; without one it says to run `sinedec report`.
    /// With `[harmonics]` the line before it (`resources (harmonics)`) gives the harmonic
    /// table's own figures the same way. `check` reads the cache only and never runs Yosys.
    Check {
        /// Configuration file (TOML); the embedded default when omitted.
        config: Option<PathBuf>,
    },
    /// Writes a commented example configuration.
    ///
    /// Creates missing parent directories; refuses an existing file without `--force`.
    Init {
        /// Where to write it (missing parent directories are created).
        #[arg(default_value = "sinedec.toml")]
        path: PathBuf,
        /// Overwrite an existing file.
        #[arg(long)]
        force: bool,
    },
    /// Gates, LUTs, flip-flops, latency and accuracy per CORDIC iteration count (both
    /// architectures), and every block of the top synthesized alone.
    ///
    /// Per CORDIC iteration count (`--iterations`): latency, throughput, Yosys
    /// LUT/FF/carry/multiplier/BRAM counts for xc3sa and cycloneive, a generic 2-input gate
    /// count (`abc -g AND,NAND,OR,NOR,XOR,XNOR,ANDNOT,ORNOT,MUX`, MUX = 1 gate), logic depth
    /// (`ltp -noff`), max/RMS error against exact atan2 over every 14-bit input pair of at
    /// least 1/8 full scale, predicted error, the thesis's figures as marked reference rows,
    /// and SVG plots.
    ///
    /// Per N it also synthesizes the other CORDIC architecture (table "Architectures
    /// (unrolled vs iterative)": LUT/FF/LE, latency, throughput, LUT ratio; plot
    /// `<name>_report_area_vs_n_arch.svg`), and it synthesizes every block of `<name>_top`
    /// alone plus the whole top (table "Blocks of `<name>_top`", JSON `blocks`,
    /// `<name>_report_blocks.csv`), with the post-route Fmax of nextpnr-ecp5 at placement
    /// seeds 1, 2 and 3 and their median, the figures the timing rule of docs/timing.md
    /// judges.
    ///
    /// Yosys and nextpnr results are cached by design hash. DIR follows the output-directory
    /// rule, checked before the run.
    Report {
        /// Configuration file (TOML); the embedded default when omitted.
        config: Option<PathBuf>,
        /// Iteration counts: A..=B, A..B, A-B, N or a comma-separated list (1..=20).
        #[arg(long, default_value = "2..=20")]
        iterations: String,
        /// Output directory, under the same rule as `generate -o` (checked before the run).
        #[arg(short, long, default_value = "report")]
        output: PathBuf,
        /// As `generate --force`.
        #[arg(long)]
        force: bool,
        /// Files to write: comma-separated md, csv (per N and per block), json, svg.
        #[arg(long, default_value = "md,csv,json,svg")]
        format: String,
        /// N of the error-against-angle plot (default: the config's N).
        #[arg(long)]
        angle_n: Option<u32>,
        /// Yosys result cache (default: $XDG_CACHE_HOME/sinedec/yosys or ~/.cache/sinedec/yosys).
        #[arg(long)]
        cache_dir: Option<PathBuf>,
        /// Run every Yosys synthesis again instead of using the cache.
        #[arg(long)]
        no_cache: bool,
    },
    /// Characterizes the configured top in its closed loop and writes a data sheet page.
    ///
    /// Runs `<name>_top` as `simulate` does (compiled engine, encoder and ADC chip models) over
    /// a grid of operating points, in parallel on every core, with a progress bar: error
    /// against electrical angle at three speeds before and after correction and its histogram;
    /// max/RMS error against speed from standstill to 1.5 x the unwrap limit (QEP fallback
    /// above it), ideal and with imperfections; the Lissajous figure of the raw and corrected
    /// samples and, with `correction.mode = "auto"` or `"peak"`, the coefficients against time;
    /// latency from CONV to each output and the sample rate (the derivations `check` prints);
    /// the velocity estimator's noise against speed, step and ramp response and lag; resources
    /// and post-route Fmax under the timing rule from the caches `sinedec report` fills (or how
    /// to get them); the config, command and version.
    ///
    /// A `[capacitive]` config gets the capacitive path's page: the capacitive `<name>_top`
    /// against the capacitive-encoder model, as `simulate` runs it, over a grid of speeds in
    /// parallel: error in mechanical degrees and arc-seconds against the angle within the
    /// signal period at three speeds and its histogram (with ADC noise); max/RMS error against
    /// speed from standstill to the speed limit `check` prints (the low-pass corner), ideal and
    /// with noise; the per-sample processing time and the sample rate (the derivation `check`
    /// and `simulate` print); resources and Fmax as above; the config, command and version.
    /// Correction, the Lissajous figure, the QEP fallback and velocity do not apply to that
    /// path, and the page says so in one line.
    ///
    /// Writes `DIR/index.html` (one file: inline SVG figures, inline CSS with print rules, no
    /// external asset) and `DIR/datasheet.json` (every number of the page's tables). DIR
    /// follows the output-directory rule of `generate`. Same config and command give the same
    /// bytes.
    Datasheet {
        /// Configuration file (TOML); the embedded default when omitted.
        config: Option<PathBuf>,
        /// Output directory, under the same rule as `generate -o` (checked before the run).
        #[arg(short, long, default_value = "datasheet")]
        output: PathBuf,
        /// As `generate --force`.
        #[arg(long)]
        force: bool,
        /// The reduced grid (fewer speeds, shorter runs): for CI.
        #[arg(long)]
        quick: bool,
    },
}

/// `simulate`'s arguments (the command's help is on [`Command::Simulate`]).
#[derive(clap::Args)]
pub(crate) struct SimulateArgs {
    /// Configuration file (TOML); the embedded default when omitted.
    pub(crate) config: Option<PathBuf>,
    /// Speed profile: constant:RPM, ramp:FROM:TO:SECONDS, reversal:RPM:AT_S:OVER_S, creep.
    #[arg(long, default_value = "constant:300")]
    pub(crate) profile: String,
    /// Simulated time in seconds.
    #[arg(long, default_value_t = 0.002, allow_hyphen_values = true)]
    pub(crate) duration: f64,
    /// Track amplitude as a fraction of the ADC input range.
    #[arg(long, default_value_t = 0.8, allow_hyphen_values = true)]
    pub(crate) amplitude: f64,
    /// Gaussian noise, RMS in ADC LSB.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) noise_lsb: f64,
    /// Offset of the sin track, fraction of the amplitude.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) offset_sin: f64,
    /// Offset of the cos track, fraction of the amplitude.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) offset_cos: f64,
    /// Relative gain mismatch of the tracks.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) gain_mismatch: f64,
    /// Quadrature phase error in degrees.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) phase_error: f64,
    /// Second-harmonic ratio of both tracks' waveform.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) harmonic2: f64,
    /// Phase of the second harmonic in degrees.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) harmonic2_phase: f64,
    /// Third-harmonic ratio.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) harmonic3: f64,
    /// Phase of the third harmonic in degrees.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) harmonic3_phase: f64,
    /// Fifth-harmonic ratio.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) harmonic5: f64,
    /// Phase of the fifth harmonic in degrees.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) harmonic5_phase: f64,
    /// Eccentricity of the scale in arc-seconds: a once-per-turn angle error.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) eccentricity: f64,
    /// Seconds of simulated time before the statistics start.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) settle: f64,
    /// Noise seed.
    #[arg(long, default_value_t = 1)]
    pub(crate) seed: u64,
    /// With `[capture] enabled`: 1 us pulses on `capture` at this rate (default 20000, a
    /// PWM frequency), the first one period after the start; rejected without `[capture]`.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) capture_hz: Option<f64>,
    /// Injects a fault, repeatable (each kind once): KIND[@FROM[..TO]] in seconds (from 0,
    /// to the end of the run when left out). KIND: los (tracks at 5 %), clip (tracks at 1.5
    /// ADC full scales), broken-wire (the sin track at 0 V), overspeed (1.1 x the unwrap
    /// limit), qep-b-stuck (comparator B low), adc-frame (the ADC's data lines stuck
    /// high), no-index (qep_z low). With `[registers]` the summary lists each fault STATUS
    /// latched with the exact cycle it was raised (docs/cli.md).
    #[arg(long = "fault", value_name = "KIND[@FROM[..TO]]")]
    pub(crate) fault: Vec<String>,
    /// Write every decoded sample as CSV (checked before the simulation; the directory
    /// must exist; an existing file is replaced).
    #[arg(long)]
    pub(crate) csv: Option<PathBuf>,
    /// Write the top's pins, cycle by cycle, as VCD (checked like --csv).
    #[arg(long)]
    pub(crate) vcd: Option<PathBuf>,
    /// Simulation engine of the top. compiled: Yosys turns the emitted Verilog into a
    /// netlist, rustc compiles it (cached under ~/.cache/sinedec/engine; 100-250x
    /// rust-hdl). rust-hdl: the reference simulation. interpreter: the engine's netlist
    /// interpreted (no rustc needed). Without --engine the compiled engine runs, or the
    /// interpreter without rustc, or rust-hdl without Yosys, each fallback said on
    /// stderr; an engine named here runs or fails. All give the same report, proven by
    /// tests/system/engine.rs, tests/system/engine_loop.rs and the co-simulation tests.
    #[arg(long, value_enum)]
    pub(crate) engine: Option<EngineArg>,
}

/// `simulate --engine`.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub(crate) enum EngineArg {
    /// The compiled engine (Yosys + rustc, cached under ~/.cache/sinedec/engine).
    Compiled,
    /// rust-hdl's own simulation (the reference).
    RustHdl,
    /// The engine's netlist interpreted (Yosys only).
    Interpreter,
}
