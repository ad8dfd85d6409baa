#!/usr/bin/env python3
"""The Embree comparison's table, from Google Benchmark JSON files of build/bench/patchsim_embree_bench.

    python3 scripts/embree-matrix.py RUN.json... [--csv OUT.csv]

Each row of the matrix (scene, blur, lens, threads) is the median real time of the patch
rasterizer and of each way Embree traces (`embree/`: one ray at a time, `embreePacket16/`: coherent
16-ray packets, `embreeStream/`: coherent streams), over every repetition in the files; the
ratio is against the fastest Embree variant of that row. The covered-sample counts of all four
must agree, or the script stops: the methods must find the same samples.

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
                    if covered.setdefault(key, hits) != hits:
                        sys.exit(f"embree-matrix.py: {b['name']} covers {hits} samples, "
                                 f"another method {covered[key]}")
                if method == "patchRasterizer":
                    counters[key] = (b.get("rays/sample", 0.0), b.get("STE", 0.0))
    keys = sorted({k for (_, k) in times},
                  key=lambda k: (["default", "factor32", "scale1m"].index(k[0]),
                                 int(k[3]), ["none", "moderate", "large"].index(k[1]),
                                 k[2] == "lens"))
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
                     "rays_per_sample": counters[key][0], "ste": counters[key][1]})
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
