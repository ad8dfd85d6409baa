#!/usr/bin/env python3
"""Plots of a `patchsim sweep`: error against time for every method, and crop sheets.

    python3 plot_sweep.py SWEEP_DIR

Reads SWEEP_DIR/results.csv and SWEEP_DIR/images/*.png (written by `patchsim sweep`) and writes,
per scene, SWEEP_DIR/plots/<scene>.png and .svg (PSNR and RMSE against wall time and against
modelled cycles, log scales, one line per method with its samples per pixel labelled, the Pareto
front of all runs marked) and SWEEP_DIR/plots/<scene>-crops.png (the same crop of every run beside
the converged image, where the runs disagree most). Needs matplotlib (Debian: python3-matplotlib).
"""

import csv
import math
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

MARKERS = "osD^vP*Xh<>"


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def pareto(points):
    """Indices of the points no other point beats in both cost (lower) and error (lower)."""
    front = []
    for i, (ci, ei) in enumerate(points):
        if not any(cj <= ci and ej <= ei and (cj, ej) != (ci, ei) for cj, ej in points):
            front.append(i)
    return sorted(front, key=lambda i: points[i][0])


def plot_scene(scene, rows, out_dir):
    methods = sorted({r["method"] for r in rows}, key=lambda m: [r["method"] for r in rows].index(m))
    fig, axes = plt.subplots(2, 2, figsize=(12, 9))
    panels = [
        ("wall_seconds", "psnr", "wall time (s)", "PSNR (dB, higher is better)"),
        ("modelled_cycles", "psnr", "modelled cycles", "PSNR (dB, higher is better)"),
        ("wall_seconds", "rmse", "wall time (s)", "RMSE (linear RGB, lower is better)"),
        ("modelled_cycles", "rmse", "modelled cycles", "RMSE (linear RGB, lower is better)"),
    ]
    for ax, (xkey, ykey, xlabel, ylabel) in zip(axes.flat, panels):
        everything = []
        for k, method in enumerate(methods):
            mine = sorted((r for r in rows if r["method"] == method), key=lambda r: int(r["spp"]))
            xs = [float(r[xkey]) for r in mine]
            ys = [float(r[ykey]) if math.isfinite(float(r[ykey])) else np.nan for r in mine]
            ax.plot(xs, ys, marker=MARKERS[k % len(MARKERS)], label=method)
            for x, y, r in zip(xs, ys, mine):
                ax.annotate(r["spp"], (x, y), textcoords="offset points", xytext=(4, 4), fontsize=7)
            everything += [(x, y) for x, y in zip(xs, ys) if np.isfinite(y)]
        # The Pareto front: lower cost and lower error (higher PSNR) than any other run.
        sign = -1 if ykey == "psnr" else 1
        front = pareto([(x, sign * y) for x, y in everything])
        ax.plot([everything[i][0] for i in front], [everything[i][1] for i in front], color="black",
                linestyle=":", linewidth=1.5, label="Pareto front")
        ax.set_xscale("log")
        if ykey == "rmse":
            ax.set_yscale("log")
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].legend(fontsize=8)
    fig.suptitle(f"{scene}: error against the converged image, by cost (labels: samples per pixel)")
    fig.tight_layout()
    written = []
    for ext in ("png", "svg"):
        path = os.path.join(out_dir, f"{scene}.{ext}")
        fig.savefig(path, dpi=110)
        written.append(path)
    plt.close(fig)
    return written


def crop_sheet(scene, rows, sweep_dir, out_dir, size=48):
    images_dir = os.path.join(sweep_dir, "images")
    converged = mpimg.imread(os.path.join(images_dir, f"{scene}-converged.png"))[..., :3]
    runs = [(r["method"], int(r["spp"])) for r in rows]
    pictures = {run: mpimg.imread(os.path.join(images_dir, f"{scene}-{run[0]}-{run[1]}.png"))[..., :3]
                for run in runs}
    h, w = converged.shape[:2]
    size = min(size, h, w)
    # Where the runs disagree most with the converged image: the crop with the largest summed error.
    error = sum(np.abs(p - converged).sum(axis=2) for p in pictures.values())
    best, where = -1.0, (0, 0)
    for y in range(0, h - size + 1, max(1, size // 4)):
        for x in range(0, w - size + 1, max(1, size // 4)):
            e = error[y:y + size, x:x + size].sum()
            if e > best:
                best, where = e, (y, x)
    y, x = where
    methods = list(dict.fromkeys(m for m, _ in runs))
    spps = sorted({s for _, s in runs})
    fig, axes = plt.subplots(len(methods), len(spps) + 1,
                             figsize=(1.6 * (len(spps) + 1), 1.7 * len(methods)), squeeze=False)
    for i, method in enumerate(methods):
        for j, spp in enumerate(spps):
            ax = axes[i][j]
            ax.axis("off")
            if (method, spp) in pictures:
                ax.imshow(pictures[(method, spp)][y:y + size, x:x + size], interpolation="nearest")
            ax.set_title(f"{method} {spp} spp", fontsize=6)
        ax = axes[i][-1]
        ax.axis("off")
        ax.imshow(converged[y:y + size, x:x + size], interpolation="nearest")
        ax.set_title("converged", fontsize=6)
    fig.suptitle(f"{scene}: pixels ({x}, {y}) to ({x + size}, {y + size})", fontsize=8)
    fig.tight_layout()
    path = os.path.join(out_dir, f"{scene}-crops.png")
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    sweep_dir = sys.argv[1]
    rows = read_rows(os.path.join(sweep_dir, "results.csv"))
    out_dir = os.path.join(sweep_dir, "plots")
    os.makedirs(out_dir, exist_ok=True)
    by_scene = defaultdict(list)
    for r in rows:
        by_scene[r["scene"]].append(r)
    for scene, mine in by_scene.items():
        for path in plot_scene(scene, mine, out_dir):
            print("wrote", path)
        print("wrote", crop_sheet(scene, mine, sweep_dir, out_dir))


if __name__ == "__main__":
    main()
