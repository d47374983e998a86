//! [`Derived::describe`]: the human-readable listing of the derived parameters that
//! `sinedec check` prints (core, correction, velocity, ABZ, BiSS-C, line timing, board).

use super::*;

impl Derived {
    /// The board clock and the ADC round trip, for `describe`.
    fn describe_board(&self) -> String {
        let mut s = String::new();
        if let Some(b) = &self.board_clock {
            match b.synth {
                None => s.push_str(&format!(
                    "board clock                 {:.3} MHz oscillator = the system clock (no clock synthesizer)\n",
                    b.osc_hz / 1e6
                )),
                Some(x) => s.push_str(&format!(
                    "board clock                 {:.3} MHz oscillator -> {} x {} / {} = {:.3} MHz ({:+.0} ppm from clock.frequency_hz), reset held until locked\n",
                    b.osc_hz / 1e6,
                    x.kind.label(),
                    x.multiply,
                    x.divide,
                    x.out_hz / 1e6,
                    x.error_ppm
                )),
            }
        }
        s.push_str(&format!(
            "ADC sample rate             {:.0} samples/s per channel ({}): {}\n",
            self.adc.sample_rate_hz(),
            self.adc.chip,
            self.adc.rate_bound()
        ));
        let io = &self.io_timing;
        let (available, needed) = crate::board::adc_round_trip(
            io,
            self.adc.timing.data_valid_ns,
            self.adc.capture_distance_clocks(),
            self.adc.clock_hz,
        );
        s.push_str(&format!(
            "ADC round trip              {needed:.2} ns of {available:.2} ns (capture distance {} clocks: adc_sck edge to the adc_miso sample; SCK period {} clocks): clock-to-out {:.2} + 2 x trace {:.2} + SCK-to-data {:.2} + input set-up {:.2}; slack {:.2} ns (SCK-to-data up to {:.2} ns)\n",
            self.adc.capture_distance_clocks(),
            self.adc.sck_period_clocks,
            io.clock_to_out_ns,
            io.trace_ns,
            self.adc.timing.data_valid_ns,
            io.input_setup_ns,
            available - needed,
            self.adc.timing.data_valid_ns + available - needed
        ));
        s
    }

    /// The serial slaves' line timing for `describe` (one line per slave, from
    /// [`crate::blocks::serial::answer_window`] and
    /// [`crate::blocks::serial::max_round_trip_ns`]; docs/interfaces.md): when the answer
    /// leaves the pin after the master's clock edge, and the longest line round trip
    /// (cable and transceivers) at each rate up to the synchronizer's limit.
    fn describe_lines(&self) -> String {
        use crate::blocks::serial::{answer_window, max_round_trip_ns, LINE_RATES_HZ};
        let io = &self.io_timing;
        let rates = |max_hz: f64,
                     window: &dyn Fn(f64) -> f64,
                     a: &crate::blocks::serial::AnswerWindow|
         -> String {
            LINE_RATES_HZ
                .iter()
                .filter(|&&f| f <= max_hz)
                .map(|&f| {
                    let r = max_round_trip_ns(window(f), a);
                    let at = if f >= 1e6 {
                        format!("{:.0} MHz", f / 1e6)
                    } else {
                        format!("{:.0} kHz", f / 1e3)
                    };
                    if r >= 0.0 {
                        format!("{r:.1} ns at {at}")
                    } else {
                        format!("none at {at}")
                    }
                })
                .collect::<Vec<_>>()
                .join(", ")
        };
        let answer = |what: &str, a: &crate::blocks::serial::AnswerWindow, l: u32| {
            format!(
                "{what} {:.2}..{:.2} ns after the master's edge at the pin ({l}..{} clocks, input set-up {:.2}, clock-to-out {:.2})",
                a.min_ns,
                a.max_ns,
                l + 1,
                io.input_setup_ns,
                io.clock_to_out_ns
            )
        };
        let period = |f: f64| 1e9 / f;
        let b = &self.biss;
        let a = answer_window(b.clock_hz, b.glitch_filter, io);
        let mut s = format!(
            "biss line timing            {}; round trip (cable + transceivers, both ways) for a master reading each bit at the next MA rising edge: {}; a BiSS-C master with line-delay compensation: any round trip it compensates (MA up to {:.2} MHz)\n",
            answer("SLO answers", &a, b.latch_latency()),
            rates(b.max_ma_hz(), &period, &a),
            b.max_ma_hz() / 1e6
        );
        if let Some(x) = &self.ssi {
            let a = answer_window(x.clock_hz, x.glitch_filter, io);
            let max =
                x.clock_hz / (2 * crate::blocks::serial::min_level_clocks(x.glitch_filter)) as f64;
            s.push_str(&format!(
                "ssi line timing             {}; round trip for a master reading each bit at the next rising clock edge: {}\n",
                answer("data answers", &a, x.latch_latency()),
                rates(max, &period, &a)
            ));
        }
        if let Some(x) = &self.spi {
            let a = answer_window(x.clock_hz, x.glitch_filter, io);
            let half = |f: f64| 0.5e9 / f;
            s.push_str(&format!(
                "spi line timing             {}; round trip for a master sampling at the rising SCK edge after the falling one (50 % duty): {}\n",
                answer("MISO answers a falling SCK edge", &a, x.latch_latency()),
                rates(x.max_sck_hz(0.0), &half, &a)
            ));
        }
        s
    }

    /// Human-readable listing printed by `sinedec check`.
    pub fn describe(&self) -> String {
        let core = self.describe_core();
        let Some(k) = &self.capacitive else {
            let mut s = core;
            if self.preamp.is_some() {
                // The same quantity, under the same name, as `simulate` prints.
                let c = crate::blocks::top::hdl::conv_to_position_cycles(self);
                s.push_str(&format!(
                    "latency CONV -> position    {c} cycles = {:.0} ns (ADC {} + correction {} + core {}{})\n",
                    c as f64 * 1e9 / self.clock_hz,
                    self.adc.conv_to_valid_clocks(),
                    self.correction.latency_cycles(),
                    self.latency_cycles,
                    match crate::blocks::top::hdl::reference_cycles(self) {
                        0 => String::new(),
                        r => format!(" + reference {r}"),
                    }
                ));
            }
            {
                use crate::blocks::top::hdl::{BLOCK_RESET_CLOCKS, RESET_SYNC_CLOCKS};
                s.push_str(&format!(
                    "reset release               {} clock edges from the fall of <name>_top's rst to the blocks (synchronizer {RESET_SYNC_CLOCKS} + a register per block {BLOCK_RESET_CLOCKS}); it asserts at once\n",
                    RESET_SYNC_CLOCKS + BLOCK_RESET_CLOCKS
                ));
            }
            s.push_str(&describe_correction(
                &self.correction,
                self.sample_rate_hz,
                self.quadrants_per_turn / 4,
                self.max_speed_rpm_full_res,
            ));
            if let Some(v) = &self.velocity {
                s.push_str(&describe_velocity(v, self.quadrants_per_turn));
            }
            // The optional blocks' lines (the block registry; velocity's are above).
            for b in crate::blocks::registry::BLOCKS {
                if let Some(lines) = (b.describe)(self) {
                    s.push_str(&lines);
                }
            }
            s.push_str(&describe_biss(&self.biss));
            s.push_str(&self.describe_lines());
            s.push_str(&self.describe_board());
            return s;
        };
        // One speed limit: theta moves periods_per_turn x rpm / 60 Hz, and the low-pass
        // corner bounds it far below the CORDIC's unwrap limit.
        let mut s: String = core
            .lines()
            .filter(|l| !l.starts_with("max speed at full res."))
            .map(|l| format!("{l}\n"))
            .collect();
        let corner = k.config.lowpass.corner_hz.unwrap_or(0.0);
        let ppr = self.quadrants_per_turn as f64 / 4.0;
        let lp_rpm = corner / ppr * 60.0;
        let limit = lp_rpm.min(self.max_speed_rpm_full_res);
        s.push_str(&format!(
            "core input                  the filters' I/Q outputs ({} bits; ADC {} bits)\n\
             carrier                     {:.0} Hz, {:.1} samples per carrier period\n\
             max speed                   {:.0} rpm: the low-pass corner {:.0} Hz with {} periods per turn (the CORDIC's unwrap alone would allow {:.0} rpm)\n",
            self.adc_width,
            self.adc.frame.width,
            k.config.carrier_hz,
            k.sample_rate_hz / k.config.carrier_hz,
            limit,
            corner,
            ppr,
            self.max_speed_rpm_full_res
        ));
        s.push_str(&self.describe_board());
        s
    }

    fn describe_core(&self) -> String {
        format!(
            "core input width A          {} bits\n\
             cordic iterations N         {}\n\
             fine bits F                 {} (1 LSB = {:.4} arc-seconds of electrical angle)\n\
             x/y datapath                {} bits ({} guard bits)\n\
             angle accumulator           {} bits ({} guard bits)\n\
             cordic gain K_N             {:.12}\n\
             min magnitude (x units)     {}\n\
             quadrant count              {} bits (4 x PPR = {} quadrants per turn)\n\
             out_position width          {} bits ({:.2} bits per turn)\n\
             out_turns width             {} bits\n\
             core latency in -> out      {} cycles = {:.1} ns at {:.3} MHz\n\
             throughput                  1 sample per {} clock(s) ({} CORDIC)\n\
             sample rate                 {:.0} samples/s per channel\n\
             max speed at full res.      {:.0} rpm (steps below {:.2} quadrants per sample)\n",
            self.adc_width,
            self.iterations,
            self.fine_bits,
            90.0 * 3600.0 / (1u64 << self.fine_bits) as f64,
            self.xy_width,
            self.xy_guard,
            self.z_width,
            self.z_guard,
            self.gain,
            self.min_magnitude,
            self.quadrant_bits,
            self.quadrants_per_turn,
            self.position_width,
            self.resolution_bits,
            self.turns_width,
            self.latency_cycles,
            self.latency_ns(),
            self.clock_hz / 1e6,
            self.cycles_per_sample,
            self.architecture,
            self.sample_rate_hz,
            self.max_speed_rpm_full_res,
            self.warn_step as f64 / (1u64 << self.fine_bits) as f64,
        )
    }
}

/// The `[velocity]` lines of `check`: method, update period, the LSB of out_velocity in
/// rpm and the largest speed it represents.
fn describe_velocity(v: &VelocityParams, quadrants_per_turn: u64) -> String {
    let lsb = v.lsb_rpm(quadrants_per_turn as f64);
    let top = ((1u64 << (v.spec.width - 1)) - 1) as f64 * lsb;
    format!(
        "velocity                    method {}, one update every {} clocks ({:.1} Hz), latency {} clocks after the update's tick\n\
         velocity LSB                {:.6e} rpm (2^-{} position LSB per update period)\n\
         velocity range              +-{:.0} rpm representable in {} bits; the decoder's maximum speed gives at most {} LSB\n\
         velocity lag                {}\n",
        v.spec.method,
        v.period_clocks,
        v.spec.clock_hz / v.period_clocks as f64,
        v.latency(),
        lsb,
        v.spec.frac_bits,
        top,
        v.spec.width,
        v.max_output,
        velocity_lags(v)
    )
}

/// The `velocity lag` line: how far `out_velocity` trails the speed on a ramp
/// (`VelocityParams::lag_s`: the estimator's group delay plus the output latency), for the
/// configured method and, at the same rate and settings, for each other method.
fn velocity_lags(v: &VelocityParams) -> String {
    use crate::blocks::velocity::Method;
    let one = |p: &VelocityParams| {
        format!(
            "{} {:.3} ms ({:.2} updates + {} clocks)",
            p.spec.method,
            p.lag_s() * 1e3,
            p.lag_periods(),
            p.latency()
        )
    };
    let others: Vec<String> = [
        Method::Tracking,
        Method::Kalman,
        Method::Lsq,
        Method::DiffLpf,
    ]
    .into_iter()
    .filter(|m| *m != v.spec.method)
    .filter_map(|m| {
        let spec = crate::blocks::velocity::VelocitySpec {
            method: m,
            ..v.spec.clone()
        };
        VelocityParams::new(&spec).ok().map(|p| one(&p))
    })
    .collect();
    format!(
        "{} behind a speed ramp (the position's own age, CONV -> position, comes first); other methods: {}",
        one(v),
        others.join(", ")
    )
}

/// The `[correction]` lines of `check`: the mode, the phase correction and, for `auto`,
/// the limit of the peak tracker. A track sampled n times per signal period shows its
/// peak low by up to 1 - cos(pi / n) of the amplitude (the nearest sample is at most half a
/// sample period, pi / n, from the crest), so the tracked gain is too high by that much.
/// The printed speed is where that deficit reaches one LSB of the A-bit half range,
/// 2^-(A-1); the deficit is also given at 3000 rpm and at the decoder's speed limit.
fn describe_correction(c: &CorrectionParams, fs: f64, ppr: u64, max_rpm: f64) -> String {
    let extra = crate::blocks::correction::PHASE_EXTRA_CYCLES;
    let phase = if c.has_phase() && c.dynamic_cross() {
        format!(
            "phase correction with a run-time cross code (PHASE register; {} after reset; products >> {}) and {extra} more clocks",
            c.cross(),
            c.phase_shift()
        )
    } else if c.has_phase() {
        format!(
            "static phase correction, cross code {} (products >> {}) and {extra} more clocks",
            c.cross(),
            c.phase_shift()
        )
    } else {
        "no phase correction (correction.phase_deg = 0)".to_string()
    };
    if let Some(f) = c.fit() {
        let spp = |rpm: f64| fs / (ppr as f64 * rpm / 60.0);
        let win = |rpm: f64| {
            let per = spp(rpm);
            // Whole periods: at least K, and enough of them for min_samples.
            let k = (f.periods() as f64).max((f.min_samples() as f64 / per).ceil());
            k * per / fs
        };
        return format!(
            "correction                  auto: least-squares ellipse fit over whole periods (offset, gain and phase; cross code and two more clocks); products as run-time shift-add trees, no hard multiplier ({} more clocks)\n\
             auto fit window             at least {} periods and {} samples ({:.2} ms at the sample rate), then a {}-clock solve: new coefficients {} clocks after the window's closing sample (with the fit's {} pipeline stages); 1st update after about {:.1} ms at 300 rpm, {:.1} ms at 3000 rpm\n\
             auto fit limits             works up to the decoder's {:.0} rpm unwrap limit (a two-quadrant step counts in the last direction); no update below {} LSB amplitude or with an offset outside the ADC range; a window longer than 2^24 samples is abandoned\n",
            crate::blocks::correction::SHIFT_ADD_EXTRA_CYCLES,
            f.periods(),
            f.min_samples(),
            1e3 * f.min_samples() as f64 / fs,
            crate::blocks::correction::fit_solve::SOLVE_CYCLES,
            crate::blocks::correction::fit_solve::UPDATE_LATENCY,
            crate::blocks::correction::fit_hdl::FIT_STAGES,
            1e3 * win(300.0),
            1e3 * win(3000.0),
            max_rpm,
            f.min_amplitude()
        );
    }
    let Some(_) = c.auto() else {
        // Codes that are not powers of two: constant products as shift-add trees; writable
        // codes: run-time trees.
        let products = if c.writable() {
            format!(
                "; run-time codes (registers OFFSET_SIN .. PHASE, the values above after reset): gain and cross products as run-time shift-add trees ({} more clocks)",
                crate::blocks::correction::SHIFT_ADD_EXTRA_CYCLES
            )
        } else if c.shift_add() {
            format!(
                "; gain and cross products as shift-add trees, no hard multiplier ({} more clocks)",
                crate::blocks::correction::SHIFT_ADD_EXTRA_CYCLES
            )
        } else {
            String::new()
        };
        return format!(
            "correction                  static: offsets {:?} LSB, gain codes {:?} (2^-{}); {phase}{products}\n",
            c.offset(),
            c.gain(),
            c.gain_frac_bits()
        );
    };
    // Deficit 1 - cos(pi / n) at n = fs / (ppr rpm / 60) samples per period.
    let deficit = |rpm: f64| 1.0 - (std::f64::consts::PI * ppr as f64 * rpm / 60.0 / fs).cos();
    let lsb = 2f64.powi(1 - c.adc_width() as i32);
    let n_lsb = std::f64::consts::PI / (1.0 - lsb).acos();
    let rpm_lsb = 60.0 * fs / (n_lsb * ppr as f64);
    format!(
        "correction                  peak: offset and gain from per-track peaks over whole periods (peak tracker); no phase correction; products as run-time shift-add trees, no hard multiplier ({} more clocks)\n\
         peak-tracker limit          the sampled peaks are low by up to 1 - cos(pi / samples per period): within 1 LSB of 2^{} up to {:.0} rpm; {:.2} % at 3000 rpm, {:.2} % at the {:.0} rpm limit. Above that calibrate at low speed and copy the values into mode = \"static\" (which also takes phase_deg)\n",
        crate::blocks::correction::SHIFT_ADD_EXTRA_CYCLES,
        c.adc_width() - 1,
        rpm_lsb,
        100.0 * deficit(3000.0),
        100.0 * deficit(max_rpm),
        max_rpm
    )
}

/// The `[biss]` lines of `check`: the data word and, with `control = true`, the control
/// channel's register map as the master will read it.
fn describe_biss(b: &crate::blocks::biss::BissParams) -> String {
    let mut s = format!(
        "biss data word              {} bits ({} multi-turn + {} single-turn, {}), CRC6, timeout {} clocks\n",
        b.multiturn_bits + b.position_bits,
        b.multiturn_bits,
        b.position_bits,
        if b.gray { "Gray" } else { "binary" },
        b.timeout_clocks
    );
    match &b.control {
        None => s.push_str("biss control channel        off (CDS always 0)\n"),
        Some(id) => s.push_str(&format!(
            "biss control channel        on: 128-byte register file, 0x00..0x40 read/write; read-only IDs: \
             EDS bank 0x41 = 0x{:02X}, profile 0x42..43 = 0x{:04X}, serial 0x44..47 = {}, \
             device 0x78..7D = \"{}\", manufacturer 0x7E..7F = \"{}\"\n",
            id.eds_bank,
            id.profile_id,
            id.serial_number,
            ascii(&id.device_id),
            ascii(&id.manufacturer_id)
        )),
    }
    s
}

/// An ID register's bytes as text, the 0 padding dropped.
fn ascii(b: &[u8]) -> String {
    b.iter()
        .take_while(|&&c| c != 0)
        .map(|&c| c as char)
        .collect()
}
