//! SSI and SPI slaves in `<name>_top` when enabled: an SSI master model reads the position
//! through the top end to end, the ports are exported, and the top with both slaves replays
//! bit-exactly in Icarus and Verilator.
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::sim::encoder::EncoderModel;
use sinedec::sim::serial_line::{FrameRequest, LineTiming};
use sinedec::sim::ssi_master::{SsiMaster, SsiMasterConfig, SsiOutcome};
use sinedec::sim::system::System;
use std::cell::RefCell;
use std::rc::Rc;

fn config() -> Loaded {
    let text = DEFAULT_CONFIG
        .replace(
            "[ssi]\n# SSI slave on ssi_clk/ssi_data, sending the BiSS data word (binary or Gray).\nenabled = false\ngray = false\ntimeout_us = 20.0",
            "[ssi]\nenabled = true\ngray = false\ntimeout_us = 2.0",
        )
        .replace(
            "enc_miso: the BiSS data word, then E and W.\nenabled = false",
            "enc_miso: the BiSS data word, then E and W.\nenabled = true",
        );
    let l = Loaded::parse(&text, "outputs").expect("config");
    assert!(
        l.derived.ssi.is_some() && l.derived.spi.is_some(),
        "both slaves enabled"
    );
    l
}

#[test]
fn ssi_master_reads_the_position_through_the_top() {
    let l = config();
    let d = &l.derived;
    let clock = d.clock_hz;
    let mut s = System::new(d, EncoderModel::ideal(2048, 1.0, 300.0)).expect("system");
    let timing = LineTiming {
        clock_hz: clock,
        line_delay_ns: 25.0,
    };
    let cfg = SsiMasterConfig::new(timing, d.biss.position_bits, 0);
    let reqs: Vec<FrameRequest> = (0..30).map(|_| FrameRequest::new(2e6).gap(300.0)).collect();
    let master = Rc::new(RefCell::new(SsiMaster::new(cfg, reqs, 15_000.0)));
    s.attach_ssi_master(Box::new(master.clone()));
    s.start().expect("settles");
    let drop = d.position_width - d.biss.position_bits;
    let mut words = vec![];
    for _ in 0..(100e-6 * clock) as u64 {
        s.run(1).expect("runs");
        let t = s.top().expect("rust-hdl top");
        words.push(((t.par_qc.val().to_u64() << d.fine_bits) | t.par_fine.val().to_u64()) >> drop);
    }
    let frames = master.borrow().frames().to_vec();
    assert!(frames.len() >= 3, "{} frames", frames.len());
    for f in &frames {
        let SsiOutcome::Data(g) = &f.outcome else {
            panic!("bad frame {f:?}")
        };
        let c0 = ((f.t_start_ns + 25.0) * clock / 1e9) as usize;
        let window = &words[c0.saturating_sub(1)..(c0 + 6).min(words.len())];
        assert!(
            window.contains(&g.position),
            "{} not in {:?}",
            g.position,
            window
        );
    }
}

#[test]
fn top_with_ssi_and_spi_replays_in_icarus_and_verilator() {
    use sinedec::blocks::top::hdl::TopRtl;
    use sinedec::cosim::CosimBlock;
    use sinedec::verify::{block_traces, Simulators};
    let l = config();
    let d = &l.derived;
    let mut s = System::new(d, EncoderModel::ideal(2048, 1.0, 3000.0)).expect("system");
    s.record_inputs();
    s.start().expect("settles");
    s.run(3000).expect("runs");
    let mut r = s.finish();
    // Clock the SPI slave and the SSI line in the replay: a 16-clock SCK under CS. The
    // columns are found by name.
    let top = TopRtl::new(d).expect("top");
    let ins = top.input_ports();
    let col = |n: &str| ins.iter().position(|p| p.name == n).expect("input");
    let (ssi_clk, enc_sck, enc_cs_n) = (col("ssi_clk"), col("enc_sck"), col("enc_cs_n"));
    for (k, row) in r.inputs.iter_mut().enumerate().skip(1500) {
        row[ssi_clk] = ((k / 20) % 2) as u64;
        row[enc_sck] = ((k / 8) % 2) as u64;
        row[enc_cs_n] = (k > 2800) as u64;
    }
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("outputs_top");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    assert!(top.output_ports().iter().any(|p| p.name == "ssi_data"));
    let t = block_traces(top, "sd_top_rtl", "clk", &r.inputs, Simulators::ALL, &dir)
        .expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
    // The SPI slave drove its output while selected.
    let oe = t
        .outputs
        .iter()
        .position(|p| p.name == "enc_miso_oe")
        .expect("port");
    assert!(t.rust_hdl.iter().any(|row| row[oe] == 1));
}
