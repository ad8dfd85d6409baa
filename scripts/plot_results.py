#!/usr/bin/env python3
"""Plots of patchsim's results, for `patchsim sweep` and `patchsim explore` alike.

    python3 plot_results.py sweep SWEEP_DIR/results.csv OUT_DIR
    python3 plot_results.py explore RESULTS.csv OUT_DIR

sweep: per scene, OUT_DIR/<scene>.png and .svg (PSNR and RMSE against wall time, modelled
cycles and modelled energy, log scales, one line per method with its samples per pixel labelled, the Pareto
front of all runs marked) and OUT_DIR/<scene>-crops.png (the same crop of every run, read from
SWEEP_DIR/images, beside the converged image, where the runs disagree most).

explore: per grid parameter, OUT_DIR/cycles_vs_<parameter>.png and .svg (modelled cycles against
the parameter, one panel per scene, one line per setting of the other parameters, or their median
and min-max band when there are many); per pair of parameters, OUT_DIR/heatmap_<a>_x_<b>.png and
.svg (cycles of every cell, the best over the other parameters, with its bottleneck stage); and
OUT_DIR/energy_vs_cycles.png and .svg (every point's modelled energy against its cycles, the
Pareto front labelled). The marker of every point is its bottleneck stage.

Both binaries write a copy of this script next to their plots, so it can be rerun on the CSV.
Needs matplotlib and numpy (Debian: python3-matplotlib).
"""

import csv
import math
import os
import re
import sys
import textwrap
from collections import defaultdict
from itertools import combinations

import matplotlib

matplotlib.use("Agg")
matplotlib.rcParams["svg.fonttype"] = "none"  # SVG text stays text: searchable, editable
matplotlib.rcParams["svg.hashsalt"] = "patchsim"  # fixed element ids: same results, same SVG
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib import ticker  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

MARKERS = "osD^vP*Xh<>"
# The pipeline's stages (docs/HARDWARE.md), each with the marker of the points it limits.
STAGE_MARKERS = {"IA": "v", "VS": "^", "HS": "<", "TS": ">", "DS": "D", "RS": "o", "PS": "s",
                 "OM": "P", "none": "x"}
STAGE_COLOURS = {"IA": "C7", "VS": "C4", "HS": "C5", "TS": "C8", "DS": "C9", "RS": "C0", "PS": "C1",
                 "OM": "C2", "none": "C3"}
# Units of the grid parameters (docs/EXPLORE.md, docs/HARDWARE.md); options such as
# branch_method have none.
UNITS = [
    (r"^tile_size$", "pixels"),
    (r"^(leaf_size|max_triangles_per_group|merge_triangles_below)$", "triangles"),
    (r"^bounds_level$", "hierarchy level, 0 = root"),
    (r"\.units$", "units"),
    (r"\.latency$", "cycles"),
    (r"\.fifo_depth$", "patches"),
    (r"\.throughput\.", "ops per unit per clock"),
    (r"^clock_ghz$", "GHz"),
    (r"^scratch_budget_bytes$", "bytes"),
]
CYCLES = "modelled cycles per frame"


# --- shared --------------------------------------------------------------------------------------

def eng(v):
    """A number with an SI prefix and three significant digits: 695355 -> 695k, 1234567 -> 1.23M."""
    if not math.isfinite(v):
        return str(v)
    v = float(f"{v:.3g}")  # round first, so 999999 becomes 1M, not 1e+03k
    for scale, prefix in ((1e12, "T"), (1e9, "G"), (1e6, "M"), (1e3, "k")):
        if abs(v) >= scale:
            return f"{v / scale:.3g}{prefix}"
    return f"{v:.3g}"


def eng_axis(axis):
    """eng() tick labels; on a log axis at 1, 2 and 5 times each power of ten when it spans few."""
    if "log" in axis.get_scale():  # also a log axis's secondary ("functionlog")
        low, high = axis.get_view_interval()
        few = low > 0 and high / low < 1e3
        axis.set_major_locator(ticker.LogLocator(subs=(1.0, 2.0, 5.0) if few else (1.0,)))
        axis.set_minor_formatter(ticker.NullFormatter())
    axis.set_major_formatter(ticker.FuncFormatter(lambda v, _: eng(v)))


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def run_name(row):
    """A method at its setting, as the legends show it: "interval time-strata=16"."""
    setting = row.get("setting", "")
    return f"{row['method']} {setting}" if setting else row["method"]


def image_label(row):
    """The method and setting as patchsim names the run's image (SweepVariant::label)."""
    setting = row.get("setting", "")
    text = f"{row['method']}-{setting}" if setting else row["method"]
    return re.sub(r"[^A-Za-z0-9._-]", "_", text)


def in_order(values):
    return list(dict.fromkeys(values))


def save(fig, out_dir, name, formats=("png", "svg")):
    written = []
    for ext in formats:
        path = os.path.join(out_dir, f"{name}.{ext}")
        # No date in the SVG either.
        fig.savefig(path, dpi=120, bbox_inches="tight",
                    metadata={"Date": None} if ext == "svg" else None)
        written.append(path)
    plt.close(fig)
    return written


# --- sweep ---------------------------------------------------------------------------------------

def pareto(points):
    """Indices of the points no other point beats in both cost (lower) and error (lower)."""
    front = []
    for i, (ci, ei) in enumerate(points):
        if not any(cj <= ci and ej <= ei and (cj, ej) != (ci, ei) for cj, ej in points):
            front.append(i)
    return sorted(front, key=lambda i: points[i][0])


def plot_scene(scene, rows, out_dir):
    methods = in_order(run_name(r) for r in rows)
    costs = [("wall_seconds", "wall time (s)"), ("modelled_cycles", "modelled cycles")]
    if all(r.get("energy_nj") for r in rows):  # CSVs before the energy model have none
        costs.append(("energy_nj", "modelled energy (nJ)"))
    errors = [("psnr", "PSNR (dB, higher is better)"), ("rmse", "RMSE (linear RGB, lower is better)")]
    fig, axes = plt.subplots(2, len(costs), figsize=(6 * len(costs), 9), squeeze=False)
    panels = [(x, y, xl, yl) for y, yl in errors for x, xl in costs]
    for ax, (xkey, ykey, xlabel, ylabel) in zip(axes.flat, panels):
        everything = []
        for k, method in enumerate(methods):
            mine = sorted((r for r in rows if run_name(r) == method), key=lambda r: int(r["spp"]))
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
        eng_axis(ax.xaxis)
        eng_axis(ax.yaxis)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].legend(fontsize=8)
    fig.suptitle(f"{scene}: error against the converged image, by cost (labels: samples per pixel)")
    fig.tight_layout()
    return save(fig, out_dir, scene)


def crop_sheet(scene, rows, images_dir, out_dir, size=48):
    converged = mpimg.imread(os.path.join(images_dir, f"{scene}-converged.png"))[..., :3]
    runs = [(run_name(r), int(r["spp"])) for r in rows]
    pictures = {(run_name(r), int(r["spp"])):
                mpimg.imread(os.path.join(images_dir, f"{scene}-{image_label(r)}-{r['spp']}.png"))[..., :3]
                for r in rows}
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
    methods = in_order(m for m, _ in runs)
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


def sweep(csv_path, out_dir):
    by_scene = defaultdict(list)
    for r in read_rows(csv_path):
        by_scene[r["scene"]].append(r)
    images_dir = os.path.join(os.path.dirname(os.path.abspath(csv_path)), "images")
    written = []
    for scene, mine in by_scene.items():
        written += plot_scene(scene, mine, out_dir)
        written.append(crop_sheet(scene, mine, images_dir, out_dir))
    return written


# --- explore -------------------------------------------------------------------------------------

def unit_of(parameter):
    return next((unit for pattern, unit in UNITS if re.search(pattern, parameter)), None)


def axis_title(parameter, wrap=False):
    unit = unit_of(parameter)
    return f"{parameter}{chr(10) if wrap else ' '}({unit})" if unit else parameter


def value_label(value, unit):
    try:
        v = float(value)
    except ValueError:
        return value
    if unit == "bytes" and v >= 1024:
        for size, prefix in ((2**30, "Gi"), (2**20, "Mi"), (2**10, "Ki")):
            if v >= size:
                return f"{v / size:.3g} {prefix}B"
    return eng(v) if abs(v) >= 1000 else value


def file_name(text):
    return re.sub(r"[^A-Za-z0-9_-]+", "_", text)


class Explore:
    """The rows of an explore CSV: its parameters are the columns between scene and total_cycles."""

    def __init__(self, rows):
        header = list(rows[0])
        self.parameters = header[1:header.index("total_cycles")]
        self.values = {p: in_order(r[p] for r in rows) for p in self.parameters}
        self.scenes = in_order(r["scene"] for r in rows)
        self.stages = in_order(r["bottleneck"] for r in rows)
        self.rows = rows

    def of(self, scene):
        return [r for r in self.rows if r["scene"] == scene]


def cycles(row):
    return float(row["total_cycles"])


def bottleneck_text(row):
    share = row.get("bottleneck_utilisation")
    return f"{row['bottleneck']} {float(share):.0%}" if share else row["bottleneck"]


def panels(count, width, height):
    """One panel per scene, up to three in a row; each panel width x height inches."""
    cols = min(count, 3)
    rows = math.ceil(count / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols, height * rows), squeeze=False)
    for ax in axes.flat[count:]:
        ax.set_visible(False)
    return fig, axes.flat[:count]


def below(fig, handles=(), text=""):
    """A legend and a caption under the panels (savefig's tight box takes them in)."""
    per_row = max(1, int(fig.get_figwidth() // 2.2))
    if handles:
        fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, 0.01), frameon=False,
                   ncol=min(len(handles), per_row), fontsize=8)
    if text:
        fig.text(0.5, -0.05 * math.ceil(len(handles) / per_row),
                 textwrap.fill(text, int(fig.get_figwidth() * 14)), ha="center", va="top",
                 fontsize=8, color="0.25")


def microsecond_axis(ax, rows):
    """Cycles as microseconds on the right, when the clock is the same at every point."""
    ratios = [cycles(r) / float(r["microseconds"]) for r in rows if float(r["microseconds"]) > 0]
    if ratios and max(ratios) - min(ratios) < 1e-6 * max(ratios):
        ratio = float(np.median(ratios))
        right = ax.secondary_yaxis("right", functions=(lambda c: c / ratio, lambda u: u * ratio))
        right.set_ylabel(f"microseconds at {ratio / 1000:.4g} GHz")
        eng_axis(right.yaxis)


def stage_handles(stages, coloured):
    return [Line2D([], [], marker=STAGE_MARKERS.get(s, "o"), linestyle="none",
                   color=STAGE_COLOURS.get(s, "0.4") if coloured else "0.3",
                   label=f"bottleneck {s}") for s in stages]


def scatter_by_stage(ax, xs, rows, colour=None, **style):
    """The points, each with its bottleneck's marker (and colour, when the caller gives none)."""
    for stage in in_order(r["bottleneck"] for r in rows):
        mine = [(x, cycles(r)) for x, r in zip(xs, rows) if r["bottleneck"] == stage]
        ax.scatter(*zip(*mine), marker=STAGE_MARKERS.get(stage, "o"), zorder=3,
                   color=colour or STAGE_COLOURS.get(stage, "0.4"), **style)


MAX_LINES = 8


def cycles_against(data, parameter, out_dir):
    values = data.values[parameter]
    x_of = {v: i for i, v in enumerate(values)}
    others = [p for p in data.parameters if p != parameter]
    settings = in_order(tuple(r[p] for p in others) for r in data.rows)
    lines = len(settings) <= MAX_LINES
    fig, axes = panels(len(data.scenes), 5.6, 4.2)
    for ax, scene in zip(axes, data.scenes):
        rows = data.of(scene)
        if lines:
            # One line per setting of the other parameters.
            handles = []
            for k, setting in enumerate(settings):
                mine = sorted((r for r in rows if tuple(r[p] for p in others) == setting),
                              key=lambda r: x_of[r[parameter]])
                xs = [x_of[r[parameter]] for r in mine]
                ax.plot(xs, [cycles(r) for r in mine], color=f"C{k % 10}", linewidth=1.6)
                scatter_by_stage(ax, xs, mine, colour=f"C{k % 10}", s=34, edgecolors="white",
                                 linewidths=0.6)
                label = ", ".join(f"{p} {v}" for p, v in zip(others, setting)) or "cycles"
                handles.append(Line2D([], [], color=f"C{k % 10}", label=label))
        else:
            # Too many settings for lines: the median and the min-max band, and every point,
            # spread a little sideways so that equal values stay visible.
            by_value = [[cycles(r) for r in rows if r[parameter] == v] for v in values]
            ax.fill_between(range(len(values)), [min(c) for c in by_value],
                            [max(c) for c in by_value], color="0.5", alpha=0.2, linewidth=0)
            ax.plot(range(len(values)), [np.median(c) for c in by_value], color="0.15",
                    linewidth=1.8)
            seen = defaultdict(int)
            xs = []
            for r in rows:
                xs.append(x_of[r[parameter]] + 0.25 * (seen[r[parameter]] / len(settings) - 0.5))
                seen[r[parameter]] += 1
            scatter_by_stage(ax, xs, rows, s=14, alpha=0.75, linewidths=0)
            handles = [Line2D([], [], color="0.15", linewidth=1.8, label="median"),
                       Rectangle((0, 0), 1, 1, color="0.5", alpha=0.2,
                                 label=f"min to max over the {len(settings)} settings of the "
                                       "other parameters")]
        ax.set_xticks(range(len(values)), [value_label(v, unit_of(parameter)) for v in values])
        ax.set_xlabel(axis_title(parameter))
        ax.set_ylabel(CYCLES)
        low, high = min(map(cycles, rows)), max(map(cycles, rows))
        if 0 < low and 8 * low < high:  # ratios read better than gaps
            ax.set_yscale("log")
        ax.margins(x=0.08, y=0.12)
        eng_axis(ax.yaxis)
        ax.grid(True, alpha=0.3)
        microsecond_axis(ax, rows)
        best = min(rows, key=cycles)
        at = value_label(best[parameter], unit_of(parameter))
        ax.set_title(f"{scene}\nbest {eng(cycles(best))} cycles at {parameter} {at}", fontsize=10)
    fig.suptitle(f"Modelled cycles against {parameter}", fontsize=12)
    fig.tight_layout()
    below(fig, handles + stage_handles(data.stages, coloured=not lines),
          "" if lines else f"Other parameters: {', '.join(others)}.")
    return save(fig, out_dir, f"cycles_vs_{file_name(parameter)}")


def heat_map(data, a, b, out_dir):
    """Cycles over a (rows) x b (columns): each cell the best point with those two values."""
    rows_of, cols_of = data.values[a], data.values[b]
    others = [p for p in data.parameters if p not in (a, b)]
    fig, axes = panels(len(data.scenes), 1.1 * len(cols_of) + 3.2, 0.65 * len(rows_of) + 1.6)
    for ax, scene in zip(axes, data.scenes):
        best = {}
        for r in data.of(scene):
            key = (r[a], r[b])
            if key not in best or cycles(r) < cycles(best[key]):
                best[key] = r
        grid = np.full((len(rows_of), len(cols_of)), np.nan)
        for (va, vb), r in best.items():
            grid[rows_of.index(va), cols_of.index(vb)] = cycles(r)
        image = ax.imshow(grid, cmap="YlOrRd", aspect="auto")
        bar = fig.colorbar(image, ax=ax)
        bar.set_label(CYCLES, fontsize=9)
        eng_axis(bar.ax.yaxis)
        for (va, vb), r in best.items():
            i, j = rows_of.index(va), cols_of.index(vb)
            shade = image.cmap(image.norm(grid[i, j]))
            dark = 0.299 * shade[0] + 0.587 * shade[1] + 0.114 * shade[2] < 0.5  # luma
            ink = "white" if dark else "black"
            ax.text(j, i - 0.12, eng(cycles(r)), ha="center", va="center", fontsize=10,
                    fontweight="bold", color=ink)
            ax.text(j, i + 0.2, bottleneck_text(r), ha="center", va="center", fontsize=8,
                    color=ink)
        i, j = np.unravel_index(np.nanargmin(grid), grid.shape)
        ax.add_patch(Rectangle((j - 0.5, i - 0.5), 1, 1, fill=False, edgecolor="black",
                               linewidth=3, clip_on=False))
        ax.set_xticks(range(len(cols_of)), [value_label(v, unit_of(b)) for v in cols_of])
        ax.set_yticks(range(len(rows_of)), [value_label(v, unit_of(a)) for v in rows_of])
        ax.set_xlabel(axis_title(b))
        ax.set_ylabel(axis_title(a, wrap=len(axis_title(a)) > 24))
        ax.set_title(scene, fontsize=10)
    fig.suptitle(f"Modelled cycles over {a} and {b}", fontsize=12)
    fig.tight_layout()
    share = " and its utilisation" if "bottleneck_utilisation" in data.rows[0] else ""
    below(fig, text=f"Each cell: modelled cycles, and the bottleneck stage{share}"
          + (f", of the best point over {', '.join(others)}" if others else "")
          + ". Outlined: the fewest cycles.")
    return save(fig, out_dir, f"heatmap_{file_name(a)}_x_{file_name(b)}")


def energy(row):
    return float(row["energy_nj"]) / 1e3  # microjoules


def energy_against_cycles(data, out_dir):
    """Every grid point's modelled energy against its cycles, the Pareto front of the two."""
    fig, axes = panels(len(data.scenes), 5.6, 4.2)
    for ax, scene in zip(axes, data.scenes):
        rows = data.of(scene)
        xs = [cycles(r) for r in rows]
        for stage in in_order(r["bottleneck"] for r in rows):
            mine = [(cycles(r), energy(r)) for r in rows if r["bottleneck"] == stage]
            ax.scatter(*zip(*mine), marker=STAGE_MARKERS.get(stage, "o"), zorder=3,
                       color=STAGE_COLOURS.get(stage, "0.4"))
        points = [(x, energy(r)) for x, r in zip(xs, rows)]
        front = pareto(points)
        ax.plot([points[i][0] for i in front], [points[i][1] for i in front], color="black",
                linestyle=":", linewidth=1.5)
        for i in front:
            label = ", ".join(f"{p} {rows[i][p]}" for p in data.parameters)
            ax.annotate(label, points[i], textcoords="offset points", xytext=(4, 4), fontsize=6)
        eng_axis(ax.xaxis)
        eng_axis(ax.yaxis)
        ax.set_xlabel(CYCLES)
        ax.set_ylabel("modelled energy per frame (uJ)")
        ax.grid(True, alpha=0.3)
        ax.set_title(scene, fontsize=10)
    fig.suptitle("Modelled energy against cycles (dotted: the Pareto front)", fontsize=12)
    below(fig, stage_handles(data.stages, True),
          "Each point a grid point; labelled, those on the front. Energy is the arithmetic's "
          "only when the hardware file models no memory.")
    return save(fig, out_dir, "energy_vs_cycles")


def explore(csv_path, out_dir):
    rows = read_rows(csv_path)
    if not rows:
        sys.exit(f"{csv_path}: no rows to plot")
    data = Explore(rows)
    if not data.parameters:
        print("no grid parameters: nothing to plot")
    written = []
    for parameter in data.parameters:
        written += cycles_against(data, parameter, out_dir)
    for a, b in combinations(data.parameters, 2):
        written += heat_map(data, a, b, out_dir)
    if data.parameters and all(r.get("energy_nj") for r in rows):
        written += energy_against_cycles(data, out_dir)
    return written


MANIFEST = "plots.txt"


def remove_earlier_plots(out_dir):
    """The figures an earlier run listed in the folder's manifest, and only those, are removed:
    a plot of a scene or parameter the new results no longer have must not stay beside them."""
    manifest = os.path.join(out_dir, MANIFEST)
    if not os.path.isfile(manifest):
        return
    with open(manifest) as f:
        for name in f.read().split("\n"):
            path = os.path.join(out_dir, name)
            if name and os.path.basename(name) == name and os.path.isfile(path):
                os.remove(path)


def main():
    modes = {"sweep": sweep, "explore": explore}
    if len(sys.argv) != 4 or sys.argv[1] not in modes:
        sys.exit(__doc__)
    out_dir = sys.argv[3]
    os.makedirs(out_dir, exist_ok=True)
    remove_earlier_plots(out_dir)
    written = [os.path.basename(p) for p in modes[sys.argv[1]](sys.argv[2], out_dir)]
    with open(os.path.join(out_dir, MANIFEST), "w") as f:
        f.write("".join(name + "\n" for name in written))
    for name in written:
        print("wrote", os.path.join(out_dir, name))


if __name__ == "__main__":
    main()
