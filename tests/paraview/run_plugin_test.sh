#!/usr/bin/env bash
# The ParaView plugin's test (CTest ParaViewPluginTest): ParaView 5.11's own pvpython, taken from
# the Debian package python3-paraview without installing it (scripts/paraview_python.sh: it
# conflicts with python3-vtk9), loads the plugin and runs plugin_field.py on the armadillo:
# the error field's arrays against `hapticbox field`'s, bit for bit.
# Usage: run_plugin_test.sh HAPTICBOX_CLI PLUGIN PVPYTHON PYTHONPATH_OF_HAPTICBOX WORK_DIR DATASETS_DIR
set -euo pipefail
cli="$1" plugin="$2" pvpython="$3" module_dir="$4" work="$5" data="$6"
here="$(cd "$(dirname "$0")" && pwd)"
mesh="$data/meshes/armadillo.off"
[ -f "$mesh" ] || { echo "run_plugin_test: $mesh missing (datasets/fetch.sh)"; exit 1; }
[ -f "$plugin" ] || { echo "run_plugin_test: $plugin missing (the plugin was not built)"; exit 1; }
mkdir -p "$work"
[ -x "$pvpython" ] || { echo "run_plugin_test: $pvpython missing (scripts/paraview_python.sh)"; exit 1; }
quiet() { "$@" >"$work/step.log" 2>&1 || { cat "$work/step.log"; exit 1; }; }
quiet "$cli" bake "$mesh" -o "$work/armadillo.hbox" --cache "$work/cache"
quiet "$cli" field "$work/armadillo.hbox" "$mesh" -o "$work/armadillo_field.vtp"
PYTHONPATH="$module_dir" /usr/bin/python3 - "$mesh" "$work/armadillo.vtp" <<'PY'
import sys
import hapticbox
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter
w = vtkXMLPolyDataWriter()
w.SetFileName(sys.argv[2])
w.SetInputData(hapticbox.polydata(hapticbox.Model(sys.argv[1])))
w.SetDataModeToBinary()
assert w.Write() == 1
PY
# pvpython needs no display for this (no view is rendered).
env -u DISPLAY "$pvpython" --force-offscreen-rendering "$here/plugin_field.py" "$plugin" "$work/armadillo.vtp" \
  "$work/armadillo.hbox" "$work/armadillo_field.vtp"
