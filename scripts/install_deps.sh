#!/usr/bin/env bash
# Installs the Debian 12 packages HapticBox needs to build, test and run.
# Only packages that are missing are installed; needs root (or sudo) when any are.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config git ca-certificates
  libopenmesh-dev libembree-dev libtbb-dev libeigen3-dev
  libvtk9-dev libvtk9-qt-dev qtbase5-dev
  libusb-1.0-0-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev nlohmann-json3-dev libfmt-dev libxxhash-dev libzstd-dev
  libplplot-dev plplot-driver-cairo
  libopenmpi-dev openmpi-bin
  xvfb xauth
  libocct-data-exchange-dev libocct-modeling-algorithms-dev libocct-modeling-data-dev libocct-foundation-dev
  libassimp-dev zlib1g-dev
  python3-nibabel python3-pydicom
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install_deps: installing missing Debian packages: ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install_deps: need root to install: ${missing[*]}" >&2; exit 1; fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
