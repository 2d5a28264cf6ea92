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
    gen_cam.py --size-mb 100 --shape loops --output /tmp/LOOPS100.MIN

Shapes (--shape), from the easiest for a checker to the hardest:
  plain     the program above (the default).
  numbered  the same with a sequence number on every block (N10, N20, ...),
            as some posts write them; also --sequence-numbers.
  loops     a posted program with a few hundred user-macro loops: IF ... N..
            jumps back, GOTO forward, WHILE/DO ... END, counters in VC
            variables, G91 steps, sequence numbers that restart at every tool
            change (so names repeat), block delete, MODIN/MODOUT, fixed
            cycles, and subprograms after M30 called with CALL.
  travel    plain with every Z level 400 mm lower: with the Z stroke of
            examples/osplint.toml ([machine.travel] z = [-300.0, 150.0]) each
            block with a Z breaks the travel (OSP301), about 1,000,000
            findings per 20 MB. Without that setting it is clean.
  bigloop   plain with the whole main program inside one loop (N1 ... IF
            [VC1 LT 3] N1): the engine walks all of it at least twice.
  macros    a plate of features machined with the shop's macros only: back
            spotfaces (CALL OZAGR), burr removal (CALL OM100), key slots
            (CALL OKYOY), back counterbores as a modal call with a
            positioning block per hole (MODIN OG87N), tapping with G114 and
            M204: every block runs a macro and every rule reads its arguments.

Only the travel shape gives findings on purpose. In loops, the loops jump to
sequence names that repeat (N1, N2, ... again after each tool change): OSP006
warns about each such jump (folded, a few hundred in all), and OSP003, off by
default, would warn about every repeated name.
The same arguments always give the same bytes.
"""
import argparse
import math
import random
import sys

SHAPES = ("plain", "numbered", "loops", "travel", "bigloop", "macros")
TRAVEL_SHIFT = -400.0  # below the Z minimum -300 of examples/osplint.toml


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
    def __init__(self, out, limit, numbered=False, zshift=0.0):
        self.out = out
        self.limit = limit
        self.size = 0
        self.buf = []
        self.buf_size = 0
        self.numbered = numbered
        self.number = 0
        self.zshift = zshift

    def z(self, v):
        """A Z level (Z, R, PR, PZ) as printed: shifted for the travel shape.
        With no shift the text is fmt(v) exactly (v + 0.0 == v)."""
        return fmt(v + self.zshift)

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
    w.line("G56 Z%s H%d" % (w.z(50.0), number))
    w.line("S%d M3" % speed)
    w.line("M8")


def raster(w, rng, tool, phase, reserve):
    """One surfacing pass: zig-zag rows of short G1 moves until the size limit."""
    number, text, speed, feed = tool
    step = 0.25 + 0.05 * rng.randint(0, 3)
    y = -40.0
    x0, x1 = -60.0, 60.0
    w.line("G0 Z%s" % w.z(5.0))
    z = surface(x0, y, phase)
    w.line("G1 Z%s F%d" % (w.z(z), feed // 2))
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
                w.line("G1 X%s Y%s Z%s F%d" % (fmt(x), fmt(y), w.z(z), feed))
                first = False
            elif k % 97 == 0:
                w.line("X%s Z%s F%d" % (fmt(x), w.z(z), feed))
            else:
                w.line("X%s Y%s Z%s" % (fmt(x), fmt(y), w.z(z)))
        rows += 1
        y += 1.2
        direction = -direction
        if rows % 25 == 0:
            # Lift, comment and come back down (a new region of the surface).
            w.line("G0 Z%s" % w.z(5.0))
            w.line("(REGION %d)" % (rows // 25))
            w.line("G0 X%s Y%s" % (fmt(xe), fmt(y)))
            w.line("G1 Z%s F%d" % (w.z(surface(xe, y, phase)), feed // 2))
            first = True
        else:
            w.line("Y%s" % fmt(y))
    w.line("G0 Z%s" % w.z(50.0))


def drilling(w):
    w.line("(T5 D8.5 DRILL - 4 HOLES)")
    w.line("T5 M6")
    w.line("G0 G90 X-50. Y-30.")
    w.line("G56 Z%s H5" % w.z(50.0))
    w.line("S1800 M3")
    w.line("M8")
    w.line("G99")
    w.line("G81 Z%s R%s F250" % (w.z(-20.0), w.z(3.0)))
    w.line("X50. Y-30.")
    w.line("X50. Y30.")
    w.line("X-50. Y30.")
    w.line("G80")
    w.line("G0 Z%s M9" % w.z(100.0))
    w.line("M5")


def keyway(w):
    w.line("(T6 D8 END MILL - KEY SLOTS WITH THE SHOP MACRO)")
    w.line("T6 M6")
    w.line("G0 X0 Y0")
    w.line("G56 Z%s H6" % w.z(50.0))
    w.line("S3000 M3")
    w.line("M8")
    for px in ("-50.", "50."):
        w.line("CALL OKYOY PX=%s PY=-30. PR=%s PZ=%s PI=30. PJ=-10. PD=6 PF=250 PFA=80 PS=3000"
               % (px, w.z(2.0), w.z(-5.0)))
    w.line("G0 Z%s M9" % w.z(100.0))
    w.line("M5")


def generate(size, seed, out, numbered=False, zshift=0.0, bigloop=False):
    """plain, numbered, travel (zshift) and bigloop: the same tool paths."""
    rng = random.Random(seed)
    w = Writer(out, size, numbered, zshift)
    w.line("%")
    w.line("O8800 (MOULD CAVITY 8800 - 3D SURFACING)")
    w.line("(POST: GENERIC OSP-P300M  UNITS MM)")
    w.line("(STOCK 130 X 90 X 30  TOP OF STOCK Z0)")
    w.line("G15 H1")
    if bigloop:
        # The whole program three times (VC1 counts the runs): every block
        # is inside one loop whose head is the first block.
        w.line("VC1=0")
        w.line("N1 (ALL TOOL PATHS - RUN 3 TIMES)")
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
    if bigloop:
        w.line("VC1=VC1+1")
        w.line("IF [VC1 LT 3] N1")
    w.line("G0 Z%s" % w.z(100.0))
    w.line("G30 P1")
    w.line("M30")
    w.line("%")
    w.flush()


# --- The loops shape -------------------------------------------------------
#
# A post that writes user-macro logic into the program: the surfacing tools
# of TOOLS with a loop every so many bytes (repeated rest passes over a small
# patch, in the three forms OSP programs use), and between them short
# operations with a drill, a tap, a keyway cutter and a touch probe, each in
# a loop or a modal macro call. Sequence numbers restart at N1 with every
# tool change. The subprograms the probe and drill operations call follow
# the main program's M30; their sequence names (N1, NAGN, NNEXT, ...) are
# their own.

SUBPROGRAMS = """\
O9001 (PROBE ONE POINT AT VC21 VC22 - UP TO 3 TOUCHES, RESULT IN VC31)
G0 X=VC21 Y=VC22
G0 Z5.
VC13=0
NAGN VC13=VC13+1
G1 Z-2. F300
G0 Z5.
IF [VC31 NE 0] NNEXT
IF [VC13 LT 3] NAGN
VC31=-1 (NO TOUCH)
NNEXT G0 Z50.
RTS
O9002 (GRID OF VC24 X VC25 HOLES AT PITCH VC26 FROM VC21 VC22 - CYCLE SET BY THE CALLER)
VC14=0
WHILE [VC14 LT VC25] DO 1
VC15=0
WHILE [VC15 LT VC24] DO 2
X=VC21+VC15*VC26 Y=VC22+VC14*VC26
VC15=VC15+1
END 2
VC14=VC14+1
END 1
RTS
O9003 (SQUARE POCKET 10 X 10 AT THE CURRENT XY, VC27 STEPS OF 1. DEEP)
IF [VC27 GT 0] NCUT
GOTO NNEXT
NCUT VC16=0
G0 Z2.
DO 1
VC16=VC16+1
G1 Z=-VC16 F200
G91 X5. F600
Y5.
X-10.
Y-10.
X10.
Y5.
X-5.
G90
IF [VC16 GE VC27] NNEXT
END 1
NNEXT G0 Z5.
RTS
"""


class Surfacing:
    """Where the zig-zag raster of the current tool stands, kept across the
    loops written into it."""

    def __init__(self, rng, tool, phase):
        self.tool = tool
        self.phase = phase
        self.step = 0.25 + 0.05 * rng.randint(0, 3)
        self.y = -40.0
        self.direction = 1

    def rows(self, w, rng, until):
        """Whole rows until the file reaches `until` bytes; the tool is at Z5. before and after."""
        feed = self.tool[3]
        x0, x1 = -60.0, 60.0
        xs = x0 if self.direction > 0 else x1
        w.line("G0 X%s Y%s" % (fmt(xs), fmt(self.y)))
        w.line("G1 Z%s F%d" % (fmt(surface(xs, self.y, self.phase)), feed // 2))
        first = True
        while w.size < until:
            xe = x1 if self.direction > 0 else x0
            n = int((xe - xs) / self.step * self.direction)
            for k in range(1, n + 1):
                x = xs + self.direction * k * self.step
                z = surface(x, self.y, self.phase) + rng.uniform(-0.002, 0.002)
                if first:
                    w.line("G1 X%s Y%s Z%s F%d" % (fmt(x), fmt(self.y), fmt(z), feed))
                    first = False
                else:
                    w.line("X%s Y%s Z%s" % (fmt(x), fmt(self.y), fmt(z)))
            self.direction = -self.direction
            xs = xe
            self.y += 1.2
            if self.y > 40.0:  # the next pass over the surface
                self.y = -40.0
                self.phase += 0.05
                w.line("G0 Z5.")
                w.line("G0 X%s Y%s" % (fmt(xs), fmt(self.y)))
                w.line("G1 Z%s F%d" % (fmt(surface(xs, self.y, self.phase)), feed // 2))
            else:
                w.line("Y%s" % fmt(self.y))
        w.line("G0 Z5.")


class Numbers:
    """Sequence numbers of one operation: N1, N2, ... from N1 again at each tool change."""

    def __init__(self):
        self.n = 0

    def restart(self):
        self.n = 0

    def next(self):
        self.n += 1
        return "N%d" % self.n


def patch(w, rng, phase, feed, blocks, label=""):
    """A rest pass over a small patch of the surface: `blocks` blocks (the
    positioning, the plunge, zig-zag moves with a few G91 steps and their G90,
    the retract). `label` goes on the first block (a loop's jump target)."""
    cx = rng.randint(-45, 45)
    cy = rng.randint(-28, 28)
    step = 0.5
    x, y = float(cx), float(cy)
    w.line("%sG0 X%s Y%s" % (label + " " if label else "", fmt(x), fmt(y)))
    w.line("G1 Z%s F%d" % (fmt(surface(x, y, phase) + 0.2), feed // 2))
    left = blocks - 3  # the positioning, the plunge and the retract
    col = 0
    first = True
    while left > 0:
        if left >= 6 and rng.random() < 0.04:
            # A small incremental zig-zag, as posts write a pick-feed: G91 ... G90.
            w.line("G91 X%s Y%s" % (fmt(step), fmt(step / 2)))
            w.line("X%s" % fmt(-step))
            w.line("Y%s" % fmt(-step / 2))
            w.line("G90")
            left -= 4
            continue
        col += 1
        x = cx + step * (col % 16) * (1 if (col // 16) % 2 == 0 else -1)
        y = cy + step * (col // 16)
        z = surface(x, y, phase) + rng.uniform(-0.002, 0.002)
        if first:
            w.line("X%s Y%s Z%s F%d" % (fmt(x), fmt(y), fmt(z), feed))
            first = False
        else:
            w.line("X%s Y%s Z%s" % (fmt(x), fmt(y), fmt(z)))
        left -= 1
    w.line("G0 Z5.")


def loop_if(w, rng, surf, nums):
    """VC1 counts, IF [VC1 LT n] jumps back to the patch's first block."""
    n = rng.randint(2, 6)
    target = nums.next()
    w.line("(REST PASS %d TIMES - VC1 COUNTS)" % n)
    w.line("VC1=0")
    patch(w, rng, surf.phase, surf.tool[3], rng.randint(5, 200), target)
    w.line("VC1=VC1+1")
    w.line("IF [VC1 LT %d] %s" % (n, target))


def loop_while(w, rng, surf, nums):
    n = rng.randint(2, 5)
    w.line("(REST PASS %d TIMES - WHILE LOOP)" % n)
    w.line("VC2=0")
    w.line("WHILE [VC2 LT %d] DO 1" % n)
    patch(w, rng, surf.phase, surf.tool[3], rng.randint(5, 200))
    w.line("VC2=VC2+1")
    w.line("END 1")


def loop_do(w, rng, surf, nums):
    """A bare DO loop left through an IF, two patches per turn."""
    n = rng.randint(2, 4)
    out = nums.next()
    w.line("(REST PASSES UNTIL VC3 REACHES %d - DO LOOP)" % n)
    w.line("VC3=0")
    w.line("DO 2")
    blocks = rng.randint(5, 200)
    patch(w, rng, surf.phase, surf.tool[3], max(5, blocks // 2))
    w.line("VC3=VC3+1")
    w.line("IF [VC3 GE %d] %s" % (n, out))
    patch(w, rng, surf.phase, surf.tool[3], max(5, blocks - blocks // 2))
    w.line("END 2")
    w.line("%s G0 Z5." % out)


def skip_forward(w, rng, surf, nums):
    """An optional pass: IF jumps to it, GOTO jumps over it."""
    do, over = nums.next(), nums.next()
    w.line("(EXTRA REST PASS ONLY WHEN VC20 IS 1)")
    w.line("IF [VC20 EQ 1] %s" % do)
    w.line("GOTO %s" % over)
    patch(w, rng, surf.phase, surf.tool[3], rng.randint(5, 200), do)
    w.line("%s G0 Z5." % over)


LOOPS = (loop_if, loop_while, loop_do, skip_forward)


def start_op(w, nums, number, text, speed, x="-60.", y="-40."):
    nums.restart()
    w.line("%s (T%d %s)" % (nums.next(), number, text))
    w.line("T%d M6" % number)
    w.line("G0 G90 X%s Y%s" % (x, y))
    w.line("G56 Z50. H%d" % number)
    if speed:
        w.line("S%d M3" % speed)
        w.line("M8")


def end_op(w, rng):
    if rng.random() < 0.5:
        w.line("/G0 Z100.")  # an optional stop high above the part
    w.line("G0 Z100. M9")
    w.line("M5")
    if rng.random() < 0.5:
        w.line("/M1")


def op_drill(w, rng, nums):
    """Spot drill a grid with the subprogram O9002, then a row of deep holes in a WHILE loop."""
    start_op(w, nums, 5, "D8.5 DRILL - GRID AND ROW OF HOLES", 1800, "-50.", "-30.")
    nx, ny = rng.randint(2, 5), rng.randint(2, 4)
    w.line("(GRID %d X %d PITCH 10. FROM X-50. Y-30. IN O9002)" % (nx, ny))
    w.line("VC21=-50.")
    w.line("VC22=-30.")
    w.line("VC24=%d" % nx)
    w.line("VC25=%d" % ny)
    w.line("VC26=10.")
    w.line("G98")
    w.line("G81 X-50. Y-30. Z-3. R3. F150")
    w.line("CALL O9002")
    w.line("G80")
    n = rng.randint(3, 8)
    w.line("(ROW OF %d HOLES PITCH 12. - VC4 COUNTS)" % n)
    w.line("%s G83 X-40. Y25. Z-20. R3. Q4. F250" % nums.next())
    w.line("VC4=1")
    w.line("WHILE [VC4 LT %d] DO 1" % n)
    w.line("X=-40.+VC4*12.")  # absolute: under G91 the cycle's R and Z would be incremental too
    w.line("VC4=VC4+1")
    w.line("END 1")
    w.line("G80")
    end_op(w, rng)


def op_tap(w, rng, nums):
    start_op(w, nums, 7, "M10 X 1.5 TAP - FLOATING HOLDER  F = 400 X 1.5", 400, "-50.", "-30.")
    w.line("G98")
    w.line("%s G84 X-50. Y-30. Z-18. R10. F600" % nums.next())
    w.line("X50. Y-30.")
    w.line("X50. Y30.")
    w.line("X-50. Y30.")
    w.line("G80")
    end_op(w, rng)


def op_keyway(w, rng, nums):
    """Slots with the shop macro as a modal call, then pockets in O9003."""
    start_op(w, nums, 6, "D8 END MILL - KEY SLOTS AND POCKETS", 3000, "-50.", "-30.")
    n = rng.randint(2, 5)
    w.line("(%d EQUAL SLOTS 20 X 8 - MODAL CALL)" % n)
    w.line("MODIN OKYOY PR=2. PZ=-4. PI=20. PJ=8. PD=15 PF=250")
    for k in range(n):
        w.line("X%s Y-30." % fmt(-50.0 + 25.0 * k))
    w.line("MODOUT")
    w.line("(POCKETS 10 X 10 - VC27 STEPS DEEP, VC5 COUNTS)")
    w.line("VC27=%d" % rng.randint(1, 3))
    w.line("VC5=0")
    w.line("%s G0 X=-40.+VC5*20. Y20." % nums.next())
    w.line("CALL O9003")
    w.line("VC5=VC5+1")
    w.line("IF [VC5 LT %d] N%d" % (rng.randint(2, 5), nums.n))
    end_op(w, rng)


def op_probe(w, rng, nums):
    """Four touches on the top face through O9001; skipped when VC30 is 1."""
    start_op(w, nums, 50, "TOUCH PROBE - TOP FACE AT 4 POINTS", 0)
    over = nums.next()
    w.line("IF [VC30 EQ 1] %s" % over)
    w.line("VC6=0")
    w.line("%s VC21=-50.+VC6*30." % nums.next())
    w.line("VC22=-30.+VC6*20.")
    w.line("VC31=0")
    w.line("CALL O9001")
    w.line("VC[40+VC6]=VC31")
    w.line("VC6=VC6+1")
    w.line("IF [VC6 LT 4] N%d" % nums.n)
    w.line("%s G0 Z100." % over)
    w.line("M5")


SMALL_OPS = (op_drill, op_keyway, op_tap, op_probe)


def generate_loops(size, seed, out):
    rng = random.Random(seed)
    w = Writer(out, size)
    nums = Numbers()
    w.line("%")
    w.line("O8801 (MOULD CAVITY 8801 - SURFACING WITH PROBING AND PATTERN MACROS)")
    w.line("(POST: GENERIC OSP-P300M  UNITS MM)")
    w.line("(STOCK 130 X 90 X 30  TOP OF STOCK Z0)")
    w.line("(VC20 = 1: EXTRA REST PASSES   VC30 = 1: NO PROBING)")
    w.line("G15 H1")
    # About 300 features (loops, short operations) over the whole file; a
    # surfacing operation holds four of them.
    gap = max(size // 300, 2000)
    reserve = len(SUBPROGRAMS) + 400  # the end of the main program, the subprograms
    tool_index = 0
    phases = [0.7 * k for k in range(len(TOOLS))]
    while not w.full(reserve + gap):
        k = tool_index % len(TOOLS)
        tool = TOOLS[k]
        number, text, speed, feed = tool
        start_op(w, nums, number, text, speed)
        surf = Surfacing(rng, tool, phases[k])
        w.line("G0 Z5.")
        for _ in range(4):
            if w.full(reserve + gap):
                break
            surf.rows(w, rng, w.size + gap // 2)
            rng.choice(LOOPS)(w, rng, surf, nums)
        phases[k] = surf.phase
        end_op(w, rng)
        if not w.full(reserve + gap):
            SMALL_OPS[tool_index % len(SMALL_OPS)](w, rng, nums)
        tool_index += 1
    w.line("G30 P1")
    w.line("M30")
    for s in SUBPROGRAMS.splitlines():
        w.line(s)
    w.line("%")
    w.flush()


# --- The macros shape --------------------------------------------------------
#
# Rows of features on a plate, each operation a tool change and then one
# macro block per feature, at positions that vary from row to row.

def macro_rows(w, rng, reserve):
    """One tool and one row of features per call, the macro picked in turn."""
    ops = ("ozagr", "om100", "okyoy", "og87n", "g114")
    k = 0
    while not w.full(reserve):
        op = ops[k % len(ops)]
        k += 1
        y = fmt(-40.0 + 10.0 * rng.randint(0, 8))
        xs = [fmt(-60.0 + 0.5 * rng.randint(0, 240)) for _ in range(rng.randint(20, 60))]
        if op == "ozagr":
            w.line("(T31 BIG BACK C'BORE BAR - BACK SPOTFACES D18 X 3 ON D9 HOLES)")
            w.line("T31 M6")
            w.line("G0 G90 X0 Y0")
            w.line("G56 Z50. H31")
            w.line("S600 M3")
            for x in xs:
                w.line("CALL OZAGR PX=%s PY=%s PR=5. PZ=-29. PI=6. PJ=1.5 PF=50 PFA=400 PFB=200 PP=.3 PS=600"
                       % (x, y))
        elif op == "om100":
            w.line("(T32 BURRAWAY D8 - FRONT AND BACK CHAMFER)")
            w.line("T32 M6")
            w.line("G0 G90 X0 Y0")
            w.line("G56 Z50. H32")
            w.line("S1200 M3")
            for x in xs:
                w.line("CALL OM100 PX=%s PY=%s PR=5. PZ=-32. PI=4. PK=12. PF=150 PFA=600 PS=1200 PT=35."
                       % (x, y))
        elif op == "okyoy":
            w.line("(T6 D8 END MILL - KEY SLOTS 20 X 8)")
            w.line("T6 M6")
            w.line("G0 G90 X0 Y0")
            w.line("G56 Z50. H6")
            w.line("S3000 M3")
            for x in xs:
                w.line("CALL OKYOY PX=%s PY=%s PR=2. PZ=-5. PI=20. PJ=8. PD=6 PF=250 PFA=80 PS=3000" % (x, y))
        elif op == "og87n":
            w.line("(T33 BACK C'BORE NOTCHED BAR - MODAL CALL, A HOLE PER BLOCK)")
            w.line("T33 M6")
            w.line("G0 G90 X0 Y0")
            w.line("G56 Z50. H33")
            w.line("S500 M3")
            w.line("MODIN OG87N PR=5. PZ=-25. PL=4. PI=2. PJ=6. PF=40 PS=500")
            for x in xs:
                w.line("X%s Y%s" % (x, y))
            w.line("MODOUT")
        else:
            w.line("(T7 M10 TAP - AUTO-REVERSE TAPPER)")
            w.line("T7 M6")
            w.line("G0 G90 X0 Y0")
            w.line("G56 Z50. H7")
            w.line("S400 M3")
            w.line("G98 G114 X%s Y%s R10. Z-21.5 L1.5 P.5 F600 FA=650" % (xs[0], y))
            for x in xs:
                w.line("X%s Y%s" % (x, y))
            w.line("M204")
        w.line("G0 Z100.")
        w.line("M5")


def generate_macros(size, seed, out):
    rng = random.Random(seed)
    w = Writer(out, size)
    w.line("%")
    w.line("O7700 (PLATE 7700 - SHOP MACROS ON EVERY FEATURE)")
    w.line("(POST: GENERIC OSP-P300M  UNITS MM)")
    w.line("G15 H1")
    macro_rows(w, rng, 200)
    w.line("G30 P1")
    w.line("M30")
    w.line("%")
    w.flush()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size-mb", type=float, default=1.0, help="approximate size in MB (10^6 bytes)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--output", default="-")
    ap.add_argument("--shape", choices=SHAPES, default="plain", help="program shape (see above)")
    ap.add_argument("--sequence-numbers", action="store_true", help="N10, N20, ... on every block (= --shape numbered)")
    args = ap.parse_args()
    if args.sequence_numbers:
        if args.shape not in ("plain", "numbered"):
            ap.error("--sequence-numbers goes with --shape plain or numbered only")
        args.shape = "numbered"
    size = int(args.size_mb * 1000 * 1000)

    def run(f):
        if args.shape == "loops":
            generate_loops(size, args.seed, f)
        elif args.shape == "macros":
            generate_macros(size, args.seed, f)
        else:
            generate(size, args.seed, f, numbered=args.shape == "numbered",
                     zshift=TRAVEL_SHIFT if args.shape == "travel" else 0.0, bigloop=args.shape == "bigloop")

    if args.output == "-":
        run(sys.stdout)
    else:
        with open(args.output, "w", newline="\n") as f:
            run(f)


if __name__ == "__main__":
    main()
