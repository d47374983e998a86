//! Table 4-1 of the thesis by simulation on the bit-accurate velocity models
//! (`sim/velocity_table.rs`, `docs/velocity.md`):
//! `cargo run --release --example velocity_table`.
use sinedec::sim::velocity_table::{markdown, run, Setup};

fn main() -> anyhow::Result<()> {
    let s = Setup::thesis(200_000, 1);
    println!(
        "Table 4-1: {:.4} rpm ({:.4} 16-bit counts per 7.5 kHz sample), position noise \
         {:.3} counts rms, 16-bit truncation, {} updates\n",
        s.rpm,
        s.speed(),
        s.noise_lsb,
        s.updates
    );
    print!("{}", markdown(&run(&s)?, "16-bit counts per sample"));
    // The default configuration: F = 14 (27 bits per turn); decoder noise of 1 ADC LSB rms
    // at 14 bits and full amplitude: 2^14 / (pi / 2) / 8191 LSB of position.
    let noise = 16384.0 / std::f64::consts::FRAC_PI_2 / 8191.0;
    for rpm in [0.3, 3.0, 30.0] {
        let s = Setup {
            fine_bits: 14,
            ppr: 2048,
            rpm,
            noise_lsb: noise,
            updates: 100_000,
            seed: 2,
        };
        println!(
            "\nDefault configuration (F = 14) at {rpm} rpm: {:.3} LSB per period, noise {:.3} LSB rms\n",
            s.speed(),
            noise
        );
        print!(
            "{}",
            markdown(&run(&s)?, "position LSB (2^-27 turn) per period")
        );
    }
    Ok(())
}
