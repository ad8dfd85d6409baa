#!/usr/bin/env python3
"""Ranks the exact visibility methods (and the accumulation buffer) by modelled cycles on the
shipped scenes under two hardware files, to show which conclusions survive repricing the
rasterizer's operations (docs/HARDWARE.md, "Iso-arithmetic hardware").

    scripts/hardware-ranking.py OUT_DIR [--hw A.json B.json] [--spp 4 16]

Writes OUT_DIR/hardware_ranking.csv (scene, spp, method, cycles under each file) and prints a
Markdown table: each scene and spp with the methods cheapest first under each file, and whether
the order is the same. Renders run on one thread into a temporary folder; only the CSV is kept.
"""
import argparse
import json
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
SCENES = ["static", "motion", "camera_pan", "defocus", "motion_defocus", "transparency"]
METHODS = ["patch", "interval", "triangle-bbox", "interleaved"]


def cycles(patchsim, scene, method, spp, hw, tmp):
    out = pathlib.Path(tmp) / f"{scene}-{method}-{spp}-{pathlib.Path(hw).stem}"
    subprocess.run([patchsim, "render", "-q", "--no-progress", "--threads", "1",
                    str(ROOT / "scenes" / f"{scene}.json"), "--method", method, "--spp", str(spp),
                    "--hw", hw, "-o", str(out)], check=True, stdout=subprocess.DEVNULL)
    return json.loads((out / "stats.json").read_text())["timing"]["total_cycles"]


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out")
    parser.add_argument("--hw", nargs=2, default=[str(ROOT / "pipeline/hw/default.json"),
                                                   str(ROOT / "pipeline/hw/iso_arithmetic.json")])
    parser.add_argument("--spp", nargs="+", type=int, default=[4, 16])
    parser.add_argument("--patchsim", default=str(ROOT / "build/pipeline/app/patchsim"))
    args = parser.parse_args()
    names = [pathlib.Path(h).stem for h in args.hw]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for scene in SCENES:
            for spp in args.spp:
                for method in METHODS:
                    rows.append((scene, spp, method,
                                 [cycles(args.patchsim, scene, method, spp, h, tmp) for h in args.hw]))
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "hardware_ranking.csv", "w") as f:
        f.write(f"scene,spp,method,cycles_{names[0]},cycles_{names[1]}\n")
        for scene, spp, method, c in rows:
            f.write(f"{scene},{spp},{method},{c[0]:.0f},{c[1]:.0f}\n")
    print(f"| scene | spp | cheapest first, {names[0]} (M cycles) | cheapest first, {names[1]} | same order |")
    print("|---|---|---|---|---|")
    for scene in SCENES:
        for spp in args.spp:
            mine = [r for r in rows if r[0] == scene and r[1] == spp]
            ranked = [sorted(mine, key=lambda r: r[3][k]) for k in range(2)]
            texts = [", ".join(f"{r[2]} {r[3][k] / 1e6:.2f}" for r in ranked[k]) for k in range(2)]
            same = [r[2] for r in ranked[0]] == [r[2] for r in ranked[1]]
            print(f"| {scene} | {spp} | {texts[0]} | {texts[1]} | {'yes' if same else '**no**'} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
