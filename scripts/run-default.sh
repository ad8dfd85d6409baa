#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job on the built-in default scene.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
./build/pipeline/app/patchsim
