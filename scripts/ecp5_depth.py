#!/usr/bin/env python3
"""Modelled register-to-register delays of a synth_ecp5 netlist, grouped by start and end
register: a quick way to list every path that may become critical after place and route,
where nextpnr names only the worst one (docs/timing.md).

    scripts/ecp5_depth.py NETLIST.json TOP [THRESHOLD_NS]

NETLIST.json is Yosys's `synth_ecp5 -json` output (scripts/ecp5_fmax.sh leaves TOP.json in
its directory). Prints, worst first, each (start register, end register, flip-flop pin)
group whose modelled delay exceeds THRESHOLD_NS (default 5.3), with its LUT levels, carry
cells and the number of flip-flop bits in the group.

Model (ns, ECP5 speed 6, from the nextpnr reports of docs/timing.md): clock-to-out 0.52,
0.9 of routing into every LUT, carry-chain entry and flip-flop input, 0.24 per LUT4, 0.25
per PFUMX/L6MUX21, 0.45 to enter a carry chain, 0.06 per CCU2C along it, 0.35 for its sum,
0.1 set-up. It ranks paths; it is not a timing figure (placement adds or removes 1-2 ns
of routing). Written by hand: Yosys's `sta` does not know ECP5 cell delays, and nextpnr
reports one path per clock.
"""
import json
import sys
from collections import defaultdict

ROUTE, LUT, CLKQ, SETUP = 0.9, 0.24, 0.52, 0.1
MUX, CARRY_IN, CARRY_STEP, SUM = 0.25, 0.45, 0.06, 0.35
NONE = (0.0, "const/port", 0, 0)


def main():
    netlist = json.load(open(sys.argv[1]))
    mod = netlist["modules"][sys.argv[2]]
    thr = float(sys.argv[3]) if len(sys.argv) > 3 else 5.3
    names = {}
    for n, v in mod["netnames"].items():
        for i, b in enumerate(v["bits"]):
            if isinstance(b, int):
                cand = f"{n}[{i}]"
                old = names.get(b)
                if old is None or (old.startswith("$") and not n.startswith("$")):
                    names[b] = cand
    cells = mod["cells"]
    drivers = {}
    for cn, c in cells.items():
        for p, dirn in c.get("port_directions", {}).items():
            if dirn == "output":
                for b in c["connections"][p]:
                    if isinstance(b, int):
                        drivers[b] = (cn, p)
    memo = {}

    def arr(bit):
        """(arrival ns, start register, LUT levels, carry cells) at a net bit."""
        if not isinstance(bit, int) or bit not in drivers:
            return NONE
        if bit in memo:
            return memo[bit]
        memo[bit] = NONE  # breaks combinational loops (there should be none)
        cn, p = drivers[bit]
        c = cells[cn]
        t, conn = c["type"], c["connections"]
        if t == "TRELLIS_FF":
            r = (CLKQ, names.get(bit, cn), 0, 0)
        elif t == "LUT4":
            ins = [arr(conn[i][0]) for i in "ABCD" if conn.get(i)]
            b = max(ins, default=NONE)
            r = (b[0] + ROUTE + LUT, b[1], b[2] + 1, b[3])
        elif t in ("PFUMX", "L6MUX21"):
            ins = []
            for i in ("ALUT", "BLUT", "D0", "D1"):
                if i in conn:
                    a = arr(conn[i][0])  # from the LUTs beside it: no routing
                    ins.append((a[0] + MUX, a[1], a[2], a[3]))
            sd = arr(conn["C0" if "C0" in conn else "SD"][0])
            ins.append((sd[0] + ROUTE + MUX, sd[1], sd[2] + 1, sd[3]))
            r = max(ins)
        elif t == "CCU2C":
            ins = []
            for i in ("A0", "B0", "C0", "D0", "A1", "B1", "C1", "D1"):
                b = conn[i][0]
                if isinstance(b, int) and b in drivers:
                    a = arr(b)
                    ins.append((a[0] + ROUTE + CARRY_IN, a[1], a[2], a[3] + 1))
            if conn.get("CIN") and conn["CIN"][0] in drivers:
                a = arr(conn["CIN"][0])
                ins.append((a[0] + CARRY_STEP, a[1], a[2], a[3] + 1))
            b = max(ins, default=NONE)
            r = (b[0] + SUM, b[1], b[2], b[3]) if p.startswith("S") else b
        else:
            r = (0.0, "other:" + t, 0, 0)
        memo[bit] = r
        return r

    sys.setrecursionlimit(1000000)
    groups = defaultdict(list)
    for cn, c in cells.items():
        if c["type"] != "TRELLIS_FF":
            continue
        q = c["connections"]["Q"][0]
        for pin in ("DI", "CE", "LSR"):
            b = c["connections"].get(pin, [None])[0]
            if isinstance(b, int) and b in drivers:
                a = arr(b)
                delay = a[0] + ROUTE + SETUP
                if delay > thr:
                    key = (a[1].split("[")[0], names.get(q, cn).split("[")[0], pin)
                    groups[key].append((delay, a[2], a[3]))
    rows = sorted(groups.items(), key=lambda kv: -max(kv[1])[0])
    for (start, end, pin), es in rows:
        w = max(es)
        print(f"{w[0]:5.2f} ns  luts {w[1]} carry {w[2]:2d}  x{len(es):3d}  {start} -> {end}.{pin}")


if __name__ == "__main__":
    main()
