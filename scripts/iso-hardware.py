#!/usr/bin/env python3
"""Writes pipeline/hw/iso_arithmetic.json: the default hardware with every rasterizer (RS) and
output-merger (OM) operation priced by its arithmetic against one shared budget per unit.

The default file's throughputs are round numbers (docs/HARDWARE.md), and they decide which method
is cheapest: a sample test at 32 per clock, a ray-box test at 8. Here each kind costs the
arithmetic operations its kernel performs (a fused multiply-add, a compare, a min or max, a select
count one; a reciprocal or divide four), counted in the code named beside it, and a unit does
BUDGET of them per clock, so every method buys its operations from the same datapath. The budget
is set so a ray-box test keeps about its default rate, which leaves the overall scale of the
cycles near the default's. Memory traffic is not priced here (each kind's bytes are listed for
the memory model).

    scripts/iso-hardware.py            # writes the file
    scripts/iso-hardware.py --markdown # prints the table of docs/HARDWARE.md
"""
import json
import pathlib
import sys

RS_BUDGET = 256  # arithmetic operations per RS unit per clock
OM_BUDGET = 16   # per OM unit per clock

# (stage, kind, operations, bytes read, where counted, how)
COSTS = [
    ("RS", "plane_tests", 7, 24, "rasterizer/patent/tile_frustum.cpp",
     "n-vertex select (3), plane distance (3 FMA), compare (1)"),
    ("RS", "time_intervals", 7, 0, "rasterizer/patent/tile_frustum.cpp insideInterval",
     "d0 - d1 (1), divide (4), guard add (1), clamp to the shutter (1)"),
    ("RS", "samples_tested", 3, 4, "tile_traversal.cpp; bounding_rasterizer.cpp testRect",
     "the sample's time against a range or stratum (2 compares), mask or skip (1)"),
    ("RS", "ray_box_tests", 29, 48, "rasterizer/patent/moving_box_ray.h hitsMovingBox",
     "per axis two entry distances (4 FMA), min, max and the running max and min (4); "
     "slack and final compare (5)"),
    ("RS", "ray_triangle_tests", 56, 72, "rasterizer/common/watertight_triangle.h",
     "vertices at the ray's time (9 FMA), translate (9), shear (6), edge functions (6), signs (6), "
     "determinant and its checks (4), depth (6), reciprocal (4), range (2), barycentrics (4)"),
    ("RS", "edge_tests", 29, 8, "rasterizer/patent/screen_pass.cpp, common/screen_triangle.h",
     "per edge two subtracts, a multiply and a multiply-add (4) and the tie-rule compare (1), "
     "masks (2); the perspective-correct depth and barycentrics (6 multiplies, 2 adds, a "
     "reciprocal: 12), charged with every test though only covered samples need them"),
    ("RS", "triangle_setups", 150, 72, "bounding_rasterizer.cpp spanBounds",
     "six vertex positions (3 FMA each), depth checks (2), reciprocal (4), circle of confusion "
     "(3), projection (2), box growth (8): 22 per point; pixel rectangle (18)"),
    ("RS", "edge_setups", 49, 36, "rasterizer/common/screen_triangle.cpp setupScreenTriangle",
     "from three snapped vertices: edge coefficients (6), twice the area (4), orientation and "
     "the flip (1 + 6), tie rule (9), area (1), box (8), small-triangle check (4), pixel "
     "rectangle (8), kind (2)"),
    ("RS", "lens_edge_tests", 66, 16, "rasterizer/patent/screen_pass.cpp, common/lens_triangle.h",
     "per edge the sample's offset from the edge's first vertex (2), the edge seen from the lens "
     "point (4), the lens offset term (4) and the function (4): 14 each, 42; signs against the "
     "canonical order and the all-or-none test (8); depth and barycentrics (12) and the depth range "
     "(4), charged with every test"),
    ("RS", "lens_edge_setups", 89, 48, "rasterizer/common/lens_triangle.cpp setupLensTriangle",
     "from three projected vertices: canonical order per edge (9 compares, 3 swaps), differences "
     "(9), each vertex's spread |c| R (3) and its box (12), min and max (12), to pixels with the "
     "margin (16), guard band (8), floor and clamp (14), kind (3)"),
    ("RS", "nodes_built", 24, 96, "rasterizer/patent/patch_hierarchy.cpp",
     "a node's moving box from its two children: 6 min or max at each shutter end per child pair (bounds0, bounds1), two pairs"),
    ("OM", "depth_tests", 2, 32, "rasterizer/common/visibility_buffer.h",
     "depth compare (1), record write select (1)"),
    ("OM", "transparent_fragments", 12, 32, "rasterizer/common/transparent_layers.cpp",
     "insertion into a sample's depth-sorted layers (about 6 compares and 6 moves)"),
]


def main():
    root = pathlib.Path(__file__).resolve().parent.parent
    budgets = {"RS": RS_BUDGET, "OM": OM_BUDGET}
    if "--markdown" in sys.argv[1:]:
        print("| stage | operation | arithmetic ops | bytes read | throughput (budget / ops) | counted in | how |")
        print("|---|---|---|---|---|---|---|")
        for stage, kind, ops, nbytes, where, how in COSTS:
            rate = budgets[stage] / ops
            print(f"| {stage} | `{kind}` | {ops} | {nbytes} | {budgets[stage]} / {ops} = {rate:.3g} "
                  f"| {where} | {how} |")
        return 0
    config = json.loads((root / "pipeline/hw/default.json").read_text())
    for stage, kind, ops, _, _, _ in COSTS:
        config["stages"][stage]["throughput"][kind] = round(budgets[stage] / ops, 4)
    lines = ["{"]
    lines.append(f'  "clock_ghz": {config["clock_ghz"]},')
    lines.append(f'  "scratch_budget_bytes": {config["scratch_budget_bytes"]},')
    lines.append('  "stages": {')
    stages = list(config["stages"].items())
    for i, (name, stage) in enumerate(stages):
        comma = "," if i + 1 < len(stages) else ""
        lines.append(f'    "{name}": {json.dumps(stage)}{comma}')
    lines += ["  }", "}"]
    (root / "pipeline/hw/iso_arithmetic.json").write_text("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
