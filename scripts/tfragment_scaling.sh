#!/usr/bin/env bash
# The t-fragment method's own claim (Widmer et al. 2016, section 4.3): tracing each lens ray once
# and sampling time afterwards gains on time-sampled tracing as the motion samples per lens ray
# grow. Renders docs/accuracy/approximate/tfragment_scaling.json (one lens ray per pixel, as in
# the paper) both ways at 1 to 64 motion samples and writes, in OUT (default
# docs/accuracy/approximate), tfragment_scaling.csv (traversal work from the counters, modelled
# cycles) and tfragment_scaling.png/.svg (with Debian's python3-matplotlib).
set -euo pipefail
cd "$(dirname "$0")/.."
PATCHSIM=${PATCHSIM:-build/pipeline/app/patchsim}
OUT=${1:-docs/accuracy/approximate}
SCENE=docs/accuracy/approximate/tfragment_scaling.json
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
echo "motion_samples,tracing,traversal_tests,modelled_cycles" > "$OUT/tfragment_scaling.csv"
for m in 1 2 4 8 16 32 64; do
  for mode in decoupled time-sampled; do
    flag=""
    [ "$mode" = time-sampled ] && flag="--time-sampled"
    "$PATCHSIM" render -q "$SCENE" --method tfragment --motion-samples "$m" $flag --threads 1 \
      --no-progress -o "$TMP/$mode-$m" > /dev/null
    /usr/bin/python3 - "$TMP/$mode-$m/stats.json" "$m" "$mode" >> "$OUT/tfragment_scaling.csv" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
c = {k: v["value"] for k, v in d["counters"].items()}
tests = sum(c[k] for k in ("TF/Ray-node tests", "TF/Capsule tests", "TF/Sphere tests", "TF/Cube tests"))
print(f"{sys.argv[2]},{sys.argv[3]},{tests},{d['timing']['total_cycles']}")
PY
  done
done
/usr/bin/python3 - "$OUT" <<'PY'
import csv, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
out = sys.argv[1]
rows = list(csv.DictReader(open(f"{out}/tfragment_scaling.csv")))
fig, axes = plt.subplots(1, 2, figsize=(11, 4))
for mode, marker in (("decoupled", "o"), ("time-sampled", "s")):
    mine = [r for r in rows if r["tracing"] == mode]
    m = [int(r["motion_samples"]) for r in mine]
    axes[0].plot(m, [int(r["traversal_tests"]) / 1e6 for r in mine], marker=marker, label=mode)
    axes[1].plot(m, [float(r["modelled_cycles"]) / 1e6 for r in mine], marker=marker, label=mode)
for ax, label in zip(axes, ("box, capsule, sphere and cube tests (millions)", "modelled cycles (millions)")):
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xlabel("motion samples per lens ray")
    ax.set_ylabel(label)
    ax.grid(alpha=0.3)
    ax.legend()
fig.suptitle("t-fragments: decoupled tracing against time-sampled tracing (160x120, 1 lens ray per pixel)")
fig.tight_layout()
for ext in ("png", "svg"):
    fig.savefig(f"{out}/tfragment_scaling.{ext}", dpi=100)
PY
echo "wrote $OUT/tfragment_scaling.csv and tfragment_scaling.png/.svg"
