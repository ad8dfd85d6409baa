#!/usr/bin/env python3
"""Times two builds of one Google Benchmark program side by side, in one run.

Wall times on a shared guest drift by tens of percent between runs, so a before/after claim is
only worth the ratio of medians taken from alternating rounds: each round runs the old and the
new binary once (which goes first alternates), every row once, rows in random order. The table
gives each row's median real time for both builds, new/old, and flags rows slower than the
threshold. Exit 1 if any row is flagged, so the script can gate a change.

  scripts/compare-bench.py OLD_BINARY NEW_BINARY --filter REGEX --rounds 5 [--cpu 0]
      [--csv out.csv] [--threshold 1.05]
"""
import argparse
import json
import statistics
import subprocess
import sys
import tempfile


def run_once(binary, regex, cpu, min_time):
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        command = [binary, f"--benchmark_filter={regex}", "--benchmark_enable_random_interleaving=true",
                   f"--benchmark_out={out.name}", "--benchmark_out_format=json",
                   "--benchmark_format=console"]
        if min_time:
            command.append(f"--benchmark_min_time={min_time}")
        if cpu is not None:
            command = ["taskset", "-c", str(cpu)] + command
        finished = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if finished.returncode != 0:
            sys.exit(f"{binary} failed (exit {finished.returncode}):\n{finished.stderr}")
        text = open(out.name).read()
        if not text.strip():  # a filter the program cannot compile ends with no rows
            sys.exit(f"{binary} wrote no results:\n{finished.stderr}")
        rows = json.loads(text)["benchmarks"]
    # real_time in the row's own unit; both builds report the same unit for the same row.
    return {row["name"]: (row["real_time"], row["time_unit"]) for row in rows
            if row.get("run_type", "iteration") == "iteration"}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("--filter", default=".")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--cpu", type=int, help="pin both builds to this CPU (one-thread rows)")
    parser.add_argument("--min-time", help="passed to --benchmark_min_time in seconds (e.g. 0.2)")
    parser.add_argument("--threshold", type=float, default=1.05,
                        help="flag rows whose new/old median ratio exceeds this")
    parser.add_argument("--csv", help="also write the table here")
    args = parser.parse_args()
    if args.rounds < 1:
        parser.error("--rounds must be at least 1")

    times = {"old": {}, "new": {}}
    units = {}
    for round_index in range(args.rounds):
        order = ["old", "new"] if round_index % 2 == 0 else ["new", "old"]
        for build in order:
            binary = args.old if build == "old" else args.new
            for name, (value, unit) in run_once(binary, args.filter, args.cpu, args.min_time).items():
                times[build].setdefault(name, []).append(value)
                units[name] = unit
        print(f"round {round_index + 1}/{args.rounds} done", file=sys.stderr)

    names = [name for name in times["new"] if name in times["old"]]
    missing = sorted(set(times["old"]) ^ set(times["new"]))
    lines = ["benchmark,unit,old_median,new_median,new_over_old,rounds"]
    flagged = 0
    ratios = []
    print(f"{'benchmark':60} {'old':>10} {'new':>10} {'new/old':>8}")
    for name in names:
        old = statistics.median(times["old"][name])
        new = statistics.median(times["new"][name])
        ratio = new / old if old > 0 else float("inf")
        ratios.append(ratio)
        mark = "  SLOWER" if ratio > args.threshold else ""
        flagged += bool(mark)
        print(f"{name:60} {old:10.3f} {new:10.3f} {ratio:8.3f}{mark}  ({units[name]})")
        lines.append(f"{name},{units[name]},{old:.4f},{new:.4f},{ratio:.4f},{len(times['new'][name])}")
    if ratios:
        print(f"{len(ratios)} rows; median new/old {statistics.median(ratios):.3f}; "
              f"range {min(ratios):.3f} to {max(ratios):.3f}; {flagged} above {args.threshold}")
    for name in missing:
        print(f"only in one build: {name}")
    if args.csv:
        with open(args.csv, "w") as out:
            out.write("\n".join(lines) + "\n")
    return 1 if flagged else 0


if __name__ == "__main__":
    sys.exit(main())
