#!/usr/bin/env python3
"""The Embree comparison's table, from Google Benchmark JSON files of build/bench/patchsim_embree_bench.

    python3 scripts/embree-matrix.py RUN.json... [--csv OUT.csv]

Each row of the matrix (scene, blur, lens, threads) is the median real time of the patch
rasterizer and of each way Embree traces (`embree/`: one ray at a time, `embreePacket16/`: coherent
16-ray packets, `embreeStream/`: coherent streams), over every repetition in the files; the
ratio is against the fastest Embree variant of that row. The covered-sample counts of the Embree
variants must agree, or the script stops. The patch rasterizer's must too, except on a static
frame (no blur, pinhole), which it rasterizes in fixed point with edge functions (DESIGN.md 4.7a):
there its count may differ from the float rays' by at most STATIC_TOLERANCE of the samples,
and the CSV's `covered_patch_minus_embree` says by how many.

Standard library only.
"""

import argparse
import csv
import json
import re
import statistics
import sys
from collections import defaultdict

NAME = re.compile(r"^(patchRasterizer|embree|embreePacket16|embreeStream)/"
                  r"(\w+)/(\w+)/(pinhole|lens)/threads:(\d)")
VARIANTS = ["embree", "embreePacket16", "embreeStream"]
STATIC_TOLERANCE = 1e-4  # of the covered samples: edge samples the snapping moves


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--csv")
    args = parser.parse_args()
    times = defaultdict(list)
    covered = {}
    counters = {}
    for path in args.runs:
        with open(path) as f:
            for b in json.load(f)["benchmarks"]:
                if b.get("run_type") != "iteration":
                    continue
                m = NAME.match(b["name"])
                if not m:
                    continue
                method, key = m.group(1), m.group(2, 3, 4, 5)
                times[(method, key)].append(b["real_time"])
                hits = b.get("covered samples")
                if hits is not None:
                    covered.setdefault((method == "patchRasterizer", key), hits)
                    if covered[(method == "patchRasterizer", key)] != hits:
                        sys.exit(f"embree-matrix.py: {b['name']} covers {hits} samples, "
                                 f"another run {covered[(method == 'patchRasterizer', key)]}")
                if method == "patchRasterizer":
                    counters[key] = (b.get("rays/sample", 0.0), b.get("STE", 0.0))
    keys = sorted({k for (_, k) in times},
                  key=lambda k: (["default", "factor32", "scale1m"].index(k[0]),
                                 int(k[3]), ["none", "moderate", "large"].index(k[1]),
                                 k[2] == "lens"))
    for key in keys:
        patch, embree = covered.get((True, key)), covered.get((False, key))
        if patch is None or embree is None or patch == embree:
            continue
        static = key[1] == "none" and key[2] == "pinhole"
        if not static or abs(patch - embree) > STATIC_TOLERANCE * embree:
            sys.exit(f"embree-matrix.py: {'/'.join(key)}: the patch rasterizer covers {patch} "
                     f"samples, Embree {embree}")
    rows = []
    for key in keys:
        if ("patchRasterizer", key) not in times:
            continue
        patch = statistics.median(times[("patchRasterizer", key)])
        embree = {v: statistics.median(times[(v, key)]) for v in VARIANTS if (v, key) in times}
        if not embree:
            continue
        fastest = min(embree, key=embree.get)
        rows.append({"scene": key[0], "blur": key[1], "lens": key[2], "threads": key[3],
                     "patch_ms": patch, **{f"{v}_ms": embree.get(v) for v in VARIANTS},
                     "fastest_embree": fastest, "ratio": embree[fastest] / patch,
                     "ratio_one_ray": embree.get("embree", float("nan")) / patch,
                     "repetitions": len(times[("patchRasterizer", key)]),
                     "rays_per_sample": counters[key][0], "ste": counters[key][1],
                     "covered_patch_minus_embree":
                         covered.get((True, key), 0) - covered.get((False, key), 0)})
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    print("| scene | blur | lens | thr | patch ms | Embree 1 ray | 16-ray packets | streams "
          "| patch / fastest Embree | patch / 1 ray |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    short = {"embree": "1 ray", "embreePacket16": "packets", "embreeStream": "streams"}

    def ms(v):
        return "-" if v is None else f"{v:.1f}"
    for r in rows:
        print(f"| {r['scene']} | {r['blur']} | {r['lens']} | {r['threads']} | {r['patch_ms']:.1f} "
              f"| {ms(r['embree_ms'])} | {ms(r['embreePacket16_ms'])} | {ms(r['embreeStream_ms'])} "
              f"| **{r['ratio']:.2f}x** ({short[r['fastest_embree']]}) | {r['ratio_one_ray']:.2f}x |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
