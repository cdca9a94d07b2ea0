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

# Long algorithm tests (decomposition, convergence) skipped in the sanitizer run below.
HB_ASAN_SKIP='_NOT_BUILT|AutoDecompositionTest|ErrorShrinksAsDensitiesGrow|EllipsoidDepthConvergesToExact|QuadFetchEqualsPerSampleFetchAtEveryTileSize'

cd build
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ctest --output-on-failure -j2 --timeout 600

# Hostile input: the core and device suites under AddressSanitizer + UndefinedBehaviorSanitizer
# (clang, build-asan/, only what they need), then each libFuzzer target briefly from its seeds
# (scripts/fuzz.sh runs them long). A few long algorithm tests that read no file are left to
# the plain run above.
cd ..
bash scripts/build_sanitized.sh
(cd build-asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  LSAN_OPTIONS=suppressions=$PWD/../scripts/lsan_suppressions.txt \
  ctest --output-on-failure -j2 --timeout 600 -E "${HB_ASAN_SKIP}")
bash scripts/fuzz.sh "${HB_FUZZ_SECONDS:-20}"
