#!/usr/bin/env python3
"""Times whole processes side by side: commands A and B in alternating rounds (which goes first
alternates), one warm-up round, wall and CPU seconds and peak resident set from the operating
system's accounting of each finished child. Prints each command's medians and the median of the
per-round ratios A/B, and writes every run to a CSV.

  scripts/whole-process.py --rounds 7 --csv out.csv \
      --a 'build/pipeline/app/patchsim render --no-progress -q --threads 1 SCENE -o out-a' \
      --b 'build/pipeline/app/patchsim render --no-progress -q --threads 2 SCENE -o out-b'
"""
import argparse
import csv
import os
import resource
import shlex
import statistics
import subprocess
import time


def run(command):
    start = time.perf_counter()
    child = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - start
    if status != 0:
        raise SystemExit(f"{shlex.join(command)} exited with status {status}")
    return {"wall_s": wall, "user_s": usage.ru_utime, "sys_s": usage.ru_stime,
            "peak_mib": usage.ru_maxrss / 1024.0}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--a", required=True, help="command A, split as a shell splits words")
    parser.add_argument("--b", required=True, help="command B")
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--csv", help="every run, one row each")
    args = parser.parse_args()
    commands = {"A": shlex.split(args.a), "B": shlex.split(args.b)}
    for name in "AB":
        run(commands[name])  # warm-up: page cache, the host's memory
    rows = []
    for r in range(args.rounds):
        order = "AB" if r % 2 == 0 else "BA"
        for name in order:
            rows.append({"round": r, "command": name, **run(commands[name])})
    if args.csv:
        with open(args.csv, "w", newline="") as out:
            writer = csv.DictWriter(out, fieldnames=list(rows[0].keys()))
            writer.writeheader()
            writer.writerows(rows)
    for name in "AB":
        mine = [row for row in rows if row["command"] == name]
        print(f"{name}: {shlex.join(commands[name])}")
        for key in ("wall_s", "user_s", "sys_s", "peak_mib"):
            values = [row[key] for row in mine]
            print(f"  {key:9s} median {statistics.median(values):8.3f}"
                  f"  (min {min(values):.3f}, max {max(values):.3f})")
    ratios = [a["wall_s"] / b["wall_s"] for a, b in
              zip([x for x in rows if x["command"] == "A"], [x for x in rows if x["command"] == "B"])]
    print(f"A/B wall: median {statistics.median(ratios):.3f} "
          f"(min {min(ratios):.3f}, max {max(ratios):.3f}) over {len(ratios)} rounds")


if __name__ == "__main__":
    main()
