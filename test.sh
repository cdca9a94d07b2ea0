#!/usr/bin/env bash
# All tests: install what is missing, build, fetch the datasets, then run every CTest suite.
# The whole run is under xvfb-run -a so the suites labelled `gui` get a display; the others
# do not need one (CLI tests unset DISPLAY themselves). -noreset keeps Xvfb from resetting
# (and refusing connections for a moment) each time its last client leaves.
#
# Then the hostile-input stage: the core and device suites built with clang,
# AddressSanitizer + UndefinedBehaviorSanitizer (+ float-cast-overflow) in build-asan/ (only
# those suites and the fuzz targets are built: no VTK, Qt, CLI, MPI or benchmarks), run without
# the few long algorithm tests that read no file (they run in the plain suite above), then each
# libFuzzer target for HB_FUZZ_SECONDS (default 10 s), two at a time. scripts/fuzz.sh runs
# them long. HB_HOSTILE=0 skips the stage (e.g. for a quick local run).
set -euo pipefail
cd "$(dirname "$0")"
bash scripts/build.sh
bash datasets/fetch.sh build/datasets/hb_generate_datasets

# Layering: the core never includes VTK, Qt, libusb or OpenVDB (the peers have their own layer).
if grep -rEn '#\s*include\s*[<"](vtk|Q[A-Z]|qt|libusb|openvdb)' src; then
  echo "test.sh: src/ (the core) includes a VTK, Qt, libusb or OpenVDB header" >&2
  exit 1
fi
# Rooms: no folder-level include cycle in src/, and device/ includes no evaluation/ header.
bash scripts/folder_edges.sh --check
# Size: no source file over 600 lines and no function over 150 in the code folders.
bash scripts/long_functions.sh --check
# Comments say what and why: no ISO date or issue number in a code comment.
bash scripts/check_comments.sh

(cd build && xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ctest --output-on-failure -j2 --timeout 600)

[ "${HB_HOSTILE:-1}" = 0 ] && exit 0
fuzz_seconds=${HB_FUZZ_SECONDS:-10}
[[ "$fuzz_seconds" =~ ^[0-9]+$ ]] || { echo "test.sh: HB_FUZZ_SECONDS must be a whole number of seconds, not '$fuzz_seconds'" >&2; exit 2; }
# Long algorithm tests (convergence, decomposition, every-tile-size and armadillo fetch
# comparisons, several-box refinement): they parse no input and take most of the sanitized
# suite's time; the Release run above covers them.
asan_skip='ErrorShrinksAsDensitiesGrow|EllipsoidDepthConvergesToExact|AutoDecompositionTest|QuadFetchEqualsPerSampleFetchOnArmadillo|QuadFetchEqualsPerSampleFetchAtEveryTileSize|SeamCrossingKeepsContact|ASceneOfSeveralRefinedBoxesAnswersExactly'
# ... and the budgeted bakes, a decomposition run twice, the stroke and many-probe agreement runs, the analytic sphere and the
# codec's ratio search (4-30 s each under the sanitizers, the input they read is their own).
asan_skip+='|QueryStateTest|RouteRuleTest|ErrorBudgetTest|ResolvedAutomaticPiecesAreTheDecompositionsOwn|SphereDepthAndNormalMatchAnalyticAnswer|RoutedQueriesAskOneBox|SceneOfSeveralBoxesGivesTheSameAnswers|RefinedSphereHasNoGhosts|ContactNearestTheHandleWins|RatioTargetIsReached|ErrorBoundIsHonouredOnRealTables'
start=$SECONDS
bash scripts/build_sanitized.sh
echo "test.sh: sanitizer build took $((SECONDS - start)) s"
export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  LSAN_OPTIONS=suppressions=$PWD/scripts/lsan_suppressions.txt
for suite in core device; do
  ctest --test-dir build-asan/tests/$suite --output-on-failure -j2 --timeout 600 -E "$asan_skip"
done
echo "test.sh: sanitizer build and suites took $((SECONDS - start)) s"
if [ "$fuzz_seconds" -gt 0 ]; then
  unset ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS   # scripts/fuzz.sh sets its own
  HB_FUZZ_JOBS=2 HB_FUZZ_SEED=${HB_FUZZ_SEED:-1} bash scripts/fuzz.sh "$fuzz_seconds"
fi
echo "test.sh: hostile-input stage took $((SECONDS - start)) s"
