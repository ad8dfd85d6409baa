#!/usr/bin/env bash
# Installs clang and its sanitizer runtimes if missing, builds the libFuzzer targets with ASan and
# UBSan (build-fuzz/), and runs each for FUZZ_SECONDS (default 60) from a seed corpus of the
# shipped scenes and the OpenSubdiv cages. Any crash, leak or sanitizer report fails the run.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
missing=()
for p in clang libclang-rt-14-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" \
    || { $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"; }
fi
CC=clang CXX=clang++ BUILD_DIR=build-fuzz bash scripts/build.sh -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DPATCHSIM_SANITIZE=address,undefined -DPATCHSIM_BUILD_FUZZERS=ON -DPATCHSIM_BUILD_TESTS=OFF \
  -DPATCHSIM_BUILD_BENCHMARKS=OFF -DPATCHSIM_WARNINGS_AS_ERRORS=OFF
seconds=${FUZZ_SECONDS:-60}
corpus=build-fuzz/corpus
rm -rf "$corpus"
mkdir -p "$corpus/scene_reader" "$corpus/obj_reader" "$corpus/hardware_config"
cp scenes/*.json "$corpus/scene_reader/"
cp pipeline/hw/*.json "$corpus/hardware_config/"
cp scenes/cages/*.obj "$corpus/obj_reader/"
cp tests/data/opensubdiv/*.obj "$corpus/obj_reader/"
for name in scene_reader obj_reader hardware_config; do
  echo "fuzzing $name for ${seconds}s"
  ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS="suppressions=$PWD/scripts/lsan-suppressions.txt" "build-fuzz/fuzz/fuzz_$name" -max_total_time="$seconds" -print_final_stats=1 \
    -rss_limit_mb=4096 -artifact_prefix="build-fuzz/crash-$name-" "$corpus/$name" 2>&1 | tail -n 12
done
