#!/usr/bin/env bash
# Installs the Debian 12 packages patchsim needs, if any is missing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config fonts-dejavu-core
  libosd-dev libglm-dev libopenimageio-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev valgrind
  libopenmpi-dev openmpi-bin libembree-dev libhwy-dev python3-matplotlib
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
