//! Writes the velocity block of every method at the default constants as `DIR/vel_<method>.v`
//! (module `vel_<method>`), for `scripts/ecp5_fmax.sh DIR vel_<method> 133.33`
//! (`docs/velocity.md`): `cargo run --example velocity_export -- DIR [CLOCK_HZ]`.
use sinedec::blocks::velocity::hdl::{Layout, Velocity};
use sinedec::blocks::velocity::{Method, VelocityParams, VelocitySpec};

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let dir = args
        .next()
        .ok_or_else(|| anyhow::anyhow!("usage: velocity_export DIR [CLOCK_HZ]"))?;
    let clock: f64 = match args.next() {
        Some(c) => c.parse()?,
        None => 133.33e6,
    };
    std::fs::create_dir_all(&dir)?;
    for m in [
        Method::DiffLpf,
        Method::Kalman,
        Method::Lsq,
        Method::Tracking,
    ] {
        let mut s = VelocitySpec::defaults(clock, 14, 4_997_175);
        s.method = m;
        let p = VelocityParams::new(&s)?;
        let l = Layout::new(&p)?;
        let name = format!("vel_{m}");
        let mut uut = Velocity::new(&p)?;
        rust_hdl::prelude::Block::connect_all(&mut uut);
        let v = sinedec::emit::verilog::export(&uut, &name, &name)?;
        std::fs::write(format!("{dir}/{name}.v"), v)?;
        println!(
            "{name}: {} x {} bits, {} Booth digits, latency {} clocks",
            l.a_width,
            l.b_width,
            l.mul_steps(),
            p.latency()
        );
    }
    Ok(())
}
