#!/usr/bin/env python3
"""Deterministic generator of large CAM-style OSP part programs (3D surfacing).

The output looks like what a CAM post-processor writes for a mould or die: a
tape header, one main program, tool changes with comments, long runs of short
G1 X Y Z F moves along a raster of a bumpy surface, G0 retracts and
repositioning, a drilling cycle, a few shop-macro calls, M30 and the trailer.
The program is lint-clean with the examples' catalog (examples/osplint.toml)
and with the built-in one, so that a benchmark measures the work on every
block and not the printing of findings.

    gen_cam.py --size-mb 100 --seed 1 --output /tmp/CAM100.MIN

With --sequence-numbers every block gets a sequence number (N10, N20, ...),
as some posts write them. The same arguments always give the same bytes.
"""
import argparse
import math
import random
import sys


def fmt(v):
    """A coordinate as posts print them: 3 decimals, no trailing zeros, a point."""
    s = "%.3f" % v
    s = s.rstrip("0")
    if s.startswith("-0."):
        s = "-" + s[2:]
    elif s.startswith("0."):
        s = s[1:]
    if s in ("-.", "."):
        s = "0"
    return s


class Writer:
    def __init__(self, out, limit, numbered=False):
        self.out = out
        self.limit = limit
        self.size = 0
        self.buf = []
        self.buf_size = 0
        self.numbered = numbered
        self.number = 0

    def line(self, s):
        if self.numbered and not s.startswith(("%", "O", "(")):
            self.number += 10
            s = "N%d %s" % (self.number, s)
        s += "\n"
        self.buf.append(s)
        self.buf_size += len(s)
        self.size += len(s)
        if self.buf_size > 1 << 20:
            self.flush()

    def flush(self):
        self.out.write("".join(self.buf))
        self.buf = []
        self.buf_size = 0

    def full(self, reserve):
        return self.size + reserve >= self.limit


TOOLS = [
    (1, "D16 BULL NOSE R2 - ROUGHING", 6000, 2500),
    (2, "D10 BALL - SEMI FINISHING", 9000, 2000),
    (3, "D6 BALL - FINISHING", 12000, 1800),
    (4, "D4 BALL - REST MACHINING", 15000, 1200),
]


def surface(x, y, phase):
    return -2.0 - 1.5 * math.sin(x / 17.0 + phase) * math.cos(y / 23.0) - 0.004 * (x * x + y * y) / 10.0


def tool_change(w, rng, tool, first):
    number, text, speed, feed = tool
    w.line("(T%d %s)" % (number, text))
    w.line("T%d M6" % number)
    w.line("G0 G90 X-60. Y-40.")
    w.line("G56 Z50. H%d" % number)
    w.line("S%d M3" % speed)
    w.line("M8")


def raster(w, rng, tool, phase, reserve):
    """One surfacing pass: zig-zag rows of short G1 moves until the size limit."""
    number, text, speed, feed = tool
    step = 0.25 + 0.05 * rng.randint(0, 3)
    y = -40.0
    x0, x1 = -60.0, 60.0
    w.line("G0 Z5.")
    z = surface(x0, y, phase)
    w.line("G1 Z%s F%d" % (fmt(z), feed // 2))
    first = True
    direction = 1
    rows = 0
    while y <= 40.0 and not w.full(reserve):
        xs = x0 if direction > 0 else x1
        xe = x1 if direction > 0 else x0
        n = int((xe - xs) / step * direction)
        for k in range(1, n + 1):
            x = xs + direction * k * step
            z = surface(x, y, phase) + rng.uniform(-0.002, 0.002)
            if first:
                w.line("G1 X%s Y%s Z%s F%d" % (fmt(x), fmt(y), fmt(z), feed))
                first = False
            elif k % 97 == 0:
                w.line("X%s Z%s F%d" % (fmt(x), fmt(z), feed))
            else:
                w.line("X%s Y%s Z%s" % (fmt(x), fmt(y), fmt(z)))
        rows += 1
        y += 1.2
        direction = -direction
        if rows % 25 == 0:
            # Lift, comment and come back down (a new region of the surface).
            w.line("G0 Z5.")
            w.line("(REGION %d)" % (rows // 25))
            w.line("G0 X%s Y%s" % (fmt(xe), fmt(y)))
            w.line("G1 Z%s F%d" % (fmt(surface(xe, y, phase)), feed // 2))
            first = True
        else:
            w.line("Y%s" % fmt(y))
    w.line("G0 Z50.")


def drilling(w):
    w.line("(T5 D8.5 DRILL - 4 HOLES)")
    w.line("T5 M6")
    w.line("G0 G90 X-50. Y-30.")
    w.line("G56 Z50. H5")
    w.line("S1800 M3")
    w.line("M8")
    w.line("G99")
    w.line("G81 Z-20. R3. F250")
    w.line("X50. Y-30.")
    w.line("X50. Y30.")
    w.line("X-50. Y30.")
    w.line("G80")
    w.line("G0 Z100. M9")
    w.line("M5")


def keyway(w):
    w.line("(T6 D8 END MILL - KEY SLOTS WITH THE SHOP MACRO)")
    w.line("T6 M6")
    w.line("G0 X0 Y0")
    w.line("G56 Z50. H6")
    w.line("S3000 M3")
    w.line("M8")
    w.line("CALL OKYOY PX=-50. PY=-30. PR=2. PZ=-5. PI=30. PJ=-10. PD=6 PF=250 PFA=80 PS=3000")
    w.line("CALL OKYOY PX=50. PY=-30. PR=2. PZ=-5. PI=30. PJ=-10. PD=6 PF=250 PFA=80 PS=3000")
    w.line("G0 Z100. M9")
    w.line("M5")


def generate(size, seed, out, numbered=False):
    rng = random.Random(seed)
    w = Writer(out, size, numbered)
    w.line("%")
    w.line("O8800 (MOULD CAVITY 8800 - 3D SURFACING)")
    w.line("(POST: GENERIC OSP-P300M  UNITS MM)")
    w.line("(STOCK 130 X 90 X 30  TOP OF STOCK Z0)")
    w.line("G15 H1")
    drilling(w)
    keyway(w)
    reserve = 400  # the end of the program
    tool_index = 0
    phase = 0.0
    while not w.full(reserve):
        tool = TOOLS[tool_index % len(TOOLS)]
        tool_change(w, rng, tool, tool_index == 0)
        raster(w, rng, tool, phase, reserve)
        w.line("M9")
        w.line("M5")
        tool_index += 1
        phase += 0.7
    w.line("G0 Z100.")
    w.line("G30 P1")
    w.line("M30")
    w.line("%")
    w.flush()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size-mb", type=float, default=1.0, help="approximate size in MB (10^6 bytes)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--output", default="-")
    ap.add_argument("--sequence-numbers", action="store_true", help="N10, N20, ... on every block")
    args = ap.parse_args()
    size = int(args.size_mb * 1000 * 1000)
    if args.output == "-":
        generate(size, args.seed, sys.stdout, args.sequence_numbers)
    else:
        with open(args.output, "w", newline="\n") as f:
            generate(size, args.seed, f, args.sequence_numbers)


if __name__ == "__main__":
    main()
