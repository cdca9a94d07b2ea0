#!/usr/bin/env bash
# Installs the Debian 12 packages HapticBox needs to build, test and run.
# Only packages that are missing are installed; needs root (or sudo) when any are.
#   --check   only say what is missing or in the way (exit 1 when anything is), install nothing.
# Living beside ParaView: on Debian 12, python3-paraview (which `paraview` recommends, so a
# plain `apt install paraview` brings it) conflicts with python3-vtk9, a dependency of
# libvtk9-dev. With it installed apt would remove ParaView's Python or refuse: that case is
# detected first and explained (exit 1) before apt runs. `paraview` alone does not conflict.
set -euo pipefail
CHECK_ONLY=0
[ "${1:-}" = "--check" ] && CHECK_ONLY=1

PACKAGES=(
  build-essential cmake pkg-config git ca-certificates
  libopenmesh-dev libembree-dev libtbb-dev libeigen3-dev
  libvtk9-dev libvtk9-qt-dev qtbase5-dev
  libusb-1.0-0-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev nlohmann-json3-dev libfmt-dev libxxhash-dev libzstd-dev libqhull-dev
  libplplot-dev plplot-driver-cairo
  libopenmpi-dev openmpi-bin
  xvfb xauth
  clang libclang-rt-dev  # sanitizer build and libFuzzer targets (scripts/build_sanitized.sh)
  libocct-data-exchange-dev libocct-modeling-algorithms-dev libocct-modeling-data-dev libocct-foundation-dev
  libassimp-dev zlib1g-dev
  libopenvdb-dev libboost-iostreams-dev  # peers/: the distance field peer (FindOpenVDB asks for Boost iostreams, which libopenvdb-dev does not bring)
  python3-nibabel python3-pydicom
  universal-ctags  # scripts/long_functions.sh (./test.sh: no function over 150 lines, no file over 600)
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib  # python/: the hapticbox module, its tests, examples/
  paraview-dev libqt5svg5-dev  # paraview/: the plugin (without its Recommends: python3-paraview conflicts with python3-vtk9, see above; its CMake package also asks for Qt5Svg)
)

# HB_PRETEND_INSTALLED="pkg ..." / HB_PRETEND_MISSING="pkg ..." treat those packages as
# installed / missing (the tests of this script use them with --check).
installed() {
  case " ${HB_PRETEND_INSTALLED:-} " in *" $1 "*) return 0 ;; esac
  case " ${HB_PRETEND_MISSING:-} " in *" $1 "*) return 1 ;; esac
  dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"
}

# ParaView's Python in the way of libvtk9-dev (through python3-vtk9)?
needs_vtk=0
for p in libvtk9-dev python3-vtk9; do installed "$p" || needs_vtk=1; done
if installed python3-paraview && [ "$needs_vtk" = 1 ]; then
  cat >&2 <<MSG
install_deps: cannot install HapticBox's build dependencies: the installed Debian package
python3-paraview (ParaView's Python, which 'apt install paraview' brings along) conflicts with
python3-vtk9, which libvtk9-dev needs (HapticBox builds against Debian's VTK 9.1). Debian 12
builds ParaView 5.11 with its own VTK, so the two cannot be installed together; nothing was
changed. Choose one:
  1. Keep the ParaView application, drop only its Python (the 'paraview' package itself does
     not conflict), then run this again:
       sudo apt-get remove python3-paraview && bash scripts/install_deps.sh
     (ParaView's Python shell and pvpython go; reading HapticBox's .vtp and .csv does not.)
  2. Keep all of Debian's ParaView (with Python) and build HapticBox in a Debian 12 container
     or chroot (e.g. docker run -it debian:12), where libvtk9-dev installs.
  3. Replace Debian's ParaView by ParaView's own binary release (https://www.paraview.org/download/,
     a folder such as /opt/ParaView-5.11, no Debian package, Python included):
       sudo apt-get remove paraview python3-paraview && bash scripts/install_deps.sh
MSG
  exit 1
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! installed "$p"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
if [ "$CHECK_ONLY" = 1 ]; then
  echo "install_deps: missing Debian packages: ${missing[*]}" >&2
  exit 1
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
