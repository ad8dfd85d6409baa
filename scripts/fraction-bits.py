#!/usr/bin/env python3
"""The fraction bits each tile-test site needs, per family of hard cases (issue 35).

    python3 scripts/fraction-bits.py [--patchsim build/pipeline/app/patchsim] [--cases N]

For every case family of `verify-tiles --family` and fixed point with 16 integer bits and F
fraction bits, F from 2 to 24, runs `verify-tiles --format fixed16.F` and prints a markdown
table: per site, the smallest F from which the naive variant (rounded to nearest, no bias) has no
false reject in the pinhole and lens cases at that F and every larger one, and whether the
conservative variants (rounded outward, or error-bounded) had a false reject at any F (they must
not). Standard library only.
"""

import argparse
import re
import subprocess
import sys

FAMILIES = ["mixed", "near-plane", "far-depth", "huge-motion", "tiny", "huge", "wide-lens"]
SITES = [("screen bounds (pixels)", "patent-2d-time-fixed16.{F}"),
         ("node boxes", "patent-3d-time-nodes-fixed16.{F}"),
         ("tile planes (arithmetic)", "patent-3d-time-planes-fixed16.{F}")]
FRACTIONS = list(range(2, 25))
LINE = re.compile(r"^(\S+) \((pinhole|lens)\): cases \d+, false rejects (\d+),")


def false_rejects(patchsim, family, fraction, cases):
    out = subprocess.run([patchsim, "verify-tiles", "--cases", str(cases), "--family", family,
                          "--format", f"fixed16.{fraction}"], capture_output=True, text=True)
    if out.returncode not in (0, 1):
        sys.exit(f"verify-tiles failed: {out.stderr}")
    rejects = {}
    for line in out.stdout.splitlines():
        m = LINE.match(line)
        if m:
            rejects[m.group(1)] = rejects.get(m.group(1), 0) + int(m.group(3))
    return rejects


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--patchsim", default="build/pipeline/app/patchsim")
    parser.add_argument("--cases", type=int, default=100000)
    args = parser.parse_args()
    fractions = sorted(FRACTIONS)
    print(f"| family | " + " | ".join(f"{site}: naive needs F >=" for site, _ in SITES) +
          " | conservative false rejects |")
    print("|---" * (len(SITES) + 2) + "|")
    for family in FAMILIES:
        runs = {f: false_rejects(args.patchsim, family, f, args.cases) for f in fractions}
        cells, conservative = [], 0
        for _, pattern in SITES:
            needed = None
            for f in reversed(fractions):
                if runs[f].get(pattern.format(F=f) + "-naive", 0) > 0:
                    break
                needed = f
            cells.append(str(needed) if needed is not None else f"> {fractions[-1]}")
            conservative += sum(runs[f].get(pattern.format(F=f), 0) for f in fractions)
        print(f"| {family} | " + " | ".join(cells) + f" | {conservative} |")


if __name__ == "__main__":
    main()
