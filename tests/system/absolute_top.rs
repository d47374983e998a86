//! The absolute start in `<name>_top` (`[reference] absolute = "ssi"`), in the closed loop
//! with the encoder's sin/cos tracks, its SSI digital channel (`sim::ssi_encoder`, from the
//! data sheets), the ADC and the comparators.
//!
//! The expectations come from the encoder model, not from the block: once referenced, the
//! position on the parallel bus must be the encoder's true absolute position, turns
//! included (modulo the 2^12 turns both the word and the decoder count), to within the
//! decoder's own error, from every start: at and one LSB around a period boundary and a
//! quadrant boundary, inside periods, at rest and moving slowly both ways, with the
//! channel's alignment error up to the documented tolerance (docs/absolute.md). Beyond the
//! tolerance the period is off by one: the test can fail.
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::sim::encoder::{EncoderModel, Profile};
use sinedec::sim::system::{Record, SimResult, System};

/// The default config with the absolute start: a 25-bit Gray word (12 + 13 bits, one code
/// per quadrant at 2048 lines) at 1 MHz, plus `extra` in `[reference.ssi]`.
fn config(extra: &str) -> Loaded {
    let text = format!(
        "{DEFAULT_CONFIG}\n[reference]\nenabled = true\nabsolute = \"ssi\"\n\n[reference.ssi]\nmultiturn_bits = 12\nclock_hz = 1e6\n{extra}\n"
    );
    Loaded::parse(&text, "absolute_top.toml").expect("config")
}

/// Runs an ideal 2048-line encoder from `start` turns at `rpm` for `seconds` (rust-hdl),
/// with the digital channel's alignment error `e` quadrants.
fn run(l: &Loaded, start: f64, rpm: f64, e: f64, seconds: f64) -> SimResult {
    let d = &l.derived;
    let mut enc = EncoderModel::ideal(2048, 1.0, 0.0);
    enc.start_turns = start;
    enc.profile = Profile::Constant { rpm };
    let mut s = System::new(d, enc).expect("system");
    s.absolute_encoder_mut()
        .expect("the channel")
        .set_alignment_quadrants(e);
    s.start().expect("settles");
    s.run((seconds * d.clock_hz) as u64).expect("runs");
    s.finish()
}

/// |decoded - true| in fine LSB of a record, modulo 2^12 turns.
fn error_lsb(l: &Loaded, r: &Record) -> f64 {
    let d = &l.derived;
    let range = d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64 * 4096.0;
    let e = r.unwrapped as f64 - r.truth;
    (e - range * (e / range).round()).abs()
}

#[test]
fn explore() {
    let l = config("");
    let r = run(&l, 3.0 + 100.0 / 8192.0, 0.0, 0.0, 70e-6);
    let a = r.absolute.as_ref().expect("absolute");
    eprintln!("{:?}", a);
    let k = r.records.iter().position(|x| x.referenced);
    eprintln!("first referenced {k:?} of {}", r.records.len());
    for x in r
        .records
        .iter()
        .skip(k.unwrap_or(0).saturating_sub(2))
        .take(5)
    {
        eprintln!("{x:?} err {}", error_lsb(&l, x));
    }
}
