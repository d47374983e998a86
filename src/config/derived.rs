//! [`Derived`]: the parameters computed once from a validated [`Config`] (cross-field
//! checks, widths, tables and figures); its human-readable description is in
//! `describe.rs`.

use super::params::ErrFn;
use super::*;

impl Derived {
    /// Cross-field validation and derivation.
    pub fn compute(c: &Config, text: &str, source_name: &str) -> Result<Derived> {
        // The key blamed is located in the text (or its table, for a default), and every
        // other key the message names in backquotes gets its position too.
        let err = |table: &str, name: &str, message: String| {
            let key = if table.is_empty() {
                name.to_string()
            } else {
                format!("{table}.{name}")
            };
            Error::ConfigValue {
                source_name: source_name.to_string(),
                location: locate_or_table(text, table, name),
                message: cite_keys(text, &message, &key),
                key,
            }
        };
        check_target(c, &err)?;
        check_capacitive_scope(c, &err)?;
        let a = input_width(c, &err)?;
        let n = c.cordic.iterations;
        let f = c.cordic.fine_bits;
        // Guard bits so that truncation in the x/y shifts stays below 1/4 fine LSB for
        // inputs of at least 1/8 full scale: each stage truncates by < 1 unit of
        // 2^-G input LSB; the final angle error is about 2N * 2^-G / (K |v|) rad with
        // |v| >= 2^(A-4), which in fine LSB ((pi/2) 2^-F rad) is 0.78 N 2^(F+4-A-G).
        // At least enough that the last stage's shift stays inside the word.
        let auto_guard = (f as i64 + 4 - a as i64 + ceil_log2(n) as i64 + 2)
            .max(n as i64 - a as i64)
            .max(1) as u32;
        let xy_guard = c.cordic.guard_bits.unwrap_or(auto_guard);
        let xy_width = a + 2 + xy_guard;
        if xy_width > MAX_WORD_BITS {
            return Err(err(
                "cordic",
                "guard_bits",
                format!(
                    "x/y datapath would be {xy_width} bits (adc.width {a} + 2 + guard {xy_guard}); at most {MAX_WORD_BITS} are supported"
                ),
            ));
        }
        // Angle table rounding: N entries each within 1/2 unit of 2^-(F+Gz) -> N/2^(Gz+1)
        // fine LSB; ceil(log2 N) + 2 keeps it below 1/8 LSB.
        let z_guard = ceil_log2(n) + 2;
        let z_width = f + z_guard + 2;
        if n > a + xy_guard {
            return Err(err(
                "cordic",
                "iterations",
                format!(
                    "{n} iterations shift beyond the {} bits of the x/y datapath (adc.width {a} + guard {xy_guard}); use at most {}",
                    a + xy_guard,
                    a + xy_guard
                ),
            ));
        }
        let atan_table = exact::atan_table_quadrant(n, f + z_guard);
        let gain = exact::cordic_gain(n);
        let full_scale = 1u64 << (a - 1);
        let min_in = (c.monitor.min_amplitude * full_scale as f64).ceil() as u64;
        let min_magnitude = exact::gain_times_ceil(n, min_in << xy_guard);
        let quadrants_per_turn = 4 * c.encoder.ppr as u64;
        let quadrant_bits = 64 - (quadrants_per_turn - 1).leading_zeros();
        let position_width = quadrant_bits + f;
        let clock_hz = c.clock.frequency_hz;
        let (adc, preamp) = adc_params(c, text, &err)?;
        // The QEP fallback of the sinewave top compares its count in the clocks between a
        // conversion start and the ADC's sample (src/blocks/fallback/hdl.rs): three at least.
        let gap = adc.conv_to_valid_clocks() % adc.period_clocks.max(1);
        if c.capacitive.is_none() && gap < 3 {
            let key = if c.adc.sample_rate_hz.is_some() {
                "sample_rate_hz"
            } else {
                "preset"
            };
            return Err(err(
                "adc",
                key,
                format!(
                    "the {} delivers each sample {gap} clock(s) after a conversion start ({} clocks after its own, {} per period); the top's QEP fallback needs at least 3: set a lower adc.sample_rate_hz",
                    adc.chip,
                    adc.conv_to_valid_clocks(),
                    adc.period_clocks
                ),
            ));
        }
        let rate = adc.sample_rate_hz();
        // Warn at 1.75 quadrants per sample: the fine-angle unwrap is exact below 2.
        let warn_step = 7u64 << (f - 2);
        let max_speed_rpm_full_res =
            (warn_step - 1) as f64 / (1u64 << f) as f64 * rate / quadrants_per_turn as f64 * 60.0;
        let architecture = c.cordic.architecture;
        let (cycles_per_sample, latency_cycles) = match architecture {
            Architecture::Unrolled => (1, n + 2),
            Architecture::Iterative => {
                let s = crate::blocks::cordic::iterative::steps(n, xy_width);
                (s, s + 2)
            }
        };
        // The harmonic table sits in the core, between the CORDIC and the combiner.
        let harmonics = crate::blocks::harmonics::block::params(c, z_width, z_guard, f, &err)?;
        let latency_cycles =
            latency_cycles + crate::blocks::harmonics::block::latency_cycles(harmonics.as_ref());
        check_throughput(architecture, n, cycles_per_sample, clock_hz, rate)
            .map_err(|m| err("cordic", "architecture", m.detail()))?;
        let mut biss = biss_params(c, position_width, &err)?;
        let abz = crate::blocks::abz::block::params(c, quadrants_per_turn, f, &err)?;
        let velocity = velocity_params(c, text, f, rate, warn_step, &err)?;
        // `[velocity] in_frames`: the velocity word in every serial frame (BiSS, SSI, SPI).
        let vel_bits = velocity_frame_bits(c, velocity.as_ref(), &err)?;
        let in_frames = |m: crate::error::Error| err("velocity", "in_frames", m.detail());
        biss.velocity_bits = vel_bits;
        biss.validate().map_err(in_frames)?;
        let capacitive = match &c.capacitive {
            Some(k) => Some(cap_params(c, k, rate, &err)?),
            None => None,
        };
        let mut correction = correction_params(c, rate, &err)?;
        // The register map reads and writes the correction's codes: they become run-time
        // registers, which sets the correction's latency (so before anything derives it).
        if c.registers.enabled {
            correction = correction.with_writable();
        }
        // Clocks from a conversion start to the core's out_valid of its sample (the top's
        // `conv_to_position_cycles` without the reference's own stage).
        let to_core = adc.conv_to_valid_clocks() + correction.latency_cycles() + latency_cycles;
        let reference =
            crate::blocks::reference::block::params(c, &adc, to_core, preamp.is_some(), &err)?;
        let ssi = ssi_params(c, &biss, vel_bits, &err)?;
        let spi = spi_params(c, &biss, vel_bits, &err)?;
        let monitor = monitor_params(c, n, xy_guard, xy_width, &err)?;
        check_board(c, &err)?;
        let (board_clock, io_timing) = board_timing(c, &adc, &err)?;
        let qep = QepParams::new(c.qep.filter_clocks, 32)
            .map_err(|m| err("qep", "filter_clocks", m.detail()))?;
        let mut derived = Derived {
            board_clock,
            io_timing,
            adc,
            preamp,
            biss,
            ssi,
            spi,
            correction,
            monitor,
            qep,
            qep_enabled: c.qep.enabled,
            abz,
            velocity,
            reference,
            absolute: None,
            capture: None,
            harmonics,
            registers: None,
            adc_width: a,
            capacitive,
            iterations: n,
            fine_bits: f,
            xy_guard,
            xy_width,
            z_guard,
            z_width,
            atan_table,
            gain,
            min_magnitude,
            quadrants_per_turn,
            quadrant_bits,
            position_width,
            turns_width: c.encoder.multiturn_bits.max(1),
            multiturn_bits: c.encoder.multiturn_bits,
            warn_step,
            latency_cycles,
            architecture,
            cycles_per_sample,
            clock_hz,
            sample_rate_hz: rate,
            max_speed_rpm_full_res,
            resolution_bits: (quadrants_per_turn as f64).log2() + f as f64,
        };
        check_capacitive_front(&derived, &err)?;
        // The absolute start ties its word to the core's sample of the latch's conversion,
        // and its line timing to the board's I/O budget.
        derived.absolute = crate::blocks::absolute::block::params(c, &derived, to_core, &err)?;
        // The capture ages the position every output takes: from the one CONV-to-position
        // derivation of the top.
        derived.capture = crate::blocks::capture::block::params(
            c,
            &derived.adc,
            crate::blocks::top::hdl::conv_to_position_cycles(&derived),
            derived.velocity.as_ref(),
            &err,
        )?;
        derived.registers = crate::blocks::regmap::block::params(c, &derived, &err)?;
        // The map holds the monitor's thresholds.
        if derived.registers.is_some() {
            derived.monitor = derived.monitor.with_run_time_thresholds();
        }
        // The BiSS control channel's user area becomes the register map's banks.
        if let (Some(r), Some(_)) = (derived.registers.as_mut(), derived.biss.control.as_ref()) {
            *r = r.with_biss_port();
            derived.biss.user_map = true;
        }
        Ok(derived)
    }

    /// Latency in nanoseconds at the configured clock.
    pub fn latency_ns(&self) -> f64 {
        self.latency_cycles as f64 * 1e9 / self.clock_hz
    }
}

/// The core's input width: the ADC's, or the filters' on the capacitive path.
fn input_width(c: &Config, err: &ErrFn) -> Result<u32> {
    Ok(match &c.capacitive {
        Some(k) => {
            // Checked here, before any width arithmetic uses it (the rest of the
            // capacitive checks run after the core's derivation).
            if !(12..=16).contains(&k.data_width) {
                return Err(err(
                    "capacitive",
                    "data_width",
                    format!("{}: allowed 12..=16", k.data_width),
                ));
            }
            k.data_width
        }
        None => c.adc.width,
    })
}

/// The `[ssi]` slave's parameters, when enabled, with the velocity word of `[velocity]
/// in_frames` in its frame.
fn ssi_params(
    c: &Config,
    biss: &BissParams,
    vel_bits: u32,
    err: &ErrFn,
) -> Result<Option<SsiParams>> {
    let clock_hz = c.clock.frequency_hz;
    let in_frames = |m: crate::error::Error| err("velocity", "in_frames", m.detail());
    Ok(if c.ssi.enabled {
        let mut p = SsiParams::new(biss.position_bits, biss.multiturn_bits, clock_hz)
            .map_err(|m| err("ssi", "enabled", m.to_string()))?;
        p.gray = c.ssi.gray;
        if let Some(t) = c.ssi.timeout_us {
            p.set_timeout_us(t)
                .map_err(|m| err("ssi", "timeout_us", m.to_string()))?;
        }
        p.validate()
            .map_err(|m| err("ssi", "enabled", m.to_string()))?;
        p.velocity_bits = vel_bits;
        p.validate().map_err(in_frames)?;
        Some(p)
    } else {
        None
    })
}

/// The `[spi]` slave's parameters, when enabled, with the velocity word of `[velocity]
/// in_frames` in its frame.
fn spi_params(
    c: &Config,
    biss: &BissParams,
    vel_bits: u32,
    err: &ErrFn,
) -> Result<Option<SpiSlaveParams>> {
    let clock_hz = c.clock.frequency_hz;
    let in_frames = |m: crate::error::Error| err("velocity", "in_frames", m.detail());
    Ok(if c.spi.enabled {
        let mut p = SpiSlaveParams::new(biss.position_bits, biss.multiturn_bits, clock_hz)
            .map_err(|m| err("spi", "enabled", m.to_string()))?;
        p.gray = c.spi.gray;
        p.validate()
            .map_err(|m| err("spi", "enabled", m.to_string()))?;
        p.velocity_bits = vel_bits;
        p.validate().map_err(in_frames)?;
        Some(p)
    } else {
        None
    })
}

/// The capacitive front end's own checks (NCO, biquad engine widths and
/// coefficients, clocks per sample) run here too, so that `check` accepts exactly
/// what `generate` builds, and their errors point at the key.
fn check_capacitive_front(derived: &Derived, err: &ErrFn) -> Result<()> {
    if derived.capacitive.is_some() {
        crate::blocks::capacitive::CapFrontParams::new(derived).map_err(|e| match e {
            Error::ConfigValue { key, message, .. } => {
                let (table, key) = key.rsplit_once('.').unwrap_or(("", key.as_str()));
                err(table, key, message)
            }
            e => e,
        })?;
    }
    Ok(())
}
