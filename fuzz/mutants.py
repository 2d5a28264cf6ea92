#!/usr/bin/env python3
"""Writes a fixed set of mutants of the repository's programs for the
differential fuzzer to replay (tests/scripts/fuzz_short.sh).

libFuzzer chooses its mutations by the coverage of the binary it runs, so the
inputs of a run depend on the build; a test gated on such a run passes or fails
with the compiler. These mutants depend only on the seed programs, the
dictionary and --seed: every build replays the same inputs.

    fuzz/mutants.py --dict fuzz/osp.dict --out DIR [--count N] [--seed S] FOLDER...

The seeds are the programs under the FOLDERs (.MIN, .SSB, .SUB, .LIB, .NC and
.SDF files under 64 KiB), taken in the order of their paths.

Each mutant is one seed program (or a piece of one) with one to four edits of
the kinds libFuzzer makes: a part copied over or into another place, bytes
erased, a dictionary token inserted or written over, a byte changed, a line
repeated, two lines exchanged, and line ends changed to CR or CRLF.
"""
import argparse
import os
import random
import sys

MAX_LEN = 4096  # as fuzz/run.sh's -max_len
SEED_KINDS = (".MIN", ".SSB", ".SUB", ".LIB", ".NC", ".SDF")
INTERESTING = b"0123456789.+-=[]()/%;,$ \t\n\rNOGXYZIJKRPQFHDMSTLVW\x00\x80\x8d\xe3\xff"


def read_dict(path):
    tokens = []
    with open(path, "rb") as f:
        for raw in f:
            line = raw.strip()
            if not line.startswith(b'"') or not line.endswith(b'"') or len(line) < 2:
                continue
            tokens.append(line[1:-1].decode("unicode_escape").encode("latin-1"))
    return tokens


def mutate(rng, data, others, tokens):
    kind = rng.randrange(9)
    n = len(data)
    if kind == 0 and n:  # a part copied over another place
        src = rng.choice(others) if rng.randrange(4) == 0 else data
        length = rng.randint(1, min(len(src), 400)) if src else 0
        a = rng.randint(0, len(src) - length)
        b = rng.randint(0, max(n - length, 0))
        return data[:b] + src[a:a + length] + data[b + length:]
    if kind == 1 and n:  # a part copied into another place
        src = rng.choice(others) if rng.randrange(4) == 0 else data
        length = rng.randint(1, min(len(src), 400)) if src else 0
        a = rng.randint(0, len(src) - length)
        b = rng.randint(0, n)
        return data[:b] + src[a:a + length] + data[b:]
    if kind == 2 and n:  # bytes erased
        length = rng.randint(1, min(n, 64))
        a = rng.randint(0, n - length)
        return data[:a] + data[a + length:]
    if kind == 3:  # a token inserted
        b = rng.randint(0, n)
        return data[:b] + rng.choice(tokens) + data[b:]
    if kind == 4 and n:  # a token written over
        t = rng.choice(tokens)
        b = rng.randint(0, n - 1)
        return data[:b] + t + data[b + len(t):]
    if kind == 5 and n:  # one byte changed
        b = rng.randrange(n)
        c = INTERESTING[rng.randrange(len(INTERESTING))] if rng.randrange(2) else rng.randrange(256)
        return data[:b] + bytes([c]) + data[b + 1:]
    lines = data.split(b"\n")
    if kind == 6 and len(lines) > 1:  # a line repeated
        k = rng.randrange(len(lines))
        lines.insert(k, lines[k])
        return b"\n".join(lines)
    if kind == 7 and len(lines) > 2:  # two lines exchanged
        i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
        return b"\n".join(lines)
    if kind == 8 and len(lines) > 1:  # a line end changed
        ends = [i for i, c in enumerate(data) if c == 10]
        a = rng.choice(ends)
        return data[:a] + rng.choice([b"\r", b"\r\n", b"\n\r", b"\r\r\n"]) + data[a + 1:]
    b = rng.randint(0, n)
    return data[:b] + rng.choice(tokens) + data[b:]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folders", nargs="+", help="folders of seed programs")
    ap.add_argument("--dict", required=True, help="libFuzzer dictionary of tokens")
    ap.add_argument("--out", required=True, help="folder for the mutants (created)")
    ap.add_argument("--count", type=int, default=3000)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()

    paths = []
    for folder in args.folders:
        for top, _, files in os.walk(folder):
            paths += [os.path.join(top, f) for f in files if os.path.splitext(f)[1].upper() in SEED_KINDS]
    seeds = []
    for path in sorted(paths):
        if os.path.getsize(path) < 65536:
            with open(path, "rb") as f:
                seeds.append(f.read())
    if not seeds:
        sys.exit("fuzz/mutants.py: no seed programs in " + " ".join(args.folders))
    tokens = read_dict(args.dict) or [b"G0"]
    rng = random.Random(args.seed)
    os.makedirs(args.out, exist_ok=True)
    for k in range(args.count):
        data = rng.choice(seeds)
        if len(data) > MAX_LEN:  # a window of a long program, from a line start
            starts = [0] + [i + 1 for i, c in enumerate(data[:-MAX_LEN]) if c == 10]
            a = rng.choice(starts)
            data = data[a:a + MAX_LEN]
        for _ in range(rng.randint(1, 4)):
            data = mutate(rng, data, seeds, tokens)[:MAX_LEN]
        with open(os.path.join(args.out, "mutant-%05d" % k), "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main()
