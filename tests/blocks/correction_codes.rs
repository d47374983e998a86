//! The correction's writable codes (`blocks::correction::codes`, with `[registers]`): the
//! offsets, gains and cross code written through the load port are the ones the datapath
//! uses, checked against the documented formulas (x' = g (x - b) / 2^GF; the cos track with
//! phase (g_c d_c + k d_s) / 2^GF), byte writes change their lane only, reset restores the
//! configured values, and in mode peak a written value is a start value the calibration's
//! next update replaces (k stays 0). rust-hdl == model == Icarus == Verilator == engine on
//! the same clocks.
use crate::correction_util::{self, idle, reset, run, sample};
use sinedec::blocks::correction::codes::{phase_of, phase_word, WORDS};
use sinedec::blocks::correction::model::CorrectionIn;
use sinedec::blocks::correction::{gain_code, phase_codes, CorrectionParams, COS, SIN};
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::verify::Simulators;

const A: u32 = 14;
const GF: u32 = 14;

/// Static mode with gains 1.02 / 0.98, offsets 30 / -20 and a 2 degree phase error.
fn static_params() -> CorrectionParams {
    let gs = gain_code(GF, 1.02).expect("code");
    let (gc, k) = phase_codes(GF, 1.02, 0.98, 2.0).expect("codes");
    CorrectionParams::new(A, GF, [30, -20], [gs, gc])
        .and_then(|p| p.with_phase(k))
        .expect("params")
        .with_writable()
}

fn word(name: &str) -> usize {
    WORDS.iter().position(|w| *w == name).expect("word")
}

/// A write of `value` to word `name` with byte strobes `strb`.
fn load(name: &str, value: u32, strb: u32) -> CorrectionIn {
    let msk = (0..4)
        .filter(|b| strb >> b & 1 == 1)
        .fold(0u32, |m, b| m | 0xff << (8 * b));
    CorrectionIn {
        ld: 1 << word(name),
        ld_bits: value & msk,
        ld_msk: msk,
        ..CorrectionIn::default()
    }
}

/// The codes a test expects in use: offsets, gains, k.
#[derive(Clone, Copy, Debug)]
struct Codes {
    b: [i64; 2],
    g: [i64; 2],
    k: i64,
}

/// The corrected pair by the documented formulas, in f64 (round half up on the phase
/// track, half away from zero on the sine; exact ties do not occur in these streams).
fn expected(x: [i64; 2], c: &Codes) -> [i64; 2] {
    let s = correction_util::reference(x[SIN], c.b[SIN], c.g[SIN] as u32, A, GF);
    let (ds, dc) = ((x[SIN] - c.b[SIN]) as f64, (x[COS] - c.b[COS]) as f64);
    let v = (c.g[COS] as f64 * dc + c.k as f64 * ds) / (1u64 << GF) as f64;
    let lim = (1i64 << (A - 1)) as f64;
    [s, (v + 0.5).floor().clamp(-lim, lim - 1.0) as i64]
}

#[test]
fn written_codes_are_the_ones_the_datapath_uses_four_ways() {
    let p = static_params();
    // Static with writable codes: run-time products and a run-time phase stage.
    assert_eq!(p.latency_cycles(), 3 + 2 + 3);
    let cfg = p.reset_words();
    let mut codes = Codes {
        b: [30, -20],
        g: [cfg[2] as i64, cfg[3] as i64],
        k: phase_of(cfg[4]) as i64,
    };
    let mut r = SplitMix64(5);
    let mut ins = vec![reset(), reset()];
    // (first input index of the segment, the codes in use for its samples)
    let mut expect: Vec<([i64; 2], Codes)> = vec![];
    let lim = 1i64 << (A - 1);
    let mut samples = |ins: &mut Vec<CorrectionIn>, codes: Codes, n: usize, r: &mut SplitMix64| {
        for _ in 0..n {
            let x = [r.range(-lim, lim - 1), r.range(-lim, lim - 1)];
            ins.push(sample(x[SIN], x[COS]));
            ins.extend([idle(); 9]);
            expect.push((x, codes));
        }
    };
    samples(&mut ins, codes, 40, &mut r);
    // Whole-word writes of each code, then samples.
    let writes: [(&str, u32); 5] = [
        ("OFFSET_SIN", (-1234i32) as u32),
        ("OFFSET_COS", 777),
        ("GAIN_SIN", 0x5123),
        ("GAIN_COS", 0x3456),
        ("PHASE", phase_word(-2500)),
    ];
    for (name, v) in writes {
        ins.push(load(name, v, 0xf));
    }
    ins.extend([idle(); 3]);
    codes = Codes {
        b: [-1234, 777],
        g: [0x5123, 0x3456],
        k: -2500,
    };
    samples(&mut ins, codes, 60, &mut r);
    // Byte writes: GAIN_SIN's byte 1, OFFSET_COS's byte 0 (bits above A are dropped and
    // bit A-1 extends), PHASE's byte 2 (the sign) only.
    ins.push(load("GAIN_SIN", 0x0000_7700, 0b0010));
    ins.push(load("OFFSET_COS", 0xffff_ff80, 0b0001));
    ins.push(load("PHASE", 0x0000_0000, 0b0100));
    ins.extend([idle(); 3]);
    codes.g[SIN] = 0x7723;
    codes.b[COS] = 0x380; // 777 = 0x309: byte 0 becomes 0x80, 14-bit positive
    codes.k = 2500;
    samples(&mut ins, codes, 60, &mut r);
    // Out-of-range words: an offset's bits above A wrap into the A-bit range.
    ins.push(load("OFFSET_SIN", 0x0000_3fff, 0xf));
    ins.extend([idle(); 3]);
    codes.b[SIN] = -1;
    samples(&mut ins, codes, 30, &mut r);
    // Reset: the configured values again.
    ins.extend([reset(), idle()]);
    let after_reset = ins.len();
    samples(
        &mut ins,
        Codes {
            b: [30, -20],
            g: [cfg[2] as i64, cfg[3] as i64],
            k: phase_of(cfg[4]) as i64,
        },
        30,
        &mut r,
    );
    let t = run(&p, "codes_static", &ins, Simulators::ALL);
    // Outputs: valid, sin, cos, offsets, gains, cal_update, then the five words.
    let sx = |v: u64| sinedec::blocks::sext(v, A);
    let got: Vec<[i64; 2]> = t
        .iter()
        .filter(|row| row[0] == 1)
        .map(|row| [sx(row[1]), sx(row[2])])
        .collect();
    assert_eq!(got.len(), expect.len(), "one output per sample");
    for (k, ((x, c), g)) in expect.iter().zip(&got).enumerate() {
        assert_eq!(*g, expected(*x, c), "sample {k} {x:?} with {c:?}");
    }
    // The words the map reads: the last writes before the reset, the configured after.
    let words = |row: &Vec<u64>| -> Vec<u64> { row[8..13].to_vec() };
    let before = &t[after_reset - 3];
    assert_eq!(
        words(before),
        vec![0xffff_ffff, 0x380, 0x7723, 0x3456, 2500],
        "words before the reset"
    );
    assert_eq!(
        words(t.last().expect("rows")),
        cfg.map(u64::from).to_vec(),
        "words after the reset"
    );
}

/// Mode peak: a written offset and gain are used until the calibration's next update
/// replaces them with its own; PHASE reads 0 and a write to it changes nothing.
#[test]
fn in_peak_mode_a_written_code_is_a_start_value() {
    let full = (1u32 << (A - 1)) - 1;
    let p = CorrectionParams::identity(A, GF)
        .and_then(|p| p.with_auto(full * 3 / 4, 1, full / 10))
        .expect("params")
        .with_writable();
    let mut ins = vec![reset(), reset()];
    ins.push(load("OFFSET_SIN", 321, 0xf));
    ins.push(load("GAIN_COS", 0x6000, 0xf));
    ins.push(load("PHASE", 1000, 0xf));
    ins.extend([idle(); 4]);
    let written = ins.len();
    // Enough periods for a window and its division.
    ins.extend(correction_util::sinusoid(
        A,
        [4000.0, 4400.0],
        [150.0, -90.0],
        40.0,
        3,
        200,
        1.0,
        11,
    ));
    // Random loads mixed into random stimulus, for the four-way comparison.
    let mut r = SplitMix64(3);
    for x in correction_util::auto_stimulus(A, 12, 8) {
        if r.unit() < 0.01 {
            let w = WORDS[r.range(0, 4) as usize];
            ins.push(load(w, r.next_u64() as u32, r.range(1, 15) as u32));
        }
        ins.push(x);
    }
    let t = run(&p, "codes_peak", &ins, Simulators::ALL);
    let words = |row: &Vec<u64>| -> Vec<u64> { row[8..13].to_vec() };
    assert_eq!(
        words(&t[written]),
        vec![321, 0, 1 << GF, 0x6000, 0],
        "written values in use (PHASE 0 in mode peak)"
    );
    // The datapath uses them: offset and gain outputs.
    assert_eq!(t[written][3], 321);
    assert_eq!(t[written][6], 0x6000);
    let upd = t[written..]
        .iter()
        .position(|row| row[7] == 1)
        .expect("the calibration updates")
        + written;
    // A clock after the update the codes are the calibration's: the offset near 150.
    let w = words(&t[upd + 1]);
    let b = sinedec::blocks::sext(w[0], 32);
    assert!((140..=160).contains(&b), "offset after the update {b}");
    assert_ne!(w[3], 0x6000, "gain replaced");
    assert_eq!(w[4], 0, "PHASE stays 0");
}

/// Mode auto (the ellipse fit): a written offset and gain are used until the fit's next
/// update, after which the codes are the fit's (offsets near the stimulus's); the cross
/// code follows the fit too. rust-hdl == Icarus == Verilator == engine (the fit's own
/// model is `tests/blocks/correction_fit_rtl.rs`'s subject).
#[test]
fn in_auto_mode_a_written_code_is_replaced_by_the_fit() {
    let full = (1u32 << (A - 1)) - 1;
    let p = CorrectionParams::identity(A, GF)
        .and_then(|p| p.with_fit(full * 3 / 4, 1, full / 10, 16))
        .expect("params")
        .with_writable();
    let mut ins = vec![reset(), reset()];
    ins.push(load("OFFSET_SIN", 321, 0xf));
    ins.push(load("GAIN_COS", 0x6000, 0xf));
    ins.push(load("PHASE", phase_word(-99), 0xf));
    ins.extend([idle(); 4]);
    let written = ins.len();
    ins.extend(correction_util::sinusoid(
        A,
        [4000.0, 4400.0],
        [150.0, -90.0],
        40.0,
        3,
        2000,
        1.0,
        12,
    ));
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row_writable()).collect();
    let t = crate::common::simulators_agree(
        sinedec::blocks::correction::hdl::Correction::new(&p),
        "codes_fit",
        "codes_fit",
        &rows,
        Simulators::ALL,
    );
    let words = |row: &Vec<u64>| -> Vec<u64> { row[8..13].to_vec() };
    assert_eq!(
        words(&t[written]),
        vec![321, 0, 1 << GF, 0x6000, phase_word(-99) as u64],
        "written values in use"
    );
    let upd = t[written..]
        .iter()
        .position(|row| row[7] == 1)
        .expect("the fit updates")
        + written;
    let w = words(&t[upd + 1]);
    let b = [
        sinedec::blocks::sext(w[0], 32),
        sinedec::blocks::sext(w[1], 32),
    ];
    assert!(
        (140..=160).contains(&b[0]) && (-100..=-80).contains(&b[1]),
        "offsets after the update {b:?}"
    );
    assert_ne!(w[3], 0x6000, "gain replaced");
    assert_ne!(w[4], phase_word(-99) as u64, "cross code replaced");
    assert_eq!(words(&t[upd]), words(&t[written]), "until the update");
}

/// Static mode with writable codes synthesizes with no hard multiplier and at most one
/// carry chain on its worst register-to-register path (the timing rule's premise, as for
/// mode auto in `tests/blocks/correction_fit_rtl.rs`).
#[test]
fn writable_static_mode_synthesizes_without_multipliers_and_one_carry_chain_per_path() {
    use sinedec::blocks::correction::hdl::Correction;
    let p = static_params();
    let (x, c) = correction_util::synth(Correction::new(&p), "corr_synth_codes");
    let path = x.path.expect("a register-to-register path");
    eprintln!(
        "corr_synth_codes: xc3sa {} LUT, {} FF, {} MULT18X18; cycloneive {} LE, {} FF; worst path {} -> {}: {} carry chains, {} LUT levels",
        x.luts, x.ffs, x.multipliers, c.luts, c.ffs, path.from, path.to, path.carry_chains, path.lut_levels
    );
    assert_eq!(x.multipliers, 0);
    assert_eq!(c.multipliers, 0);
    assert!(path.carry_chains <= 1, "{path:?}");
}
