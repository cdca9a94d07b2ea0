#!/usr/bin/env bash
# All tests: install what is missing, build, fetch the datasets, then run every CTest suite.
# The whole run is under xvfb-run -a so the suites labelled `gui` get a display; the others
# do not need one (CLI tests unset DISPLAY themselves). -noreset keeps Xvfb from resetting
# (and refusing connections for a moment) each time its last client leaves.
set -euo pipefail
cd "$(dirname "$0")"
bash scripts/build.sh
bash datasets/fetch.sh build/datasets/hb_generate_datasets

# Layering: the core never includes VTK, Qt or libusb.
if grep -rEn '#\s*include\s*[<"](vtk|Q[A-Z]|qt|libusb)' src; then
  echo "test.sh: src/ (the core) includes a VTK, Qt or libusb header" >&2
  exit 1
fi

cd build
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ctest --output-on-failure -j2 --timeout 600
