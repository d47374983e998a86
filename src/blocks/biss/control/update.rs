//! The logic of [`BissControl`] (`super`), in named stages.
use super::*;

// The control channel's logic in named stages, run in this order (`logic_stages!`).
crate::blocks::logic_stages!(BissControl: Sampler, StepTable, ReadWrite, Crc4);

/// The CDM sampler and the CRC register's action.
impl stages::Sampler for BissControl {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, armed, stp, bq, q_idle, q_cts, q_id, q_adr, q_crc, q_rb, q_wb, q_start,
            q_read, q_write, q_stop, q_next, zcnt, n, crc, bad, addr, rb, wr, sh, cds_r, nadr_r,
            awr, nwr, zend, zfull, n2, n3, n6, n11, nhi, kupd, kshf, rdl, rdh, kclr, sread, uupd,
            ufb, ushf, uclr, ans1, ans0, idle1, idle0, start1, start0, read1, read0, write1,
            write0, stop1, stop0, bad1, bad0, nclr1, nclr0, ninc1, ninc0, rdsh, wrsh, stwe, ldq,
            rdq
        );
        self.regs.clock.next = self.clk.val();
        self.regs.address.next = self.addr.q.val();
        self.regs.write_data.next = self.sh.q.val();
        // A complete frame arms the sampler; the end of its timeout takes one CDM bit.
        if self.done.val() {
            self.armed.d.next = true;
        }
        self.stp.d.next = self.expire.val() & self.armed.q.val();
        if self.expire.val() {
            self.armed.d.next = false;
        }
        self.bq.d.next = !self.ma.val();
        self.b.next = self.bq.q.val();
        self.zk.next = !self.b.val() & self.zend.q.val();
        self.c3.next = (self.crc.q.val() & self.msb4.val()).any();
        self.nadr.next = self.addr.q.val() + self.one7.val();
        self.nadr_r.d.next = self.nadr.val();
        self.awr.d.next = self.addr.q.val() < self.ro7.val();
        self.nwr.d.next = self.nadr.val() < self.ro7.val();
        self.zend.d.next = (self.zcnt.q.val() == self.thirteen4.val())
            | (self.zcnt.q.val() == self.fourteen4.val());
        self.zfull.d.next = self.zcnt.q.val() == self.fourteen4.val();
        self.n2.d.next = self.n.q.val() == self.two4.val();
        self.n3.d.next = self.n.q.val() == self.three4.val();
        self.n6.d.next = self.n.q.val() == self.six4.val();
        self.n11.d.next = self.n.q.val() == self.eleven4.val();
        self.nhi.d.next = (self.n.q.val() & self.msb4.val()).any();
        // The CRC register's action at a step, from the state flags above (the step's case
        // analysis below leaves the CRC alone): the same action the step took before, now
        // one clock later.
        self.kupd.d.next = self.q_cts.q.val()
            | self.q_id.q.val()
            | self.q_adr.q.val()
            | (self.q_write.q.val() & !(self.n.q.val() & self.msb4.val()).any());
        self.kshf.d.next =
            self.q_crc.q.val() | (self.q_write.q.val() & (self.n.q.val() & self.msb4.val()).any());
        self.rdl.d.next = self.q_read.q.val() & !(self.n.q.val() & self.msb4.val()).any();
        self.rdh.d.next = self.q_read.q.val() & (self.n.q.val() & self.msb4.val()).any();
        self.sread.d.next = self.q_read.q.val();
        self.kclr.d.next = (self.q_idle.q.val() & self.zfull.q.val())
            | self.q_start.q.val()
            | (self.q_next.q.val() & (!self.wr.q.val() | self.nwr.q.val()));
        self.uupd.d.next =
            self.stp.q.val() & (self.kupd.q.val() | (self.rdl.q.val() & !self.b.val()));
        self.ushf.d.next =
            self.stp.q.val() & (self.kshf.q.val() | (self.rdh.q.val() & !self.b.val()));
        self.uclr.d.next = self.stp.q.val() & self.kclr.q.val() & self.b.val();
        self.dbit.next = (self.sh.q.val() & self.msb8.val()).any();
        self.ufb.d.next = self.b.val() ^ self.c3.val();
        if self.sread.q.val() {
            self.ufb.d.next = self.dbit.val() ^ self.c3.val();
        }
    }
}

/// The step's table, the next state, bad and the bit count.
impl stages::StepTable for BissControl {
    #[hdl_gen]
    fn update(&mut self) {
        // The step's table (docs/biss_control.md), precomputed for b = 1 and b = 0 from the
        // state flags and the registered decodes (all stable between steps).
        // The answer: Idle at 14 zeros, R without error, W accepted, start bits, a read's
        // data and CRC bits, a write's echoed data and CRC bits.
        self.ans1.d.next = (self.q_idle.q.val() & self.zfull.q.val())
            | (self.q_rb.q.val() & !self.bad.q.val())
            | (self.q_wb.q.val() & !self.bad.q.val() & !self.rb.q.val() & self.awr.q.val())
            | self.q_start.q.val()
            | (self.q_next.q.val() & (!self.wr.q.val() | self.nwr.q.val()))
            | (self.q_write.q.val() & (!self.nhi.q.val() | !self.c3.val()));
        self.ans0.d.next = (self.q_read.q.val() & self.nhi.q.val() & !self.c3.val())
            | (self.q_read.q.val() & !self.nhi.q.val() & self.dbit.val())
            | (self.q_write.q.val() & self.nhi.q.val() & !self.c3.val());
        // The next state where several states lead to it.
        self.idle1.d.next = (self.q_idle.q.val() & !self.zfull.q.val())
            | (self.q_wb.q.val() & !(!self.bad.q.val() & !self.rb.q.val() & self.awr.q.val()))
            | self.q_read.q.val()
            | self.q_stop.q.val()
            | (self.q_next.q.val() & self.wr.q.val() & !self.nwr.q.val());
        self.idle0.d.next = self.q_idle.q.val()
            | (self.q_wb.q.val() & !(!self.bad.q.val() & self.rb.q.val()))
            | self.q_start.q.val()
            | self.q_next.q.val();
        self.start1.d.next =
            self.q_wb.q.val() & !self.bad.q.val() & !self.rb.q.val() & self.awr.q.val();
        self.start0.d.next = self.q_wb.q.val() & !self.bad.q.val() & self.rb.q.val();
        self.read1.d.next = (self.q_start.q.val() | self.q_next.q.val()) & !self.wr.q.val();
        self.read0.d.next = self.q_read.q.val() & !self.n11.q.val();
        self.write1.d.next = ((self.q_start.q.val() | (self.q_next.q.val() & self.nwr.q.val()))
            & self.wr.q.val())
            | (self.q_write.q.val() & !self.n11.q.val());
        self.write0.d.next = self.q_write.q.val() & !self.n11.q.val();
        self.stop1.d.next = self.q_write.q.val() & self.n11.q.val();
        self.stop0.d.next = (self.q_read.q.val() | self.q_write.q.val()) & self.n11.q.val();
        // bad: cleared by a frame's start (Idle at 14 zeros, a data part's start bit),
        // set by a wrong CTS, a set ID bit, a CRC4 mismatch.
        self.bad1.d.next = (self.bad.q.val()
            & !((self.q_idle.q.val() & self.zfull.q.val())
                | self.q_start.q.val()
                | (self.q_next.q.val() & (!self.wr.q.val() | self.nwr.q.val()))))
            | self.q_id.q.val()
            | ((self.q_crc.q.val() | (self.q_write.q.val() & self.nhi.q.val())) & self.c3.val());
        self.bad0.d.next = self.bad.q.val()
            | self.q_cts.q.val()
            | ((self.q_crc.q.val() | (self.q_write.q.val() & self.nhi.q.val())) & !self.c3.val());
        // The bit count: cleared on entering ID, address and a data part; counted in ID,
        // address, CRC4 and the data parts.
        self.nclr0.d.next = self.q_cts.q.val()
            | (self.q_id.q.val() & self.n2.q.val())
            | (self.q_adr.q.val() & self.n6.q.val());
        self.nclr1.d.next = self.q_cts.q.val()
            | (self.q_id.q.val() & self.n2.q.val())
            | (self.q_adr.q.val() & self.n6.q.val())
            | self.q_start.q.val()
            | (self.q_next.q.val() & (!self.wr.q.val() | self.nwr.q.val()));
        self.ninc1.d.next = (self.q_id.q.val() & !self.n2.q.val())
            | (self.q_adr.q.val() & !self.n6.q.val())
            | self.q_crc.q.val()
            | self.q_write.q.val();
        self.ninc0.d.next = (self.q_id.q.val() & !self.n2.q.val())
            | (self.q_adr.q.val() & !self.n6.q.val())
            | self.q_crc.q.val()
            | self.q_read.q.val()
            | self.q_write.q.val();
        self.rdsh.d.next = self.q_read.q.val() & !self.nhi.q.val();
        self.wrsh.d.next = self.q_write.q.val() & !self.nhi.q.val();
        self.stwe.d.next = self.q_stop.q.val() & self.wr.q.val() & !self.bad.q.val();
        self.we.next = false;
    }
}

/// The registered read and the step's actions.
impl stages::ReadWrite for BissControl {
    #[hdl_gen]
    fn update(&mut self) {
        // The registered read: until a read's first bit, the shift register holds the
        // register at addr (addr is stable from the clock after the step that set it, the
        // bank output from the clock after that, and steps are a frame apart, so sh holds
        // mem[addr] long before that bit's step).
        self.rdq.d.next = self.regs.read_data.val();
        // With the register map, 0x00..0x3F read its byte instead.
        for i in 0..self.k40.len() {
            if !(self.addr.q.val() & self.k40[i].val()).any() {
                self.rdq.d.next = self.ext_rdata.val();
            }
        }
        self.ldq.d.next =
            self.q_read.q.val() & (self.n.q.val() == self.zero4.val()) & !self.stp.q.val();
        if self.ldq.q.val() & !self.stp.q.val() {
            self.sh.d.next = self.rdq.q.val();
        }
        if self.stp.q.val() {
            // The state flags.
            self.q_cts.d.next = self.b.val() & self.q_idle.q.val() & self.zfull.q.val();
            self.q_id.d.next =
                (self.q_cts.q.val() | (self.q_id.q.val() & !self.n2.q.val())) & !self.zk.val();
            self.q_adr.d.next = ((self.q_id.q.val() & self.n2.q.val())
                | (self.q_adr.q.val() & !self.n6.q.val()))
                & !self.zk.val();
            self.q_crc.d.next = ((self.q_adr.q.val() & self.n6.q.val())
                | (self.q_crc.q.val() & !self.n3.q.val()))
                & !self.zk.val();
            self.q_rb.d.next = self.q_crc.q.val() & self.n3.q.val() & !self.zk.val();
            self.q_wb.d.next = self.q_rb.q.val() & !self.zk.val();
            self.q_next.d.next = !self.b.val() & self.q_stop.q.val() & !self.zend.q.val();
            if self.b.val() {
                self.q_idle.d.next = self.idle1.q.val();
                self.q_start.d.next = self.start1.q.val();
                self.q_read.d.next = self.read1.q.val();
                self.q_write.d.next = self.write1.q.val();
                self.q_stop.d.next = self.stop1.q.val();
                self.bad.d.next = self.bad1.q.val();
                self.cds_r.d.next = self.ans1.q.val();
                if self.nclr1.q.val() {
                    self.n.d.next = self.zero4.val();
                } else if self.ninc1.q.val() {
                    self.n.d.next = self.n.q.val() + self.one4.val();
                }
                // The zero run: 14 zeros end any control frame.
                self.zcnt.d.next = self.zero4.val();
            } else {
                self.q_idle.d.next = self.idle0.q.val() | self.zend.q.val();
                self.q_start.d.next = self.start0.q.val() & !self.zend.q.val();
                self.q_read.d.next = self.read0.q.val() & !self.zend.q.val();
                self.q_write.d.next = self.write0.q.val() & !self.zend.q.val();
                self.q_stop.d.next = self.stop0.q.val() & !self.zend.q.val();
                self.bad.d.next = self.bad0.q.val();
                self.cds_r.d.next = self.ans0.q.val() & !self.zend.q.val();
                if self.nclr0.q.val() {
                    self.n.d.next = self.zero4.val();
                } else if self.ninc0.q.val() {
                    self.n.d.next = self.n.q.val() + self.one4.val();
                }
                if !self.zfull.q.val() {
                    self.zcnt.d.next = self.zcnt.q.val() + self.one4.val();
                }
                self.we.next = self.stwe.q.val();
            }
            // R and W are taken in their states, the address bits in Adr (MSB first), the
            // next address at Next's start bit.
            if self.q_rb.q.val() {
                self.rb.d.next = self.b.val();
            }
            if self.q_wb.q.val() {
                self.wr.d.next = self.b.val();
            }
            if self.q_adr.q.val() {
                if self.b.val() {
                    self.addr.d.next = (self.addr.q.val() << self.one7.val()) | self.one7.val();
                } else {
                    self.addr.d.next = self.addr.q.val() << self.one7.val();
                }
            }
            if self.q_next.q.val() & self.b.val() {
                self.addr.d.next = self.nadr_r.q.val();
            }
            // A read's data bits shift out (its answer is the MSB), a write's shift in.
            if self.rdsh.q.val() & !self.b.val() {
                self.sh.d.next = self.sh.q.val() << self.one8.val();
            }
            if self.wrsh.q.val() {
                if self.b.val() {
                    self.sh.d.next = (self.sh.q.val() << self.one8.val()) | self.one8.val();
                } else {
                    self.sh.d.next = self.sh.q.val() << self.one8.val();
                }
            }
        }
    }
}

/// The serial CRC4.
impl stages::Crc4 for BissControl {
    #[hdl_gen]
    fn update(&mut self) {
        // Serial CRC4 (taps x + 1), one clock after the step that decided it.
        if self.uupd.q.val() {
            if self.ufb.q.val() {
                self.crc.d.next = (self.crc.q.val() << self.one4.val()) ^ self.taps4.val();
            } else {
                self.crc.d.next = self.crc.q.val() << self.one4.val();
            }
        }
        if self.ushf.q.val() {
            self.crc.d.next = self.crc.q.val() << self.one4.val();
        }
        if self.uclr.q.val() {
            self.crc.d.next = self.zero4.val();
        }
        self.regs.write_enable.next = self.we.val();
        // The register map behind 0x00..0x3F: its byte replaces the file's in the read, a
        // write there goes to it too, and a read's start (ldq rising) is the snapshot pulse.
        self.ext_addr.next = bit_cast::<32, 7>(self.addr.q.val());
        self.ext_we.next = false;
        self.ext_wdata.next = self.sh.q.val();
        self.ext_snap.next = false;
        for i in 0..self.bank.len() {
            self.bank[i].clock.next = self.clk.val();
            self.snp[i].clock.next = self.clk.val();
            self.snp[i].d.next = self.ldq.q.val();
            self.bank[i].d.next = self.bank[i].q.val();
            if self.we.val() & (self.addr.q.val() == self.k40[i].val()) {
                self.bank[i].d.next = bit_cast::<32, 8>(self.sh.q.val());
            }
            self.ext_addr.next = (self.bank[i].q.val() << self.k6[i].val())
                | (bit_cast::<32, 7>(self.addr.q.val()) & self.k3f[i].val());
            self.ext_we.next = self.we.val() & !(self.addr.q.val() & self.k40[i].val()).any();
            self.ext_snap.next = self.ldq.q.val() & !self.snp[i].q.val();
        }
        if self.rst.val() {
            self.armed.d.next = false;
            self.stp.d.next = false;
            self.q_idle.d.next = true;
            self.q_cts.d.next = false;
            self.q_id.d.next = false;
            self.q_adr.d.next = false;
            self.q_crc.d.next = false;
            self.q_rb.d.next = false;
            self.q_wb.d.next = false;
            self.q_start.d.next = false;
            self.q_read.d.next = false;
            self.q_write.d.next = false;
            self.q_stop.d.next = false;
            self.q_next.d.next = false;
            self.zcnt.d.next = self.zero4.val();
            self.cds_r.d.next = false;
            self.regs.write_enable.next = false;
        }
        self.cds.next = self.cds_r.q.val();
    }
}
