#!/usr/bin/env bash
# ParaView's Python (pvpython) beside Debian's VTK, without installing python3-paraview.
# On Debian 12, python3-paraview conflicts with python3-vtk9 (which libvtk9-dev needs; see
# install_deps.sh), and pvpython is in it. So: `apt-get download python3-paraview` of
# paraview-dev's version (a Debian package, not installed: no dpkg conflict) and `dpkg-deb -x`
# it into DIR/root. ParaView's own pvpython, run from DIR/root/usr/bin, finds its own vtkmodules
# first (they sit beside it, ../lib/python3/dist-packages), so Debian's python3-vtk9 is not in
# its way; numpy is Debian's.
#   paraview_python.sh DIR   prints the path of pvpython on success.
set -euo pipefail
dir="${1:?usage: paraview_python.sh DIR}"
config=/usr/lib/x86_64-linux-gnu/cmake/paraview-5.11
[ -f "$config/paraview-config.cmake" ] || { echo "paraview_python: no $config (apt-get install --no-install-recommends paraview-dev)" >&2; exit 1; }
mkdir -p "$dir"
dir="$(cd "$dir" && pwd)"
if [ ! -x "$dir/root/usr/bin/pvpython" ]; then
  version="$(dpkg-query -W -f='${Version}' paraview-dev)"
  rm -rf "$dir/download" && mkdir -p "$dir/download"
  (cd "$dir/download" && apt-get download -q "python3-paraview=$version" >/dev/null 2>&1) ||
    (apt-get update -q >/dev/null && cd "$dir/download" && apt-get download -q "python3-paraview=$version" >/dev/null) ||
    { echo "paraview_python: cannot download python3-paraview $version" >&2; exit 1; }
  dpkg-deb -x "$dir"/download/python3-paraview_*.deb "$dir/root"
  rm -rf "$dir/download"
fi
echo "$dir/root/usr/bin/pvpython"
