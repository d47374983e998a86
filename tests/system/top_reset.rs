//! `<name>_top`'s reset in Icarus: `rst` is asynchronous (the wrapper's synchronizer,
//! `rtl-templates/top/rst_sync.v.j2`): the rtl's reset asserts without a clock edge, and the
//! blocks' reset registers (`TopRtl::rst_adc` ...) leave reset `TOP_RESET_RELEASE_CLOCKS`
//! edges after `rst` falls, the figure `check` prints; every reset register powers up
//! asserted.
use crate::common;
use sinedec::blocks::top::hdl::{RESET_SYNC_CLOCKS, TOP_RESET_RELEASE_CLOCKS};
use sinedec::config::Loaded;

#[test]
fn the_top_reset_asserts_at_once_and_releases_on_the_derived_edge() {
    for tool in ["iverilog", "vvp"] {
        if let Err(e) = sinedec::cosim::require_tool(tool) {
            panic!("{tool} is needed to simulate sd_top.v: {e}");
        }
    }
    let l = Loaded::default_config().expect("default config");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let dir = common::workdir("top_reset");
    let top = g
        .files
        .iter()
        .find(|f| f.name == "sd_top.v")
        .expect("sd_top.v");
    std::fs::write(dir.join("sd_top.v"), &top.text).expect("write sd_top.v");
    // The clock is driven by hand: edge k is the k-th rising edge after time 0; rst is low
    // from the start, so it "falls" before edge 1.
    let tb = format!(
        r#"`timescale 1ns/1ps
module tb;
    reg clk = 1'b0, rst = 1'b0;
    integer k, fails = 0, sync_at = 0, blocks_at = 0;
    sd_top uut (.clk(clk), .rst(rst));
    initial begin
        #1;
        if (uut.rst_sync !== 2'b11 || uut.rtl.rst_adc_q !== 1'b1 || uut.rtl.rst_core_q !== 1'b1)
            begin $display("FAIL reset not asserted at power-up"); fails = fails + 1; end
        for (k = 1; k <= 8; k = k + 1) begin
            #4 clk = 1'b1;
            #1 if (sync_at == 0 && uut.rst_sync[1] === 1'b0) sync_at = k;
            if (blocks_at == 0 && uut.rtl.rst_core_q === 1'b0 && uut.rtl.rst_adc_q === 1'b0
                && uut.rtl.rst_biss_q === 1'b0) blocks_at = k;
            #4 clk = 1'b0;
        end
        $display("synchronizer released at edge %0d, blocks at edge %0d", sync_at, blocks_at);
        if (sync_at != {sync}) begin $display("FAIL synchronizer"); fails = fails + 1; end
        if (blocks_at != {release}) begin $display("FAIL blocks"); fails = fails + 1; end
        // Asynchronous assertion: the clock is stopped (low) when rst rises.
        #3 rst = 1'b1;
        #1 if (uut.rst_sync[1] !== 1'b1)
            begin $display("FAIL no assertion without a clock edge"); fails = fails + 1; end
        if (uut.rtl.rst_core_q !== 1'b0)
            begin $display("FAIL the blocks took it before an edge"); fails = fails + 1; end
        #1 clk = 1'b1;
        #1 if (uut.rtl.rst_core_q !== 1'b1)
            begin $display("FAIL the blocks missed it at the next edge"); fails = fails + 1; end
        if (fails == 0) $display("PASS");
        $finish;
    end
endmodule
"#,
        sync = RESET_SYNC_CLOCKS,
        release = TOP_RESET_RELEASE_CLOCKS
    );
    std::fs::write(dir.join("tb.v"), tb).expect("write tb");
    let log = common::icarus_output(&dir, "tb", &["tb.v", "sd_top.v"]);
    assert!(log.contains("PASS") && !log.contains("FAIL"), "{log}");
    assert!(
        log.contains(&format!(
            "released at edge {RESET_SYNC_CLOCKS}, blocks at edge {TOP_RESET_RELEASE_CLOCKS}"
        )),
        "{log}"
    );
}
