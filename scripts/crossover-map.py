#!/usr/bin/env python3
"""Where each exact visibility method is the cheapest: blur scale x samples per pixel.

Runs `patchsim sweep` on each blurred shipped scene with the exact methods (patch, interval,
triangle-bbox, each at its paper's setting: interval with one time stratum per sample of a pixel,
triangle-bbox with McGuire et al.'s convex hull) over blur scales and sample counts, then writes

  OUT/crossover.csv   scene, blur, spp, each method's modelled cycles and wall seconds, the
                      cheapest by each, and the patch method's cost over the cheapest other
  OUT/crossover.md    per scene and spp: the cheapest method at each blur, and the crossover
                      blur (the smallest scale from which the patch method stays the cheapest)
  OUT/crossover.png   (and .svg) the map: one panel per scene, cells coloured by the cheapest
                      method in modelled cycles, annotated with patch / cheapest other

The exact methods give the same image sample for sample (tests), so only their costs differ; the
sweeps' converged images are rendered at a low count (--converged-spp 4) since their errors are
not used here. Wall times are of one render each on this machine (noisy; the baselines are scalar
where the patch method is SIMD: docs/ACCURACY.md), cycles are the modelled hardware's
(docs/HARDWARE.md) and do not depend on the machine.

usage: scripts/crossover-map.py OUT [--scenes S...] [--blur B...] [--spp N...] [--hw FILE]
       scripts/crossover-map.py OUT --results RESULTS.csv...   (tables and map from sweeps run
                                                                before, e.g. with other blurs)
"""

import argparse
import csv
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
METHODS = ["patch", "interval", "triangle-bbox"]
LABEL = re.compile(r"(.+?)-blur(\d+(?:\.\d+)?(?:e[+-]?\d+)?)(-\d+)?")
COLOURS = {"patch": "#3b75af", "interval": "#ef8636", "triangle-bbox": "#519e3e"}


def read_results(paths):
    rows = []
    for path in paths:
        with open(path) as f:
            for row in csv.DictReader(f):
                # Each method at the setting it was run with by default (its paper's); rows of
                # other settings (sweep --vary) are not this map's.
                if row["method"] not in METHODS or row.get("setting", ""):
                    continue
                # "<scene>-blur<scale>", or the scene's own name at blur 1; a "-2" after it is
                # patchsim's mark of a label used twice, which would mix two scenes' runs.
                match = LABEL.fullmatch(row["scene"])
                if match and match.group(3):
                    sys.exit(f"{path}: scene label {row['scene']} was used twice in the sweep")
                name, blur = (match.group(1), match.group(2)) if match else (row["scene"], "1")
                rows.append({"scene": name, "blur": float(blur), "spp": int(row["spp"]),
                             "method": row["method"], "cycles": float(row["modelled_cycles"]),
                             "wall": float(row["wall_seconds"])})
    return rows


def run_sweeps(args, out):
    results = []
    for scene in args.scenes:
        folder = out / "sweeps" / pathlib.Path(scene).stem
        command = [args.patchsim, "sweep", str(ROOT / scene), "--methods", ",".join(METHODS),
                   "--spp", ",".join(map(str, args.spp)), "--blur",
                   ",".join(map(str, args.blur)), "--repeats", "1", "--converged-spp", "4",
                   "--no-progress", "-o", str(folder)]
        if args.hw:
            command += ["--hw", args.hw]
        print(" ".join(command), file=sys.stderr)
        subprocess.run(command, check=True)
        results.append(folder / "results.csv")
    return read_results(results)


def cells(rows):
    table = {}
    for r in rows:
        table.setdefault((r["scene"], r["blur"], r["spp"]), {})[r["method"]] = r
    out = []
    for (scene, blur, spp), by_method in sorted(table.items()):
        cell = {"scene": scene, "blur": blur, "spp": spp}
        for m in METHODS:
            cell[m + "_cycles"] = by_method[m]["cycles"]
            cell[m + "_wall"] = by_method[m]["wall"]
        for kind in ("cycles", "wall"):
            cheapest = min(METHODS, key=lambda m: cell[m + "_" + kind])
            others = min(cell[m + "_" + kind] for m in METHODS if m != "patch")
            cell["cheapest_" + kind] = cheapest
            cell["patch_over_best_other_" + kind] = cell["patch_" + kind] / others
        out.append(cell)
    return out


def crossover(cells_of, spp, kind="cycles"):
    """Smallest blur from which patch is the cheapest at every larger blur, or None."""
    blurs = sorted(c["blur"] for c in cells_of if c["spp"] == spp)
    by_blur = {c["blur"]: c for c in cells_of if c["spp"] == spp}
    found = None
    for b in reversed(blurs):
        if by_blur[b]["cheapest_" + kind] != "patch":
            break
        found = b
    return found


def write_csv(table, path):
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(table[0].keys()))
        writer.writeheader()
        writer.writerows(table)


def write_markdown(table, args, path):
    lines = ["| scene | spp | blur scales | cheapest in modelled cycles, by blur | "
             "patch / cheapest other (cycles) | crossover blur (cycles) | "
             "cheapest in wall time, by blur | crossover blur (wall) |",
             "|---|---|---|---|---|---|---|---|"]
    short = {"patch": "P", "interval": "I", "triangle-bbox": "B"}
    for scene in dict.fromkeys(c["scene"] for c in table):
        of_scene = [c for c in table if c["scene"] == scene]
        for spp in sorted({c["spp"] for c in of_scene}):
            row = sorted((c for c in of_scene if c["spp"] == spp), key=lambda c: c["blur"])
            blurs = " ".join(f"x{c['blur']:g}" for c in row)
            by_cycles = " ".join(short[c["cheapest_cycles"]] for c in row)
            ratios = " ".join(f"{c['patch_over_best_other_cycles']:.2f}" for c in row)
            by_wall = " ".join(short[c["cheapest_wall"]] for c in row)
            cross = crossover(of_scene, spp)
            cross_wall = crossover(of_scene, spp, "wall")
            lines.append(f"| {scene} | {spp} | {blurs} | {by_cycles} | {ratios} | "
                         f"{'x%g' % cross if cross is not None else 'none'} | {by_wall} | "
                         f"{'x%g' % cross_wall if cross_wall is not None else 'none'} |")
    lines.append("")
    lines.append("P patch, I interval (K = spp), B triangle-bbox (convex hull). The crossover is the "
                 "smallest blur scale from which the patch method is the cheapest at every larger "
                 "scale swept; `none`: it is not the cheapest at the largest.")
    path.write_text("\n".join(lines) + "\n")


def plot(table, args, out):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.patches import Patch
    except ImportError:
        print("matplotlib missing: no plot (python3-matplotlib)", file=sys.stderr)
        return
    scenes = list(dict.fromkeys(c["scene"] for c in table))
    blurs = sorted({c["blur"] for c in table})
    spps = sorted({c["spp"] for c in table})
    fig, axes = plt.subplots(1, len(scenes), figsize=(3.2 * len(scenes), 3.4), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        for c in (c for c in table if c["scene"] == scene):
            x, y = blurs.index(c["blur"]), spps.index(c["spp"])
            ax.add_patch(plt.Rectangle((x - 0.5, y - 0.5), 1, 1,
                                       color=COLOURS[c["cheapest_cycles"]], alpha=0.85))
            ax.text(x, y, f"{c['patch_over_best_other_cycles']:.2f}", ha="center", va="center",
                    fontsize=8, color="white")
        ax.set_facecolor("#dddddd")  # grey: not swept
        ax.set_xlim(-0.5, len(blurs) - 0.5)
        ax.set_ylim(-0.5, len(spps) - 0.5)
        ax.set_xticks(range(len(blurs)), [f"x{b:g}" for b in blurs])
        ax.set_yticks(range(len(spps)), [str(s) for s in spps])
        ax.set_xlabel("blur scale (motion and aperture)")
        ax.set_title(scene)
    axes[0][0].set_ylabel("samples per pixel")
    fig.legend(handles=[Patch(color=COLOURS[m], label=m) for m in METHODS], loc="lower center",
               ncol=len(METHODS), frameon=False)
    fig.suptitle("cheapest exact method in modelled cycles (cell: patch / cheapest other)")
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    for ext in ("png", "svg"):
        fig.savefig(out / f"crossover.{ext}", dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out")
    parser.add_argument("--scenes", nargs="+",
                        default=["scenes/motion.json", "scenes/camera_pan.json",
                                 "scenes/defocus.json", "scenes/motion_defocus.json",
                                 "scenes/transparency.json"])
    # x4 is left out by default: there the scalar baselines take minutes per render (on `motion`
    # at 16 spp, interval 6.5 min and triangle-bbox over 15 on the 2-core machine).
    parser.add_argument("--blur", nargs="+", type=float, default=[0.25, 0.5, 1, 2])
    parser.add_argument("--spp", nargs="+", type=int, default=[1, 4, 16])
    parser.add_argument("--hw", default="")
    parser.add_argument("--patchsim", default=str(ROOT / "build/pipeline/app/patchsim"))
    parser.add_argument("--results", nargs="+", default=[],
                        help="results.csv files of sweeps already run: no new sweep")
    args = parser.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = read_results(args.results) if args.results else run_sweeps(args, out)
    table = cells(rows)
    write_csv(table, out / "crossover.csv")
    write_markdown(table, args, out / "crossover.md")
    plot(table, args, out)
    print((out / "crossover.md").read_text())


if __name__ == "__main__":
    main()
