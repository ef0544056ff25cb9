#!/usr/bin/env bash
# Installs the Debian 12 packages Virtuelium-C builds and tests with
# (DESIGN.md section 3).  Installs only what is missing, so a second run is a
# quick no-op.  Runs apt-get as root, or through sudo.
set -euo pipefail

packages=(
  build-essential cmake pkg-config python3
  libceres-dev libgsl-dev liblapacke-dev
  libopencv-dev libopencv-contrib-dev libopenexr-dev
  libcmocka-dev libsqlite3-dev libyaml-dev libxml2-dev
  libembree-dev libassimp-dev libopenmpi-dev openmpi-bin
  iproute2
  libcairo2-dev clang libclang-rt-14-dev
  hyperfine
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo > /dev/null || { echo "install-deps: run as root or install sudo" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
echo "install-deps: installing ${missing[*]}"
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
