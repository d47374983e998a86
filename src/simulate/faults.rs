//! `simulate --fault KIND[@FROM[..TO]]`: the faults the closed loop injects into the
//! encoder, the comparators and the ADC's data lines ([`FaultSpec`], [`parse_fault`]), and
//! how each one reaches the models ([`apply`]). docs/cli.md lists them with the STATUS bits
//! each raises.

use super::*;

/// A fault of `simulate --fault`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaultKind {
    /// `los`: both tracks at 5 % of their amplitude (a dirty scale): STATUS.LOS.
    Los,
    /// `clip`: both tracks at 1.5 times the ADC's full scale: STATUS.CLIP and FULL_SCALE.
    Clip,
    /// `broken-wire`: the sin track's wire broken, the ADC's input at 0 V (the cos track
    /// and the comparators unchanged): STATUS.FULL_SCALE (and CLIP, and QEP_MISMATCH with
    /// the QEP cross-check, as the angle goes wrong).
    BrokenWire,
    /// `overspeed`: [`OVERSPEED_FACTOR`] times the unwrap limit (`check`'s max speed), in
    /// the profile's direction at FROM: STATUS.OVERSPEED.
    Overspeed,
    /// `qep-b-stuck`: the comparator of the sin track (`qep_b`) stuck low: STATUS.QEP_MISMATCH.
    QepBStuck,
    /// `adc-frame`: every ADC data line stuck high at the FPGA's pad (a shorted or broken
    /// SDO with the input's pull-up): STATUS.ADC_FRAME.
    AdcFrame,
    /// `no-index`: `qep_z` held low (the index track lost): with `[reference]`,
    /// STATUS.NOT_REFERENCED stays set while the position has not homed.
    NoIndex,
}

/// Every kind with its `--fault` name, in the order docs/cli.md lists them.
pub const FAULT_KINDS: [(FaultKind, &str); 7] = [
    (FaultKind::Los, "los"),
    (FaultKind::Clip, "clip"),
    (FaultKind::BrokenWire, "broken-wire"),
    (FaultKind::Overspeed, "overspeed"),
    (FaultKind::QepBStuck, "qep-b-stuck"),
    (FaultKind::AdcFrame, "adc-frame"),
    (FaultKind::NoIndex, "no-index"),
];

/// The speed of `--fault overspeed` over the unwrap limit: 1.925 quadrants per sample,
/// beyond the 1.75 where the core warns and short of the 2.25 that would alias below it.
pub const OVERSPEED_FACTOR: f64 = 1.1;

/// The amplitude factor of `--fault los`.
pub const LOS_FACTOR: f64 = 0.05;

/// The tracks' amplitude with `--fault clip`, in ADC full scales.
pub const CLIP_FULL_SCALES: f64 = 1.5;

impl FaultKind {
    /// The `--fault` name.
    pub fn name(self) -> &'static str {
        FAULT_KINDS
            .iter()
            .find(|(k, _)| *k == self)
            .map_or("", |(_, n)| n)
    }
}

/// One injected fault: its kind and time window in seconds (`to` infinite: to the end).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaultSpec {
    /// What fails.
    pub kind: FaultKind,
    /// From, seconds.
    pub from: f64,
    /// To, seconds (infinite: the whole run).
    pub to: f64,
}

impl FaultSpec {
    /// `kind from..to` as the summary prints it.
    pub fn describe(&self) -> String {
        if self.to.is_finite() {
            format!(
                "{} from {:.1} us to {:.1} us",
                self.kind.name(),
                self.from * 1e6,
                self.to * 1e6
            )
        } else {
            format!("{} from {:.1} us on", self.kind.name(), self.from * 1e6)
        }
    }
}

/// Parses `KIND[@FROM[..TO]]` (seconds; FROM defaults to 0, TO to the end of the run).
pub fn parse_fault(s: &str) -> Result<FaultSpec> {
    let names: Vec<&str> = FAULT_KINDS.iter().map(|(_, n)| *n).collect();
    let bad = |m: String| Error::option("--fault", m);
    let (name, when) = match s.split_once('@') {
        Some((n, w)) => (n, Some(w)),
        None => (s, None),
    };
    let kind = FAULT_KINDS
        .iter()
        .find(|(_, n)| *n == name)
        .map(|(k, _)| *k)
        .ok_or_else(|| {
            bad(format!(
                "`{s}`: unknown fault `{name}`; allowed KIND[@FROM[..TO]] (seconds) with KIND one of {}",
                names.join(", ")
            ))
        })?;
    let num = |t: &str, what: &str| -> Result<f64> {
        t.trim().parse::<f64>().map_err(|e| {
            bad(format!(
                "`{s}`: {what} `{t}`: {e}; allowed seconds, e.g. {name}@0.5e-3..1e-3"
            ))
        })
    };
    let (from, to) = match when {
        None => (0.0, f64::INFINITY),
        Some(w) => match w.split_once("..") {
            Some((a, b)) => (num(a, "start")?, num(b, "end")?),
            None => (num(w, "start")?, f64::INFINITY),
        },
    };
    Ok(FaultSpec { kind, from, to })
}

/// Checks the faults of `o`: each window within the run (0 <= FROM < TO, FROM finite and
/// before the end), each kind at most once.
pub fn validate_faults(faults: &[FaultSpec], duration_s: f64) -> Result<()> {
    for (i, f) in faults.iter().enumerate() {
        let name = f.kind.name();
        if !(f.from.is_finite() && f.from >= 0.0 && f.from < duration_s) {
            return Err(Error::option(
                "--fault",
                format!(
                    "{name}@{}: allowed a start of 0 <= seconds < the run's --duration ({duration_s} s)",
                    f.from
                ),
            ));
        }
        if f.to.is_nan() || f.to <= f.from {
            return Err(Error::option(
                "--fault",
                format!(
                    "{name}@{}..{}: allowed an end after the start (or none: to the end of the run)",
                    f.from, f.to
                ),
            ));
        }
        if faults[..i].iter().any(|g| g.kind == f.kind) {
            return Err(Error::option(
                "--fault",
                format!("{name} given twice: allowed once per kind"),
            ));
        }
    }
    Ok(())
}

/// Puts `faults` into the encoder model (before the loop is built) ...
pub fn apply_to_encoder(loaded: &Loaded, o: &SimOptions, e: &mut EncoderModel) {
    use crate::sim::encoder::TrackFault;
    for f in &o.faults {
        let (from, to) = (f.from, f.to);
        match f.kind {
            FaultKind::Los => e.track_faults.push(TrackFault::Amplitude {
                from,
                to,
                factor: LOS_FACTOR,
            }),
            FaultKind::Clip => e.track_faults.push(TrackFault::Amplitude {
                from,
                to,
                factor: CLIP_FULL_SCALES / o.amplitude,
            }),
            FaultKind::BrokenWire => e.track_faults.push(TrackFault::SinAtZero { from, to }),
            FaultKind::Overspeed => {
                let dir = if o.profile.rpm(from) < 0.0 { -1.0 } else { 1.0 };
                let rpm = dir * OVERSPEED_FACTOR * loaded.derived.max_speed_rpm_full_res;
                e.excursion = Some((from, to, rpm));
            }
            FaultKind::QepBStuck | FaultKind::AdcFrame | FaultKind::NoIndex => {}
        }
    }
}

/// ... and into the loop (comparators, ADC data lines).
pub fn apply_to_system(o: &SimOptions, sys: &mut System) {
    for f in &o.faults {
        match f.kind {
            FaultKind::QepBStuck => sys.qep_b_stuck_low(f.from, f.to),
            FaultKind::AdcFrame => sys.sdo_stuck(f.from, f.to, true),
            FaultKind::NoIndex => sys.no_index(f.from, f.to),
            _ => {}
        }
    }
}
