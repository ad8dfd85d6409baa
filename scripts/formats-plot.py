#!/usr/bin/env python3
"""docs/accuracy/formats/formats.png: image error against modelled energy and cycles for a
`sweep` over the number-format sites (issue 35), each site's runs in its own colour.

    python3 scripts/formats-plot.py [RESULTS_CSV] [PNG]

RESULTS_CSV defaults to docs/accuracy/formats/results.csv, PNG to formats.png beside it.
"""

import csv
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SITES = ["node-format", "plane-format", "vertex-format"]


def settings(row):
    return dict(part.split("=", 1) for part in row["setting"].split(";"))


def group_of(row):
    """Which site differs from fp32: one site's name, 'all' (every site in one format) or
    'mixed'."""
    s = settings(row)
    narrow = [site for site in SITES if s[site] != "fp32"]
    if not narrow:
        return "fp32"
    if len(narrow) == 1:
        return narrow[0]
    if len(narrow) == len(SITES) and len({s[site] for site in SITES}) == 1:
        return "all"
    return "mixed"


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        ROOT, "docs", "accuracy", "formats", "results.csv")
    out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(path), "formats.png")
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    style = {"mixed": ("lightgray", "o", "two sites narrowed"),
             "fp32": ("black", "*", "fp32 everywhere"),
             "node-format": ("tab:blue", "s", "node_format only"),
             "plane-format": ("tab:orange", "^", "plane_format only"),
             "vertex-format": ("tab:green", "D", "vertex_format only"),
             "all": ("tab:red", "P", "every site in one format")}
    fig, axes = plt.subplots(1, 2, figsize=(13, 5))
    for ax, (cost, label, scale) in zip(axes, (("energy_nj", "modelled energy (mJ)", 1e6),
                                              ("modelled_cycles", "modelled cycles (M)", 1e6))):
        for group, (colour, marker, name) in style.items():
            mine = [r for r in rows if group_of(r) == group]
            ax.scatter([float(r[cost]) / scale for r in mine], [float(r["psnr"]) for r in mine],
                       c=colour, marker=marker, s=60 if group != "mixed" else 25, label=name,
                       zorder=1 if group == "mixed" else 2)
            if group in ("mixed", "fp32"):
                continue
            for r in mine:
                s = settings(r)
                text = s[group] if group in SITES else s[SITES[0]]
                ax.annotate(text, (float(r[cost]) / scale, float(r["psnr"])), fontsize=7,
                            xytext=(3, 3), textcoords="offset points", color=colour)
        ax.set_xlabel(label)
        ax.set_ylabel("PSNR against the converged image (dB)")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="lower right")
    fig.suptitle("motion_defocus, patch method, 16 spp: each number-format site against fp32")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
