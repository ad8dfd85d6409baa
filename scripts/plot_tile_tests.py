#!/usr/bin/env python3
"""Tightness of every tile test from one `patchsim verify-tiles --summary FILE` run.

    python3 plot_tile_tests.py SUMMARY_CSV OUTPUT_STEM

Writes OUTPUT_STEM.png and OUTPUT_STEM.svg: per variant and case model, the false accepts as a
percentage of the cases that truly miss (left), and the time-interval excess over the exact
interval, median and 95th percentile (right); the hierarchy checks below (traversal false accepts,
screen-bounds false accepts per level, branch-node levels above the lowest possible). Every
variant's false rejects are printed beside its name: they must be 0. Needs matplotlib
(Debian: python3-matplotlib).
"""

import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = {"pinhole": "#4477aa", "lens": "#ee6677", "hierarchy": "#228833"}


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with open(sys.argv[1], newline="") as f:
        rows = list(csv.DictReader(f))
    boxes = [r for r in rows if r["model"] in ("pinhole", "lens")]
    hierarchy = [r for r in rows if r["model"] == "hierarchy"]
    names = list(dict.fromkeys(r["variant"] for r in boxes))
    fig, axes = plt.subplots(2, 2, figsize=(13, 10), gridspec_kw={"height_ratios": [3, 2]})
    height = 0.38
    for k, model in enumerate(("pinhole", "lens")):
        mine = {r["variant"]: r for r in boxes if r["model"] == model}
        ys = [i + (k - 0.5) * height for i in range(len(names))]
        fa = [float(mine[n]["false_accept_percent"]) if n in mine else 0 for n in names]
        axes[0][0].barh(ys, fa, height, color=COLOURS[model], label=model)
        med = [float(mine[n]["excess_median"]) if n in mine else 0 for n in names]
        p95 = [float(mine[n]["excess_p95"]) if n in mine else 0 for n in names]
        axes[0][1].barh(ys, p95, height, color=COLOURS[model], alpha=0.35,
                        label=model + " p95")
        axes[0][1].barh(ys, med, height, color=COLOURS[model], label=model + " median")
        for y, m, p in zip(ys, med, p95):
            axes[0][1].text(p + 0.01, y, f"{m:.3g} / {p:.3g}", va="center", fontsize=6)
    labels = []
    for n in names:
        rejects = sum(int(r["false_rejects"]) for r in boxes if r["variant"] == n)
        labels.append(f"{n}  (false rejects {rejects})")
    for ax in axes[0]:
        ax.set_yticks(range(len(names)))
        ax.set_yticklabels(labels if ax is axes[0][0] else names, fontsize=8)
        ax.invert_yaxis()
        ax.legend(fontsize=8)
        ax.grid(axis="x", alpha=0.3)
    cases = boxes[0]["cases"] if boxes else "?"
    axes[0][0].set_xlabel("false accepts, % of the cases that truly miss")
    axes[0][0].set_title(f"box cases ({cases} per model)")
    axes[0][1].set_xlabel("time-interval excess over the exact interval (shutter fraction)")
    axes[0][1].set_title("how much time the test keeps that no ray needs")
    checks = [r for r in hierarchy if not r["variant"].startswith("branch-")]
    branches = [r for r in hierarchy if r["variant"].startswith("branch-")]
    axes[1][0].barh(range(len(checks)), [float(r["false_accept_percent"]) for r in checks],
                    color=COLOURS["hierarchy"])
    axes[1][0].set_yticks(range(len(checks)))
    axes[1][0].set_yticklabels([f"{r['variant']}  (false rejects {r['false_rejects']})"
                                for r in checks], fontsize=8)
    axes[1][0].invert_yaxis()
    axes[1][0].set_xlabel("false accepts, % of the hierarchy cases that truly miss")
    axes[1][0].set_title("hierarchy cases: traversals and screen bounds per level")
    axes[1][1].barh(range(len(branches)), [float(r["excess_p95"]) for r in branches],
                    color=COLOURS["hierarchy"], alpha=0.35, label="p95")
    axes[1][1].barh(range(len(branches)), [float(r["excess_median"]) for r in branches],
                    color=COLOURS["hierarchy"], label="median")
    axes[1][1].set_yticks(range(len(branches)))
    axes[1][1].set_yticklabels([f"{r['variant']}  (false rejects {r['false_rejects']})"
                                for r in branches], fontsize=8)
    axes[1][1].invert_yaxis()
    axes[1][1].legend(fontsize=8)
    axes[1][1].set_xlabel("levels above the lowest node over every hit leaf")
    axes[1][1].set_title("branch node: where rays start")
    for ax in axes[1]:
        ax.grid(axis="x", alpha=0.3)
    fig.tight_layout()
    for ext in ("png", "svg"):
        fig.savefig(f"{sys.argv[2]}.{ext}", dpi=110)


if __name__ == "__main__":
    main()
