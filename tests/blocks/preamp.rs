//! LTC6912-1 set-up: the amplifier model decodes the configured gains from the pins, the
//! timing and the other bus devices' levels hold, invalid gains are rejected, a reset in the
//! middle of the transfer restarts it, the SCK hand-over to the ADC works with both chip
//! models on the shared line, and rust-hdl == Icarus == Verilator.
use crate::common;
use sinedec::blocks::adc::hdl::AdcController;
use sinedec::blocks::adc::AdcParams;
use sinedec::blocks::preamp::hdl::PreampSetup;
use sinedec::blocks::preamp::{PreampParams, GAINS};
use sinedec::blocks::sext;
use sinedec::cosim::step::{prepare, tick};
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::sim::ltc1407a::Ltc1407a;
use sinedec::sim::ltc6912::Ltc6912;
use sinedec::synth::{synthesize, Family};
use sinedec::verify::{block_traces, Simulators};

const F133: f64 = 133.33e6;
const F50: f64 = 50e6;

/// Output rows of the set-up (CosimBlock order: spi_sck, spi_mosi, amp_cs, amp_shdn,
/// dac_cs, dac_clr, spi_ss_b, sf_ce0, done) for input rows [rst, adc_sck], with the
/// amplifier model watching the pins.
fn run(p: &PreampParams, rows: &[Vec<u64>], amp: &mut Ltc6912) -> Vec<Vec<u64>> {
    let mut uut = PreampSetup::new(p);
    prepare(&mut uut).expect("settles");
    let mut outs = Vec::with_capacity(rows.len());
    for r in rows {
        uut.rst.next = r[0] != 0;
        uut.adc_sck.next = r[1] != 0;
        tick(&mut uut).expect("settles");
        let o = vec![
            uut.spi_sck.val() as u64,
            uut.spi_mosi.val() as u64,
            uut.amp_cs.val() as u64,
            uut.amp_shdn.val() as u64,
            uut.dac_cs.val() as u64,
            uut.dac_clr.val() as u64,
            uut.spi_ss_b.val() as u64,
            uut.sf_ce0.val() as u64,
            uut.done.val() as u64,
        ];
        amp.step(o[2] == 1, o[0] == 1, o[1] == 1, o[3] == 1);
        outs.push(o);
    }
    outs
}

/// Reset for `release` rows, then free running with a toggling adc_sck input.
fn rows(n: usize, release: usize, seed: u64) -> Vec<Vec<u64>> {
    let mut r = SplitMix64(seed);
    (0..n)
        .map(|k| vec![(k < release) as u64, r.next_u64() & 1])
        .collect()
}

#[test]
fn amplifier_model_decodes_every_gain_pair() {
    for clock in [F133, F50] {
        for (i, &a) in GAINS.iter().enumerate() {
            let b = GAINS[(i * 3 + 2) % GAINS.len()];
            let p = PreampParams::new(clock, a, b).expect("valid gains");
            let release = 4;
            let n = release + p.done_clocks() as usize + 60;
            let input = rows(n, release, i as u64);
            let mut amp = Ltc6912::new(clock);
            let outs = run(&p, &input, &mut amp);
            assert!(
                amp.violations().is_empty(),
                "{a}/{b}: {:?}",
                amp.violations()
            );
            assert_eq!(amp.transfers().len(), 1, "{a}/{b}: one transfer");
            let t = amp.transfers()[0];
            assert!(t.well_formed && t.bits == 8, "{t:?}");
            assert_eq!(amp.gains(), Some((a, b)), "{:.0} MHz", clock / 1e6);
            assert_eq!(t.word, p.word());
            // done rises when predicted and stays; then SPI_SCK is the ADC's SCK and the
            // amplifier stays deselected.
            let done_row = outs.iter().position(|o| o[8] == 1).expect("done");
            assert_eq!(done_row, release + p.done_clocks() as usize);
            for k in done_row..n {
                assert_eq!(outs[k][8], 1);
                assert_eq!(outs[k][0], input[k][1], "spi_sck follows adc_sck at {k}");
                assert_eq!(outs[k][2], 1, "amp_cs high");
                assert_eq!(outs[k][1], 0, "mosi idle");
            }
            for (k, o) in outs.iter().enumerate() {
                assert_eq!(&o[3..8], &[0, 1, 1, 1, 1], "bus devices held off at {k}");
                if k < done_row {
                    assert_eq!(o[8], 0);
                }
            }
            // SCK at most about 10 MHz: 8 rising edges spaced by 2 half periods >= 100 ns.
            assert!(p.sck_hz() <= 10e6, "{}", p.sck_hz());
        }
    }
}

#[test]
fn gain_word_is_b_nibble_first() {
    let p = PreampParams::new(F133, -1, -100).expect("valid");
    assert_eq!(p.word(), 0x71);
    let p = PreampParams::new(F133, -50, -2).expect("valid");
    assert_eq!(p.word(), 0x26);
    assert_eq!(
        PreampParams::new(F133, -1, -1)
            .expect("valid")
            .half_period_clocks,
        7
    );
    assert_eq!(
        PreampParams::new(F50, -1, -1)
            .expect("valid")
            .half_period_clocks,
        3
    );
    let slow = PreampParams::new(F133, -1, -1)
        .and_then(|p| p.with_max_sck_hz(1e6))
        .expect("valid");
    assert!(slow.sck_hz() <= 1e6 && slow.half_period_clocks == 67);
}

#[test]
fn invalid_gains_are_rejected_naming_the_allowed_set() {
    for (a, b, which) in [
        (-3, -1, "A"),
        (0, -1, "A"),
        (1, -1, "A"),
        (-1, -200, "B"),
        (-1, 2, "B"),
    ] {
        let e = PreampParams::new(F133, a, b)
            .expect_err("invalid gain")
            .to_string();
        assert!(e.contains("-1, -2, -5, -10, -20, -50, -100"), "{e}");
        assert!(e.contains(&format!("gain {which}")), "{e}");
    }
    assert!(PreampParams::new(0.0, -1, -1).is_err());
    assert!(PreampParams::new(F133, -1, -1)
        .and_then(|p| p.with_max_sck_hz(-5.0))
        .is_err());
}

#[test]
fn reset_mid_transfer_restarts_it() {
    let p = PreampParams::new(F133, -5, -20).expect("valid");
    let h = p.half_period_clocks as usize;
    for cut in [h * 3, h * 5 + 1, h * 9 + 3, h * 16 + 2] {
        let n = 2 + cut + 2 + p.done_clocks() as usize + 30;
        let input: Vec<Vec<u64>> = (0..n)
            .map(|k| vec![(k < 2 || (k >= 2 + cut && k < 2 + cut + 2)) as u64, 0])
            .collect();
        let mut amp = Ltc6912::new(F133);
        let outs = run(&p, &input, &mut amp);
        let restart = 2 + cut + 2;
        // The interrupted transfer is flagged (fewer than 8 bits), the restarted one is good.
        assert!(
            amp.transfers().len() == 2,
            "cut {cut}: {:?}",
            amp.transfers()
        );
        assert!(!amp.transfers()[0].well_formed);
        assert!(amp.transfers()[1].well_formed);
        assert!(amp
            .violations()
            .iter()
            .all(|v| (v.clock as usize) < restart));
        assert_eq!(amp.gains(), Some((-5, -20)));
        let done_row = outs.iter().position(|o| o[8] == 1).expect("done");
        assert_eq!(done_row, restart + p.done_clocks() as usize);
    }
}

#[test]
fn amplifier_model_flags_malformed_transfers() {
    // Drive the model by hand: 7 bits, SCK high at the CS fall, too fast a clock.
    let mut amp = Ltc6912::new(F133);
    let mut pins = |cs: bool, sck: bool, mosi: bool, n: usize| {
        for _ in 0..n {
            amp.step(cs, sck, mosi, false);
        }
    };
    pins(true, false, false, 10);
    pins(false, false, true, 10);
    for _ in 0..7 {
        pins(false, true, true, 8);
        pins(false, false, true, 8);
    }
    pins(true, false, false, 10);
    pins(true, true, false, 10);
    pins(false, true, false, 10);
    pins(false, false, false, 2);
    pins(false, true, false, 2);
    pins(true, false, false, 10);
    let v: Vec<String> = amp.violations().iter().map(|v| v.message.clone()).collect();
    assert!(v.iter().any(|m| m.contains("7 SCK rising edges")), "{v:?}");
    assert!(v.iter().any(|m| m.contains("extra clock pulse")), "{v:?}");
    assert!(v.iter().any(|m| m.contains("SCK low")), "{v:?}");
    assert!(amp.transfers().iter().all(|t| !t.well_formed));
}

/// The top's wiring: adc.enable = preamp.done, preamp.adc_sck = adc.adc_sck, SPI_SCK =
/// preamp.spi_sck seen by both chips; the ADC delivers the voltages through the gains the
/// amplifier latched.
#[test]
fn preamp_then_adc_on_the_shared_sck() {
    let (ga, gb) = (-2, -10);
    let pp = PreampParams::new(F133, ga, gb).expect("valid");
    let ap = AdcParams::ltc1407a_fastest(F133).expect("feasible");
    let mut pre = PreampSetup::new(&pp);
    let mut adc = AdcController::new(&ap);
    prepare(&mut pre).expect("settles");
    prepare(&mut adc).expect("settles");
    let mut amp = Ltc6912::new(F133);
    // The ADC model sees the amplifier's gain through a shared cell, set once latched.
    let gains = std::rc::Rc::new(std::cell::Cell::new((0.0f64, 0.0f64)));
    let g2 = gains.clone();
    let mut chip = Ltc1407a::new(F133, 3).with_codes(move |_, t| {
        let (a, b) = g2.get();
        let w = 2.0 * std::f64::consts::PI * 50e3 * t;
        [
            Ltc1407a::code_from_voltage(1.65 + 0.1 * w.sin(), a),
            Ltc1407a::code_from_voltage(1.65 + 0.02 * w.cos(), b),
        ]
    });
    let (mut miso, mut done, mut adc_sck) = (false, false, false);
    let mut samples = Vec::new();
    let n = 3 + pp.done_clocks() as usize + ap.startup_clocks() as usize + 20 * 102;
    for k in 0..n {
        let rst = k < 3;
        pre.rst.next = rst;
        pre.adc_sck.next = adc_sck;
        adc.rst.next = rst;
        adc.enable.next = done;
        adc.adc_miso.next = miso;
        tick(&mut pre).expect("settles");
        tick(&mut adc).expect("settles");
        // The mux in the preamp block is combinational on adc_sck: settle it with the ADC's
        // SCK of this clock.
        adc_sck = adc.adc_sck.val();
        pre.adc_sck.next = adc_sck;
        pre.clk.next = rust_hdl::prelude::Clock::from(true);
        assert!(rust_hdl::prelude::simulate(&mut pre, 200));
        let spi_sck = pre.spi_sck.val();
        let cs = pre.amp_cs.val();
        amp.step(cs, spi_sck, pre.spi_mosi.val(), pre.amp_shdn.val());
        if let Some((a, b)) = amp.gains() {
            gains.set((a as f64, b as f64));
        }
        miso = chip.step(adc.adc_conv.val(), spi_sck);
        done = pre.done.val();
        if adc.out_valid.val() {
            samples.push((
                k,
                sext(adc.out_ch0.val().to_u64(), 14),
                sext(adc.out_ch1.val().to_u64(), 14),
            ));
        }
        if done {
            assert!(cs, "amplifier deselected once done");
        }
    }
    assert!(amp.violations().is_empty(), "{:?}", amp.violations());
    assert_eq!(amp.gains(), Some((ga, gb)));
    assert_eq!(amp.transfers().len(), 1);
    assert!(chip.violations().is_empty(), "{:?}", chip.violations());
    assert!(samples.len() >= 18, "{}", samples.len());
    let lat = ap.conv_to_valid_clocks() as usize;
    for &(row, a, b) in &samples {
        let c = chip
            .conversions()
            .iter()
            .find(|c| c.clock as usize + lat == row)
            .expect("conversion for every sample");
        assert_eq!([a, b], [c.codes[0] as i64, c.codes[1] as i64]);
    }
    // Gain -2 on 0.1 V amplitude: about 1311 LSB, inverted.
    let peak = samples.iter().map(|s| s.1.abs()).max().unwrap_or(0);
    assert!(peak > 1000 && peak <= 1311, "{peak}");
}

#[test]
fn cosim_preamp_with_resets() {
    let p = PreampParams::new(F133, -20, -1).expect("valid");
    let mut input = rows(3 * p.done_clocks() as usize, 3, 8);
    let h = p.half_period_clocks as usize;
    for row in input.iter_mut().skip(3 + h * 7 + 2).take(2) {
        row[0] = 1; // reset in the middle of the transfer
    }
    let mut amp = Ltc6912::new(F133);
    let outs = run(&p, &input, &mut amp);
    assert_eq!(amp.gains(), Some((-20, -1)));
    let dir = common::workdir("preamp_cosim");
    let t = block_traces(
        PreampSetup::new(&p),
        "preamp",
        "clk",
        &input,
        Simulators::ALL,
        &dir,
    )
    .expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
    assert_eq!(t.rust_hdl, outs);
    // 50 MHz, another gain pair, no mid-transfer reset.
    let p = PreampParams::new(F50, -100, -50).expect("valid");
    let input = rows(2 * p.done_clocks() as usize, 2, 9);
    let mut amp = Ltc6912::new(F50);
    let outs = run(&p, &input, &mut amp);
    assert_eq!(amp.gains(), Some((-100, -50)));
    let t = block_traces(
        PreampSetup::new(&p),
        "preamp50",
        "clk",
        &input,
        Simulators::ALL,
        &dir,
    )
    .expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
    assert_eq!(t.rust_hdl, outs);
}

#[test]
fn preamp_and_adc_synthesize_without_latches() {
    use rust_hdl::prelude::Block;
    let dir = common::workdir("adc_synth");
    let mut pre = PreampSetup::new(&PreampParams::new(F133, -1, -1).expect("valid"));
    pre.connect_all();
    let vp = sinedec::emit::verilog::export(&pre, "preamp", "sd_preamp").expect("export");
    let mut adc = AdcController::new(&AdcParams::ltc1407a_fastest(F133).expect("feasible"));
    adc.connect_all();
    let va = sinedec::emit::verilog::export(&adc, "adc", "sd_adc").expect("export");
    for fam in [Family::Xc3sa, Family::CycloneIve] {
        let s = synthesize(&vp, "sd_preamp", fam, &dir).expect("preamp synthesis");
        eprintln!("preamp {}: {} LUT, {} FF", fam.name(), s.luts, s.ffs);
        // hp, step, shift register, four pins, and the three flags registered with the
        // counters for timing (hp at its end, step done, next advance shifts).
        assert!(s.ffs <= 8 + 8 + 8 + 4 + 3, "{} FF", s.ffs);
        let s = synthesize(&va, "sd_adc", fam, &dir).expect("adc synthesis");
        eprintln!("adc {}: {} LUT, {} FF", fam.name(), s.luts, s.ffs);
        // pc 16 + ph 8 + cyc 8 + warm 4 + live + 2 x 16 shift + 2 x 16 out + 3 pins, the
        // delayed adc_miso and rst 2, the period-counter flags 2 and the six window flags
        // (SCK and capture windows kept with cyc and ph), and the stop / last-phase flags
        // of cyc and ph at most, and the three registered capture enables (the bit is
        // shifted in one clock after miso_d samples it).
        assert!(
            s.ffs <= 16 + 8 + 8 + 4 + 1 + 64 + 3 + 2 + 2 + 6 + 2 + 3,
            "{} FF",
            s.ffs
        );
    }
}
